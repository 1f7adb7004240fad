// Camera rays and projection: round trips at extremes, conventions, bad views.
#include <gtest/gtest.h>

#include "shade/view.h"
#include "test_scenes.h"

namespace epi {
namespace {

struct ViewCase {
  glm::vec3 eye, target, up;
  float fov;
  int width, height;
};

TEST(View, RayThenProjectRoundTripsAtExtremes) {
  const ViewCase cases[] = {
      {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45.0f, 512, 512},
      {{1e4f, -2e4f, 3e3f}, {1e4f + 1.0f, -2e4f, 3e3f}, {0, 0, 1}, 60.0f, 1920, 1080},
      {{0.1f, 0.2f, 0.3f}, {0.1f, 0.2f, -5.0f}, {0, 1, 0}, 1.0f, 7, 3},
      {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 170.0f, 3, 1000},
      {{2, 2, 2}, {0, 0, 0}, {0, 0, 1}, 90.0f, 1, 1},
      {{0, 5, 0}, {0, 0, 0}, {0, 1, 0}, 30.0f, 64, 32},  // up parallel to the view direction
  };
  for (const ViewCase& c : cases) {
    View view{test::look(c.eye, c.target, c.fov), c.width, c.height};
    view.camera.up = c.up;
    ViewFrame frame(view);
    const float w = float(c.width), h = float(c.height);
    const glm::vec2 pixels[] = {{0, 0}, {w, 0}, {0, h}, {w, h}, {w * 0.5f, h * 0.5f}, {1e-6f, 1e-6f},
                                {w - 1e-3f, 0.5f}, {0.25f, h - 0.25f}, {-3.0f * w, 5.0f * h}};
    for (glm::vec2 px : pixels) {
      Ray ray = frame.ray(px.x, px.y);
      ASSERT_NEAR(glm::length(ray.direction), 1.0f, 1e-6f);
      for (float t : {1e-3f, 1.0f, 1e3f, 1e6f}) {
        if (t < 1e-4f * glm::length(c.eye)) continue;  // eye + t * direction is not representable
        glm::vec3 world = ray.origin + t * ray.direction;
        Projection p = frame.project(world);
        ASSERT_TRUE(p.in_front());
        EXPECT_NEAR(p.depth, t * glm::dot(ray.direction, frame.forward()), 1e-5f * t + 1e-6f * glm::length(c.eye));
        // Tolerance: float error of the world point relative to the image-plane scale.
        float scale = (1e-5f + 4e-7f * glm::length(c.eye) / t) * std::max(w, h) *
                      (1.0f + std::abs(px.x / w) + std::abs(px.y / h)) / std::tan(glm::radians(std::min(c.fov, 90.0f)) / 2);
        EXPECT_NEAR(p.pixel.x, px.x, scale) << "fov " << c.fov << " t " << t;
        EXPECT_NEAR(p.pixel.y, px.y, scale) << "fov " << c.fov << " t " << t;
      }
    }
  }
}

TEST(View, PixelConventions) {
  View view{test::look({0, 0, 0}, {0, 1, 0}, 90.0f), 200, 100};  // forward +y, up +z, right +x
  ViewFrame frame(view);
  EXPECT_NEAR(glm::distance(frame.ray(100, 50).direction, glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
  // y down: the top row looks up; x right: the last column looks right.
  EXPECT_GT(frame.ray(100, 0).direction.z, 0.5f);
  EXPECT_GT(frame.ray(200, 50).direction.x, 0.8f);
  // Vertical fov 90: the top edge is 45 degrees up; aspect 2: the right edge is at tan = 2.
  glm::vec3 top = frame.ray(100, 0).direction;
  EXPECT_NEAR(top.z / top.y, 1.0f, 1e-5f);
  glm::vec3 right = frame.ray(200, 50).direction;
  EXPECT_NEAR(right.x / right.y, 2.0f, 1e-5f);
  // Behind the eye projects with negative depth.
  EXPECT_FALSE(frame.project({0, -1, 0}).in_front());
}

TEST(View, FarOffPixelsStillGiveUnitDirections) {
  ViewFrame frame(View{test::look({0, 0, 0}, {0, 1, 0}, 60.0f), 100, 100});
  for (glm::vec2 px : {glm::vec2(1e30f, 0), glm::vec2(-1e30f, 1e30f), glm::vec2(50, 3e38f)}) {
    Ray ray = frame.ray(px.x, px.y);
    EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(ray.direction, frame.forward()), 0.0f, 1e-6f);  // at the image plane's infinity
  }
}

TEST(View, RaysStartOnTheNearPlane) {
  View view{test::look({1, 2, 3}, {4, -2, 0}, 70.0f), 320, 240};
  view.camera.znear = 0.25f;
  ViewFrame frame(view);
  for (glm::vec2 px : {glm::vec2(0, 0), glm::vec2(320, 240), glm::vec2(17.5f, 200.25f)}) {
    Ray ray = frame.ray(px.x, px.y);
    EXPECT_NEAR(frame.project(ray.origin + ray.tnear * ray.direction).depth, 0.25f, 1e-6f);
  }
}

TEST(View, RejectsUnusableViews) {
  View good{test::look({0, 0, 5}, {0, 0, 0}), 64, 64};
  EXPECT_NO_THROW(ViewFrame{good});
  View v = good;
  v.width = 0;
  EXPECT_THROW(ViewFrame{v}, std::invalid_argument);
  v = good;
  v.camera.yfov_degrees = 180.0f;
  EXPECT_THROW(ViewFrame{v}, std::invalid_argument);
  v = good;
  v.camera.yfov_degrees = std::nanf("");
  EXPECT_THROW(ViewFrame{v}, std::invalid_argument);
  v = good;
  v.camera.target = v.camera.eye;
  EXPECT_THROW(ViewFrame{v}, std::invalid_argument);
}

}  // namespace
}  // namespace epi

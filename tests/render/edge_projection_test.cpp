// 3D edges into pixel segments: projection against ViewFrame::project, near-plane and frustum
// clipping (property test over random segments), and occlusion culling against filtered depth.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "render/edge_projection.h"

namespace epi::render {
namespace {

ViewFrame test_frame(int w = 64, int h = 48) {
  View v;
  v.camera.eye = {0.3f, -0.2f, 6.0f}, v.camera.target = {0, 0, 0}, v.camera.yfov_degrees = 50.0f, v.camera.znear = 0.1f;
  v.width = w, v.height = h;
  return ViewFrame(v);
}

double distance_to_segment(glm::dvec2 p, const Segment& s) {
  const glm::dvec2 a(s.x0, s.y0), b(s.x1, s.y1);
  const glm::dvec2 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

TEST(EdgeProjection, EndpointsInFrontProjectAsViewFrameSays) {
  const ViewFrame frame = test_frame();
  std::vector<Segment> out;
  const glm::dvec3 a(-0.5, 0.2, 0.0), b(0.4, -0.3, 1.0);
  ASSERT_EQ(project_edge(frame, a, b, {}, out), EdgeFate::visible);
  ASSERT_EQ(out.size(), 1u);
  const Projection pa = frame.project(glm::vec3(a)), pb = frame.project(glm::vec3(b));
  EXPECT_NEAR(out[0].x0, pa.pixel.x, 1e-4);
  EXPECT_NEAR(out[0].y0, pa.pixel.y, 1e-4);
  EXPECT_NEAR(out[0].x1, pb.pixel.x, 1e-4);
  EXPECT_NEAR(out[0].y1, pb.pixel.y, 1e-4);
}

TEST(EdgeProjection, BehindTheEyeOrOffScreenIsOutside) {
  const ViewFrame frame = test_frame();
  std::vector<Segment> out;
  EXPECT_EQ(project_edge(frame, {0, 0, 7}, {1, 1, 9}, {}, out), EdgeFate::outside);      // behind
  EXPECT_EQ(project_edge(frame, {40, 0, 0}, {40, 5, 0}, {}, out), EdgeFate::outside);    // far right
  EXPECT_EQ(project_edge(frame, {0.3, -0.2, 6.05}, {0.3, -0.2, 6.09}, {}, out), EdgeFate::outside);  // inside znear
  EXPECT_TRUE(out.empty());
}

// Random segments, many crossing the near plane or the image border: every in-front point of the
// 3D segment that projects inside the image lies on an output piece, and every output point lies
// inside the grown image and on the projection of the segment.
TEST(EdgeProjection, ClippingKeepsExactlyTheVisiblePartOfRandomSegments) {
  const ViewFrame frame = test_frame();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coord(-8.0, 8.0);
  int crossing_near = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const glm::dvec3 a(coord(rng), coord(rng), coord(rng)), b(coord(rng), coord(rng), coord(rng));
    std::vector<Segment> out;
    const EdgeFate fate = project_edge(frame, a, b, {}, out);
    const glm::dvec3 eye(frame.eye()), fwd(frame.forward());
    crossing_near += (glm::dot(a - eye, fwd) - 0.1) * (glm::dot(b - eye, fwd) - 0.1) < 0;
    for (int k = 0; k <= 200; ++k) {
      const glm::dvec3 p = glm::mix(a, b, k / 200.0);
      const Projection proj = frame.project(glm::vec3(p));
      if (!(proj.depth > 0.1 + 1e-6)) continue;
      if (proj.pixel.x < 0 || proj.pixel.y < 0 || proj.pixel.x > 64 || proj.pixel.y > 48) continue;
      ASSERT_EQ(fate, EdgeFate::visible) << trial;
      ASSERT_EQ(out.size(), 1u);
      EXPECT_LT(distance_to_segment(glm::dvec2(proj.pixel), out[0]), 2e-3 * (1.0 + 1.0 / proj.depth)) << trial;
    }
    for (const Segment& s : out)
      for (const glm::dvec2 p : {glm::dvec2(s.x0, s.y0), glm::dvec2(s.x1, s.y1)}) {
        EXPECT_GE(p.x, -1.0 - 1e-9);
        EXPECT_LE(p.x, 65.0 + 1e-9);
        EXPECT_GE(p.y, -1.0 - 1e-9);
        EXPECT_LE(p.y, 49.0 + 1e-9);
      }
  }
  EXPECT_GT(crossing_near, 50);
}

PointImage plane_points(int w, int h, float depth, int hole_x0 = -1, int hole_x1 = -1) {
  PointImage image;
  image.width = w, image.height = h;
  image.point.assign(size_t(w * h), 0);
  image.depth.assign(size_t(w * h), depth);
  image.region.assign(size_t(w * h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = std::max(0, hole_x0); x < hole_x1; ++x) {
      image.point[size_t(y * w + x)] = -1;
      image.depth[size_t(y * w + x)] = std::numeric_limits<float>::infinity();
    }
  return image;
}

TEST(EdgeProjection, FilteredDepthIsTheWindowMaximumPlusASparsenessOffset) {
  PointImage image = plane_points(16, 16, 4.0f);
  image.depth[image.index(5, 5)] = 6.0f;
  image.point[image.index(9, 9)] = -1;  // one empty pixel
  std::vector<float> filtered;
  const DepthFilterSettings s;
  filter_depth(image, s, filtered);
  EXPECT_FLOAT_EQ(filtered[image.index(4, 4)], 6.0f * (1.0f + s.base_offset));  // window x 3..6 holds (5,5)
  EXPECT_FLOAT_EQ(filtered[image.index(7, 3)], 4.0f * (1.0f + s.base_offset));  // window x 6..9, y 2..5: full, no (5,5)
  EXPECT_FLOAT_EQ(filtered[image.index(8, 8)], 4.0f * (1.0f + s.base_offset + s.sparse_offset / 16.0f));
  const PointImage empty = plane_points(8, 8, 1.0f, 0, 8);
  filter_depth(empty, s, filtered);
  for (float d : filtered) EXPECT_TRUE(std::isinf(d));
}

// A wall of points at depth 3 in front of the camera: an edge behind it is culled, an edge on it
// is kept, and an edge behind it where the wall has a hole keeps the piece seen through the hole.
TEST(EdgeProjection, OcclusionCullingAgainstThePointDepth) {
  View v;
  v.camera.eye = {0, 0, 10}, v.camera.target = {0, 0, 0}, v.camera.yfov_degrees = 40.0f;
  v.width = 64, v.height = 64;
  const ViewFrame frame(v);
  std::vector<float> filtered;
  filter_depth(plane_points(64, 64, 3.0f, 28, 36), DepthFilterSettings{}, filtered);
  std::vector<Segment> out;
  // Behind the wall (z = 0: depth 10), across the whole image: only the hole's piece survives.
  ASSERT_EQ(project_edge(frame, {-3, 0.1, 0}, {3, 0.1, 0}, filtered, out), EdgeFate::visible);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_GT(std::min(out[0].x0, out[0].x1), 25.0);
  EXPECT_LT(std::max(out[0].x0, out[0].x1), 39.0);
  out.clear();
  EXPECT_EQ(project_edge(frame, {-3, 0.1, 0}, {-1, 0.1, 0}, filtered, out), EdgeFate::culled);
  EXPECT_TRUE(out.empty());
  // On the wall (depth 3).
  EXPECT_EQ(project_edge(frame, {-0.8, 0.1, 7}, {-0.3, 0.1, 7}, filtered, out), EdgeFate::visible);
}

}  // namespace
}  // namespace epi::render

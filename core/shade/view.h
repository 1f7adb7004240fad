// Camera rays and their inverse, shared by every stage: a View is a camera and an image size.
// Pixel units, y down: pixel (i, j) covers [i, i+1) x [j, j+1), its centre is (i + 0.5, j + 0.5).
#pragma once

#include "scene/scene.h"

namespace epi {

// Embree refuses rays whose origin or direction has a component beyond FLT_LARGE (1.844e18): the
// camera and the scene's world bounds must stay within this distance of the origin.
inline constexpr float kMaxRayCoordinate = 1e18f;

struct View {
  Camera camera;
  int width = 512, height = 512;
};

struct Ray {
  glm::vec3 origin{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // unit length
  float tnear = 0.0f;
  float tfar = 1e30f;
};

// A world point seen from the camera: pixel position and depth along the view axis.
struct Projection {
  glm::vec2 pixel{0.0f};
  float depth = 0.0f;  // distance along the camera's forward axis; <= 0 behind the eye
  bool in_front() const { return depth > 0.0f; }
};

// The camera basis of a View, computed once. Throws std::invalid_argument with a one-line
// message for an unusable view (size, field of view, eye == target).
class ViewFrame {
 public:
  explicit ViewFrame(const View& view);

  // World-space ray through pixel position (x, y); tnear puts its start on the near plane.
  Ray ray(float x, float y) const;
  // Inverse of ray(): where a world point lands in the image, and its depth.
  Projection project(const glm::vec3& world) const;

  const View& view() const { return view_; }
  const glm::vec3& eye() const { return view_.camera.eye; }
  const glm::vec3& forward() const { return forward_; }
  const glm::vec3& right() const { return right_; }
  const glm::vec3& up() const { return up_; }
  float half_width() const { return half_width_; }    // project() divides by depth x these
  float half_height() const { return half_height_; }

 private:
  View view_;
  glm::vec3 forward_, right_, up_;
  float half_height_ = 1.0f;  // tan(yfov / 2): image half-height at unit depth
  float half_width_ = 1.0f;   // half_height * aspect
};

inline Ray camera_ray(const View& view, float x, float y) { return ViewFrame(view).ray(x, y); }
inline Projection project(const View& view, const glm::vec3& world) { return ViewFrame(view).project(world); }

}  // namespace epi

#include "shade/view.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace epi {

namespace {
std::string camera_label(const Camera& camera) { return camera.name.empty() ? "camera" : "camera '" + camera.name + "'"; }
}  // namespace

ViewFrame::ViewFrame(const View& view) : view_(view) {
  const Camera& c = view.camera;
  if (view.width <= 0 || view.height <= 0)
    throw std::invalid_argument("view: image size " + std::to_string(view.width) + "x" + std::to_string(view.height) +
                                " is not positive");
  if (!(c.yfov_degrees > 0.0f && c.yfov_degrees < 180.0f))
    throw std::invalid_argument(camera_label(c) + ": vertical field of view " + std::to_string(c.yfov_degrees) +
                                " is not in (0, 180) degrees");
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(c.eye[k]) <= kMaxRayCoordinate))
      throw std::invalid_argument(camera_label(c) + ": eye coordinate " + std::to_string(c.eye[k]) +
                                  " is beyond the ray tracer's range (1e18)");
  // Validity in double: the float difference and its square overflow for large but finite
  // coordinates. The basis stays the float computation it always was (the same bits for every
  // ordinary camera); the double one only replaces a float result that overflowed.
  const glm::dvec3 to_target_d = glm::dvec3(c.target) - glm::dvec3(c.eye);
  const double distance = glm::length(to_target_d);
  if (!(distance > 0.0) || !std::isfinite(distance))
    throw std::invalid_argument(camera_label(c) + ": eye and target coincide or are not finite");
  const glm::vec3 to_target = c.target - c.eye;
  const float distance_f = glm::length(to_target);
  forward_ = std::isfinite(distance_f) && distance_f > 0.0f ? to_target / distance_f : glm::vec3(to_target_d / distance);
  glm::vec3 side = glm::cross(forward_, c.up);
  if (!std::isfinite(glm::length(side)))  // a huge up vector
    side = glm::vec3(glm::cross(glm::dvec3(forward_), glm::dvec3(c.up) / glm::length(glm::dvec3(c.up))));
  if (!(glm::length(side) > 1e-6f)) {  // up zero or parallel to the view direction: pick any perpendicular
    glm::vec3 axis = std::abs(forward_.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    side = glm::cross(forward_, axis);
  }
  right_ = glm::normalize(side);
  up_ = glm::cross(right_, forward_);
  half_height_ = float(std::tan(double(c.yfov_degrees) * M_PI / 360.0));
  half_width_ = half_height_ * float(view.width) / float(view.height);
}

Ray ViewFrame::ray(float x, float y) const {
  float sx = (x / float(view_.width) * 2.0f - 1.0f) * half_width_;
  float sy = (1.0f - y / float(view_.height) * 2.0f) * half_height_;
  glm::vec3 d = forward_ + sx * right_ + sy * up_;
  // Normalise without overflow for far-off pixel positions: scale by the largest component first.
  float scale = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  glm::vec3 e = d / scale;
  float length = glm::length(e);
  Ray r;
  r.origin = view_.camera.eye;
  r.direction = e / length;
  r.tnear = std::max(view_.camera.znear, 0.0f) * (scale * length);  // depth znear along forward (|d| = 1 / cos)
  return r;
}

Projection ViewFrame::project(const glm::vec3& world) const {
  glm::vec3 rel = world - view_.camera.eye;
  Projection p;
  p.depth = glm::dot(rel, forward_);
  float sx = glm::dot(rel, right_) / (p.depth * half_width_);
  float sy = glm::dot(rel, up_) / (p.depth * half_height_);
  p.pixel = glm::vec2((sx + 1.0f) * 0.5f * float(view_.width), (1.0f - sy) * 0.5f * float(view_.height));
  return p;
}

}  // namespace epi

#include "navigation.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace epi::viewer {

namespace {

glm::vec3 rotate(const glm::vec3& v, const glm::vec3& axis, float degrees) {
  return glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::normalize(axis)) * glm::vec4(v, 0.0f));
}

// Turns v away from `up` by `degrees` (towards it when negative), keeping it 1 degree short of
// either pole.
glm::vec3 tilt(const glm::vec3& v, const glm::vec3& up, float degrees) {
  const float length = glm::length(v);
  const glm::vec3 axis = glm::cross(v, up);
  if (length <= 0.0f || glm::length(axis) < 1e-6f * length) return v;
  const float polar = glm::degrees(std::acos(std::clamp(glm::dot(v / length, up), -1.0f, 1.0f)));
  const float target = std::clamp(polar + degrees, 1.0f, 179.0f);
  return rotate(v, axis, polar - target);  // rotating about v x up turns v towards up
}

glm::vec3 world_up(const Camera& camera) {
  const float n = glm::length(camera.up);
  return n > 0.0f ? camera.up / n : glm::vec3(0.0f, 1.0f, 0.0f);
}

}  // namespace

Basis basis(const Camera& camera) {
  Basis b;
  b.forward = glm::normalize(camera.target - camera.eye);
  glm::vec3 right = glm::cross(b.forward, world_up(camera));
  if (glm::length(right) < 1e-6f) right = glm::cross(b.forward, glm::vec3(0.0f, 0.0f, 1.0f));
  b.right = glm::normalize(right);
  b.up = glm::cross(b.right, b.forward);
  return b;
}

void orbit(Camera& camera, float dx_pixels, float dy_pixels) {
  const glm::vec3 up = world_up(camera);
  glm::vec3 offset = rotate(camera.eye - camera.target, up, -dx_pixels * kOrbitDegreesPerPixel);
  offset = tilt(offset, up, -dy_pixels * kOrbitDegreesPerPixel);  // dragging down shows the scene from higher up
  camera.eye = camera.target + offset;
}

void pan(Camera& camera, float dx_pixels, float dy_pixels, int height) {
  const Basis b = basis(camera);
  const float distance = glm::length(camera.target - camera.eye);
  const float units_per_pixel = 2.0f * distance * std::tan(glm::radians(camera.yfov_degrees) * 0.5f) / float(std::max(1, height));
  const glm::vec3 move = (-dx_pixels * b.right + dy_pixels * b.up) * units_per_pixel;
  camera.eye += move;
  camera.target += move;
}

void dolly(Camera& camera, float steps) {
  const glm::vec3 offset = camera.eye - camera.target;
  const float length = glm::length(offset);
  const float scaled = std::max(length * std::pow(kDollyPerStep, steps), 1e-4f);
  camera.eye = camera.target + offset * (scaled / length);
}

void look(Camera& camera, float dx_pixels, float dy_pixels) {
  const glm::vec3 up = world_up(camera);
  glm::vec3 dir = rotate(camera.target - camera.eye, up, -dx_pixels * kOrbitDegreesPerPixel);
  dir = tilt(dir, up, dy_pixels * kOrbitDegreesPerPixel);  // dragging down looks down
  camera.target = camera.eye + dir;
}

void fly(Camera& camera, const glm::vec3& local) {
  const Basis b = basis(camera);
  const glm::vec3 move = local.x * b.right + local.y * b.up + local.z * b.forward;
  camera.eye += move;
  camera.target += move;
}

void frame_bounds(Camera& camera, const Bounds& bounds) {
  if (bounds.empty()) return;
  const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
  const float radius = std::max(0.5f * glm::length(bounds.max - bounds.min), 1e-3f);
  const glm::vec3 forward = basis(camera).forward;
  const float half_fov = glm::radians(camera.yfov_degrees) * 0.5f;
  const float distance = radius / std::sin(std::max(half_fov, 1e-3f)) * 1.05f;
  camera.target = centre;
  camera.eye = centre - forward * distance;
}

}  // namespace epi::viewer

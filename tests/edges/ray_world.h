// A brute-force ray caster for the shadow tests: every triangle of a small scene in world space,
// with bounding spheres per object to skip, tested by Moller-Trumbore in double.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/scene.h"

namespace epi::edges::test {

struct World {
  Scene scene;
  std::vector<glm::dvec3> triangles;  // world space, 3 per triangle
  std::vector<uint32_t> triangle_object;
  struct Sphere {
    glm::dvec3 centre;
    double radius;
  };
  static constexpr size_t kChunk = 16;
  struct Range {
    size_t begin, end;  // in triangles[]
    glm::dvec3 centre;
    double radius;
    std::vector<Sphere> chunks;  // bounding spheres of runs of kChunk triangles
  };
  std::vector<Range> ranges;  // one per object

  uint32_t add(Mesh mesh, const glm::mat4& transform) {
    const size_t begin = triangles.size();
    scene.meshes.push_back(std::move(mesh));
    scene.objects.push_back({scene.meshes.back().name + std::to_string(scene.objects.size()),
                             uint32_t(scene.meshes.size() - 1), transform});
    for (const glm::uvec3& t : scene.meshes.back().triangles)
      for (int k = 0; k < 3; ++k) {
        triangles.push_back(glm::dvec3(transform * glm::vec4(scene.meshes.back().positions[t[k]], 1.0f)));
        if (k == 0) triangle_object.push_back(uint32_t(scene.objects.size() - 1));
      }
    Range r{begin, triangles.size(), glm::dvec3(0.0), 0.0, {}};
    for (size_t i = begin; i < r.end; ++i) r.centre += triangles[i] / double(r.end - begin);
    for (size_t i = begin; i < r.end; ++i) r.radius = std::max(r.radius, glm::length(triangles[i] - r.centre));
    for (size_t c = begin; c < r.end; c += 3 * kChunk) {
      const size_t c_end = std::min(r.end, c + 3 * kChunk);
      Sphere sphere{glm::dvec3(0.0), 0.0};
      for (size_t i = c; i < c_end; ++i) sphere.centre += triangles[i] / double(c_end - c);
      for (size_t i = c; i < c_end; ++i) sphere.radius = std::max(sphere.radius, glm::length(triangles[i] - sphere.centre));
      r.chunks.push_back(sphere);
    }
    ranges.push_back(r);
    return uint32_t(scene.objects.size() - 1);
  }
  static bool misses(const Sphere& s, const glm::dvec3& x, const glm::dvec3& d, double t_max) {
    const double tc = std::clamp(glm::dot(s.centre - x, d) / glm::dot(d, d), 0.0, std::min(t_max, 1e6));
    return glm::length(x + tc * d - s.centre) > s.radius * 1.001 + 1e-9;
  }

  // Whether the open segment from x along d (t in (0, t_max)) hits any triangle (Moller-Trumbore).
  bool blocked(const glm::dvec3& x, const glm::dvec3& d, double t_max) const {
    for (const Range& r : ranges) {
      // Skip objects whose bounding sphere the segment misses.
      if (misses({r.centre, r.radius}, x, d, t_max)) continue;
      if (blocked_by(r, x, d, t_max)) return true;
    }
    return false;
  }
  bool blocked_by(const Range& r, const glm::dvec3& x, const glm::dvec3& d, double t_max) const {
    for (size_t i = r.begin; i < r.end; i += 3) {
      if ((i - r.begin) % (3 * kChunk) == 0 && misses(r.chunks[(i - r.begin) / (3 * kChunk)], x, d, t_max)) {
        i += 3 * (kChunk - 1);
        continue;
      }
      const glm::dvec3 e1 = triangles[i + 1] - triangles[i], e2 = triangles[i + 2] - triangles[i];
      const glm::dvec3 p = glm::cross(d, e2);
      const double det = glm::dot(e1, p);
      if (std::fabs(det) < 1e-300) continue;
      const glm::dvec3 s = x - triangles[i];
      const double u = glm::dot(s, p) / det;
      if (u < 0 || u > 1) continue;
      const glm::dvec3 q = glm::cross(s, e1);
      const double v = glm::dot(d, q) / det;
      if (v < 0 || u + v > 1) continue;
      const double t = glm::dot(e2, q) / det;
      if (t > 1e-9 && t < t_max) return true;
    }
    return false;
  }
  // Whether a floor point lies under (or at the foot of) a box standing on the floor.
  std::vector<glm::dmat4> footprints;
  bool inside(const glm::dvec3& x) const {
    for (const glm::dmat4& f : footprints) {
      const glm::dvec3 local = glm::dvec3(glm::inverse(f) * glm::dvec4(x, 1.0));
      if (std::fabs(local.x) < 0.43 && std::fabs(local.z) < 0.43) return true;
    }
    return false;
  }
  bool sees_point(const glm::dvec3& x, const glm::dvec3& light) const { return !blocked(x, light - x, 1.0 - 1e-9); }
  bool sees_direction(const glm::dvec3& x, const glm::dvec3& travel) const { return !blocked(x, -travel, 1e30); }
};

inline glm::mat4 at(glm::vec3 position, float angle_degrees = 0.0f, glm::vec3 axis = {0, 0, 1}) {
  return glm::rotate(glm::translate(glm::mat4(1.0f), position), glm::radians(angle_degrees), axis);
}


}  // namespace epi::edges::test

#include "scene/scene.h"

#include <algorithm>
#include <cmath>

namespace epi {

uint32_t Mesh::material_of(uint32_t triangle) const {
  auto it = std::upper_bound(materials.begin(), materials.end(), triangle,
                             [](uint32_t t, const MaterialRange& r) { return t < r.first_triangle; });
  return it == materials.begin() ? 0 : std::prev(it)->material;
}

size_t Mesh::memory_bytes() const {
  return positions.capacity() * sizeof(glm::vec3) + triangles.capacity() * sizeof(glm::uvec3) +
         normals.capacity() * sizeof(glm::vec3) + materials.capacity() * sizeof(MaterialRange);
}

size_t AreaLight::memory_bytes() const {
  size_t bytes = triangle_vertices.capacity() * sizeof(glm::vec3) +
                 triangle_materials.capacity() * sizeof(uint32_t) + triangle_cdf.capacity() * sizeof(float);
  for (const auto& loop : outlines) bytes += loop.capacity() * sizeof(glm::vec3);
  return bytes;
}

std::string camera_problem(const Camera& camera) {
  if (!(camera.yfov_degrees > 0.0f && camera.yfov_degrees < 180.0f))
    return "vertical field of view " + std::to_string(camera.yfov_degrees) + " is not in (0, 180) degrees";
  if (!(camera.znear > 0.0f) || !std::isfinite(camera.znear)) return "znear must be finite and > 0";
  const glm::dvec3 eye(camera.eye), target(camera.target), up(camera.up);
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(eye[k]) || !std::isfinite(target[k])) return "eye or target is not finite";
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(up[k])) return "up is not finite";
  const glm::dvec3 to_target = target - eye;  // finite: float values differ by less than 2 * FLT_MAX
  const double distance = glm::length(to_target), up_length = glm::length(up);
  if (!(distance > 0.0)) return "eye and target coincide";
  if (!(up_length > 0.0)) return "up is zero";
  // sin of the angle between up and the view direction; below ~1e-6 float rounding decides the side.
  if (!(glm::length(glm::cross(to_target / distance, up / up_length)) > 1e-6)) return "up is parallel to the view direction";
  return "";
}

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const Object& o : objects) n += meshes[o.mesh].triangles.size();
  return n;
}

Bounds Scene::world_bounds() const {
  Bounds b;
  for (const Object& o : objects)
    for (const glm::vec3& p : meshes[o.mesh].positions) b.extend(glm::vec3(o.object_to_world * glm::vec4(p, 1.0f)));
  return b;
}

std::vector<MemoryItem> Scene::memory() const {
  std::vector<MemoryItem> items;
  size_t mesh_bytes = 0;
  for (const Mesh& m : meshes) mesh_bytes += m.memory_bytes();
  items.push_back({"meshes", mesh_bytes});
  items.push_back({"objects", objects.capacity() * sizeof(Object)});
  items.push_back({"materials", materials.capacity() * sizeof(Material)});
  if (!punctual_lights.empty()) items.push_back({"punctual lights", punctual_lights.capacity() * sizeof(PunctualLight)});
  if (!area_lights.empty()) {
    size_t bytes = 0;
    for (const AreaLight& l : area_lights) bytes += l.memory_bytes();
    items.push_back({"area lights", bytes});
  }
  return items;
}

}  // namespace epi

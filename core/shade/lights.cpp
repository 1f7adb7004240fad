#include "shade/lights.h"

#include <utility>

#include "shade/brdf.h"

namespace epi {

AreaLight build_area_light(const Scene& scene, uint32_t object, const glm::mat4& object_to_world) {
  AreaLight light;
  light.object = object;
  const Mesh& mesh = scene.meshes[scene.objects[object].mesh];
  std::vector<float> powers;
  // A mirroring transform flips the winding: swap two vertices so that the world-space winding
  // normal stays on the emitting (front) side, as the glTF loader does.
  const bool mirrored = glm::determinant(glm::mat3(object_to_world)) < 0.0f;
  for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    uint32_t material = mesh.material_of(t);
    if (material >= scene.materials.size() || !scene.materials[material].emissive()) continue;
    glm::uvec3 tri = mesh.triangles[t];
    if (mirrored) std::swap(tri.y, tri.z);
    glm::vec3 v[3];
    for (int k = 0; k < 3; ++k) v[k] = glm::vec3(object_to_world * glm::vec4(mesh.positions[tri[k]], 1.0f));
    float area = 0.5f * glm::length(glm::cross(v[1] - v[0], v[2] - v[0]));  // 0 for a degenerate one: never sampled
    light.triangle_vertices.insert(light.triangle_vertices.end(), v, v + 3);
    light.triangle_materials.push_back(material);
    float power = rgb_luminance(scene.materials[material].emission) * area;
    powers.push_back(power);
    light.area += area;
    light.power += power;
  }
  double sum = 0.0;
  for (float p : powers) {
    sum += p;
    light.triangle_cdf.push_back(light.power > 0.0f ? float(sum / light.power) : 0.0f);
  }
  if (!light.triangle_cdf.empty()) light.triangle_cdf.back() = 1.0f;
  return light;
}

}  // namespace epi

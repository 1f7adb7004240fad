#include "area_lights.h"

#include <algorithm>
#include <utility>

#include "scene/topology.h"

namespace epi {

float luminance(const glm::vec3& rgb) { return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b; }

std::vector<std::vector<glm::vec3>> boundary_loops(const Mesh& mesh) {
  const EdgeTable table = build_edge_table(mesh);
  const std::vector<uint32_t>& remap = table.weld.remap;

  // Border edges, directed as their one triangle walks them.
  std::vector<std::pair<uint32_t, uint32_t>> directed;
  for (const MeshEdge& edge : table.edges) {
    if (edge.face_count != 1) continue;
    const glm::uvec3& t = mesh.triangles[edge.face0];
    const uint32_t w[3] = {remap[t.x], remap[t.y], remap[t.z]};
    for (int k = 0; k < 3; ++k) {
      const uint32_t from = w[k], to = w[(k + 1) % 3];
      if (std::min(from, to) == edge.v0 && std::max(from, to) == edge.v1) {
        directed.emplace_back(from, to);
        break;
      }
    }
  }

  // Outgoing border edges per welded vertex (a vertex where two loops touch has several).
  std::vector<std::vector<uint32_t>> outgoing(table.weld.positions.size());
  for (uint32_t e = 0; e < directed.size(); ++e) outgoing[directed[e].first].push_back(e);
  std::vector<bool> used(directed.size(), false);

  std::vector<std::vector<glm::vec3>> loops;
  for (uint32_t start = 0; start < directed.size(); ++start) {
    if (used[start]) continue;
    std::vector<glm::vec3> loop;
    uint32_t edge = start;
    while (true) {
      used[edge] = true;
      loop.push_back(table.weld.positions[directed[edge].first]);
      const uint32_t at = directed[edge].second;
      if (at == directed[start].first) break;  // closed
      auto next = std::find_if(outgoing[at].begin(), outgoing[at].end(), [&](uint32_t e) { return !used[e]; });
      if (next == outgoing[at].end()) break;  // inconsistent winding: keep the open chain as a loop
      edge = *next;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<AreaLight> build_area_lights(const Scene& scene) {
  std::vector<AreaLight> lights;
  for (uint32_t object_index = 0; object_index < scene.objects.size(); ++object_index) {
    const Object& object = scene.objects[object_index];
    const Mesh& mesh = scene.meshes[object.mesh];

    // The emissive triangles, as a mesh of their own (object space) for the outline.
    Mesh emitter;
    emitter.positions = mesh.positions;
    std::vector<uint32_t> materials;
    for (const MaterialRange& range : mesh.materials) {
      if (!scene.materials[range.material].emissive()) continue;
      for (uint32_t t = range.first_triangle; t < range.first_triangle + range.triangle_count; ++t) {
        emitter.triangles.push_back(mesh.triangles[t]);
        materials.push_back(range.material);
      }
    }
    if (emitter.triangles.empty()) continue;

    const glm::mat4& m = object.object_to_world;
    const bool mirrored = glm::determinant(glm::mat3(m)) < 0.0f;
    AreaLight light;
    light.object = object_index;
    light.triangle_materials = materials;
    light.triangle_cdf.reserve(materials.size());
    double area = 0.0, power = 0.0;
    for (size_t i = 0; i < emitter.triangles.size(); ++i) {
      glm::uvec3 t = emitter.triangles[i];
      if (mirrored) std::swap(t.y, t.z);
      glm::vec3 p[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = glm::vec3(m * glm::vec4(mesh.positions[t[k]], 1.0f));
        light.triangle_vertices.push_back(p[k]);
      }
      const double triangle_area = 0.5 * double(glm::length(glm::cross(p[1] - p[0], p[2] - p[0])));
      area += triangle_area;
      power += triangle_area * double(luminance(scene.materials[materials[i]].emission));
      light.triangle_cdf.push_back(float(power));
    }
    if (!(power > 0.0)) continue;  // nothing emits (all triangles degenerate in world space)
    for (float& c : light.triangle_cdf) c = float(double(c) / power);
    light.triangle_cdf.back() = 1.0f;
    light.area = float(area);
    light.power = float(power);

    for (std::vector<glm::vec3>& loop : boundary_loops(emitter)) {
      for (glm::vec3& p : loop) p = glm::vec3(m * glm::vec4(p, 1.0f));
      if (mirrored) std::reverse(loop.begin(), loop.end());
      light.outlines.push_back(std::move(loop));
    }
    lights.push_back(std::move(light));
  }
  return lights;
}

}  // namespace epi

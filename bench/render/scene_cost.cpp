// Memory and set-up time against scene content (issue 15, "Model only what a scene requires";
// docs/tradeoff-memory.md): what epi builds before the first frame (meshes, area lights, the Embree
// scene, the edge finder's edge meshes, edge trees and receiver trees) and how long each takes, as
// one of these grows while the rest stays small:
//   objects      instances of one 2k-triangle sphere mesh
//   triangles    one sphere, tessellated ever finer
//   point_lights point lights
//   area_lights  emissive quads (each its own mesh and area light)
//   subdivision  a Catmull-Clark cube cage refined to a level (OpenSubdiv)
// Every scene also holds the small ground-and-box scene of the tests. Times: the fastest of three
// builds (the machine is shared). Writes CSV to stdout (or --out FILE); plot_scene_cost.py draws it.
// Usage: render_scene_cost [--quick] [--out FILE]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "edges/scene_edges.h"
#include "scene/subdivide.h"
#include "shade/lights.h"
#include "shade/ray_scene.h"
#include "test_scenes.h"

namespace {

using namespace epi;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

struct Row {
  std::string series;
  double x = 0;
  size_t objects = 0, triangles = 0, point_lights = 0, area_lights = 0;
  int level = 0;
  size_t mem_meshes = 0, mem_area_lights = 0, mem_embree = 0, mem_edge_meshes = 0, mem_edge_trees = 0,
         mem_receiver_trees = 0;
  double ms_subdivide = 0, ms_area_lights = 0, ms_ray_scene = 0, ms_edge_finder = 0;
};

// The fastest of `repeats` runs of f, ms.
double fastest(int repeats, const std::function<void()>& f) {
  double best = 1e300;
  for (int k = 0; k < repeats; ++k) {
    const auto t = Clock::now();
    f();
    best = std::min(best, ms_since(t));
  }
  return best;
}

// Builds what the renderer builds for `scene` (area lights from its emissive objects, the ray
// scene, the edge finder) and measures each.
Row measure(Scene scene, const std::string& series, double x, int repeats) {
  Row row;
  row.series = series, row.x = x;
  std::vector<uint32_t> emissive;
  for (uint32_t o = 0; o < scene.objects.size(); ++o) {
    const Mesh& mesh = scene.meshes[scene.objects[o].mesh];
    if (!mesh.materials.empty() && scene.materials[mesh.materials[0].material].emissive()) emissive.push_back(o);
  }
  row.ms_area_lights = fastest(repeats, [&] {
    scene.area_lights.clear();
    for (uint32_t o : emissive) test::add_area_light(scene, o);
  });
  row.ms_ray_scene = fastest(repeats, [&] { RayScene rs(scene); });
  row.ms_edge_finder = fastest(repeats, [&] { edges::SceneEdgeFinder finder(scene); });
  const RayScene rs(scene);
  const edges::SceneEdgeFinder finder(scene);
  for (const MemoryItem& item : scene.memory()) {
    if (item.name == "meshes") row.mem_meshes = item.bytes;
    if (item.name == "area lights") row.mem_area_lights += item.bytes;
  }
  for (const MemoryItem& item : rs.memory()) {
    if (item.name == "embree (BVH + buffers)") row.mem_embree = item.bytes;
    if (item.name == "area lights (placed copy)") row.mem_area_lights += item.bytes;
  }
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    row.mem_edge_meshes += finder.edge_mesh(m).memory_bytes();
    row.mem_edge_trees += finder.edge_tree(m).memory_bytes();
  }
  row.mem_receiver_trees = finder.memory_bytes() - row.mem_edge_meshes - row.mem_edge_trees;
  row.objects = scene.objects.size(), row.triangles = scene.triangle_count();
  row.point_lights = scene.punctual_lights.size(), row.area_lights = scene.area_lights.size();
  return row;
}

ControlMesh cube_cage() {
  ControlMesh cage;
  for (int i = 0; i < 8; ++i) cage.positions.push_back({i & 1 ? 0.5f : -0.5f, i & 2 ? 0.5f : -0.5f, i & 4 ? 2.0f : 1.0f});
  const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    cage.face_sizes.push_back(4);
    cage.face_indices.insert(cage.face_indices.end(), f, f + 4);
  }
  return cage;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  const char* out_path = nullptr;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out_path = argv[++i];
    else {
      std::fprintf(stderr, "usage: render_scene_cost [--quick] [--out FILE]\n");
      return 2;
    }
  }
  const int repeats = quick ? 1 : 3;
  std::vector<Row> rows;
  auto note = [&](const Row& r) {
    rows.push_back(r);
    std::fprintf(stderr, "%s %g: %zu triangles, %.1f ms\n", r.series.c_str(), r.x, r.triangles,
                 r.ms_area_lights + r.ms_ray_scene + r.ms_edge_finder + r.ms_subdivide);
  };

  measure(test::plane_and_box(), "warm-up", 0, 1);  // the first Embree device and TBB arena cost extra

  const std::vector<int> counts = quick ? std::vector<int>{1, 16} : std::vector<int>{1, 4, 16, 64, 256, 1024};
  for (int n : counts) {  // instances of one sphere mesh on a grid
    Scene scene = test::plane_and_box();
    const uint32_t m = test::add_material(scene, glm::vec3(0.5f));
    scene.meshes.push_back(test::sphere_mesh({0, 0, 0}, 0.3f, 32, 32, m));
    for (int k = 0; k < n; ++k) {
      Object o;
      o.name = "sphere" + std::to_string(k), o.mesh = uint32_t(scene.meshes.size() - 1);
      o.object_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(float(k % 32) - 16.0f, float(k / 32) + 2.0f, 0.3f));
      scene.objects.push_back(o);
    }
    note(measure(std::move(scene), "objects", n, repeats));
  }
  const std::vector<int> rings = quick ? std::vector<int>{8, 32} : std::vector<int>{8, 16, 32, 64, 128, 256, 512};
  for (int r : rings) {
    Scene scene = test::plane_and_box();
    test::add_object(scene, test::sphere_mesh({3, 3, 1}, 1.0f, r, 2 * r, test::add_material(scene, glm::vec3(0.5f))), "sphere");
    Row row = measure(std::move(scene), "triangles", 0, repeats);
    row.x = double(row.triangles);
    note(row);
  }
  const std::vector<int> lights = quick ? std::vector<int>{0, 16} : std::vector<int>{0, 1, 4, 16, 64, 256};
  for (int n : lights) {
    Scene scene = test::plane_and_box();
    for (int k = 0; k < n; ++k) scene.punctual_lights.push_back(test::point_light({float(k % 16) - 8.0f, float(k / 16), 5.0f}, glm::vec3(1.0f)));
    note(measure(scene, "point_lights", n, repeats));
    Scene area = test::plane_and_box();
    const uint32_t glow = test::add_material(area, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(2.0f));
    for (int k = 0; k < n; ++k)
      test::add_object(area, test::quad_mesh({float(k % 16) - 8.0f, float(k / 16), 5.0f}, {0, 0.5f, 0}, {0.5f, 0, 0}, glow),
                       "lamp" + std::to_string(k));
    note(measure(std::move(area), "area_lights", n, repeats));
  }
  const int max_level = quick ? 2 : 7;
  for (int level = 0; level <= max_level; ++level) {
    Scene scene = test::plane_and_box();
    const ControlMesh cage = cube_cage();
    SubdividedMesh refined;
    const double ms = fastest(repeats, [&] { refined = subdivide(cage, SubdivisionScheme::catmull_clark, level); });
    Mesh mesh;
    mesh.positions = std::move(refined.positions), mesh.triangles = std::move(refined.triangles);
    mesh.normals = std::move(refined.normals), mesh.subdivided = true;
    test::finish_mesh(mesh, 0);
    test::add_object(scene, std::move(mesh), "subdivided");
    Row row = measure(std::move(scene), "subdivision", level, repeats);
    row.level = level, row.ms_subdivide = ms;
    note(row);
  }

  FILE* out = out_path ? std::fopen(out_path, "w") : stdout;
  if (!out) {
    std::fprintf(stderr, "render_scene_cost: cannot write %s\n", out_path);
    return 1;
  }
  std::fprintf(out, "series,x,objects,triangles,point_lights,area_lights,level,mem_meshes,mem_area_lights,mem_embree,"
                    "mem_edge_meshes,mem_edge_trees,mem_receiver_trees,ms_subdivide,ms_area_lights,ms_ray_scene,ms_edge_finder\n");
  for (const Row& r : rows)
    std::fprintf(out, "%s,%g,%zu,%zu,%zu,%zu,%d,%zu,%zu,%zu,%zu,%zu,%zu,%.3f,%.3f,%.3f,%.3f\n", r.series.c_str(), r.x, r.objects,
                 r.triangles, r.point_lights, r.area_lights, r.level, r.mem_meshes, r.mem_area_lights, r.mem_embree,
                 r.mem_edge_meshes, r.mem_edge_trees, r.mem_receiver_trees, r.ms_subdivide, r.ms_area_lights,
                 r.ms_ray_scene, r.ms_edge_finder);
  if (out != stdout) std::fclose(out);
  return 0;
}

// `epi info SCENE`: what the scene holds and what was built for it.
#include <cstdio>

#include "commands.h"
#include "load_scene.h"
#include "scene/topology.h"
#include "shade/ray_scene.h"
#ifdef EPI_WITH_EDGES
#include "edges/scene_edges.h"
#endif

namespace epi::cli {

namespace {

std::string format_bytes(size_t bytes) {
  char text[64];
  if (bytes >= (size_t(1) << 20))
    std::snprintf(text, sizeof text, "%.2f MiB", double(bytes) / double(1 << 20));
  else
    std::snprintf(text, sizeof text, "%.1f KiB", double(bytes) / 1024.0);
  return text;
}

}  // namespace

int run_info(const InfoOptions& options) {
  LoadOptions load_options;
  load_options.subdiv_level_override = options.subdiv_level;
  load_options.memory_limit = options.memory_limit;
  const Scene scene = load_scene(options.scene, load_options);

  size_t unique_edges = 0, border_edges = 0, non_manifold_edges = 0, welded_vertices = 0, edge_bytes = 0;
  size_t vertices = 0, merged = 0, merged_inexact = 0;
  std::vector<EdgeTable> tables;  // per mesh, for the object lines
  int subdivided = 0;
  for (const Mesh& mesh : scene.meshes) {
    const EdgeTable& table = tables.emplace_back(build_edge_table(mesh));
    vertices += mesh.positions.size();
    merged += table.weld.merged;
    merged_inexact += table.weld.merged_inexact;
    unique_edges += table.edges.size();
    border_edges += table.border_edges;
    non_manifold_edges += table.non_manifold_edges;
    welded_vertices += table.weld.positions.size();
    edge_bytes += table.memory_bytes();
    subdivided += mesh.subdivided ? 1 : 0;
  }
  int by_type[4] = {0, 0, 0, 0};
  for (const PunctualLight& light : scene.punctual_lights) by_type[int(light.type)]++;

  std::printf("scene: %s\n", scene.source.c_str());
  std::printf("objects: %zu\n", scene.objects.size());
  std::printf("meshes: %zu (subdivided: %d)\n", scene.meshes.size(), subdivided);
  std::printf("materials: %zu\n", scene.materials.size());
  // Each mesh counted once (after tessellation and subdivision), then over all objects as rendered.
  size_t mesh_triangles = 0, dropped = 0;
  for (const Mesh& mesh : scene.meshes) mesh_triangles += mesh.triangles.size(), dropped += mesh.degenerate_triangles_dropped;
  std::printf("triangles: %zu (the file's meshes, each once, after tessellation and subdivision; %zu after dropping "
              "%zu degenerate)\n",
              mesh_triangles + dropped, mesh_triangles, dropped);
  std::printf("instanced triangles: %zu (over all %zu objects, as rendered)\n", scene.triangle_count(),
              scene.objects.size());
  std::printf("welded vertices: %zu (of %zu: %zu copies welded, %zu of them within the tolerance but not bit-identical)\n",
              welded_vertices, vertices, merged, merged_inexact);
  std::printf("unique edges: %zu\n", unique_edges);
  std::printf("border edges: %zu\n", border_edges);
  std::printf("non-manifold edges: %zu\n", non_manifold_edges);
  std::printf("lights: %zu (point %d, spot %d, directional %d, area %zu)\n",
              scene.punctual_lights.size() + scene.area_lights.size(), by_type[int(LightType::point)],
              by_type[int(LightType::spot)], by_type[int(LightType::directional)], scene.area_lights.size());
  std::printf("cameras: %zu\n", scene.cameras.size());
  std::printf("camera path keys: %zu\n", scene.camera_path.size());
  const Bounds bounds = scene.world_bounds();
  std::printf("bounds: [%g, %g, %g] - [%g, %g, %g]\n", bounds.min.x, bounds.min.y, bounds.min.z, bounds.max.x,
              bounds.max.y, bounds.max.z);
  for (const Object& object : scene.objects) {
    const Mesh& mesh = scene.meshes[object.mesh];
    const EdgeTable& table = tables[object.mesh];
    std::printf("  object '%s': mesh '%s', %zu triangles%s, %u border and %u non-manifold edges (weld tolerance %.3g)\n",
                object.name.c_str(), mesh.name.c_str(), mesh.triangles.size(),
                mesh.subdivided ? (", subdivided to level " + std::to_string(mesh.subdivision.level)).c_str() : "",
                table.border_edges, table.non_manifold_edges, double(table.weld.tolerance));
  }
  std::printf("memory:\n");
  for (const MemoryItem& item : scene.memory()) std::printf("  %s: %s\n", item.name.c_str(), format_bytes(item.bytes).c_str());
  std::printf("  edge tables: %s\n", format_bytes(edge_bytes).c_str());
  // What the renderer builds for the scene, in bytes (plain numbers, for scripts).
  const RayScene ray_scene(scene);
  for (const MemoryItem& item : ray_scene.memory())
    std::printf("  ray scene, %s: %zu bytes (%s)\n", item.name.c_str(), item.bytes, format_bytes(item.bytes).c_str());
#ifdef EPI_WITH_EDGES
  const edges::SceneEdgeFinder finder(scene);
  std::printf("  edge finder (edge meshes and trees): %zu bytes (%s)\n", finder.memory_bytes(),
              format_bytes(finder.memory_bytes()).c_str());
#endif
  if (!scene.repairs.empty()) {
    std::printf("repairs:\n");
    for (const std::string& line : scene.repairs) std::printf("  %s\n", line.c_str());
  }
  return 0;
}

}  // namespace epi::cli

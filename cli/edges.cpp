// `epi edges`: every silhouette, sharp, border and shadow edge of a scene seen from one viewpoint,
// as world-space JSON, with an optional SVG line drawing and JSON stats (docs/edges.md).
#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "commands.h"
#include "edges/scene_edges.h"
#include "load_scene.h"
#include "output.h"
#include "shade/view.h"

namespace epi::cli {

namespace {

using Clock = std::chrono::steady_clock;
using edges::EdgeKind;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

const char* svg_colour(EdgeKind kind) {
  static const char* colours[] = {"#000000", "#1f5fd0", "#1a9a3a", "#d01f1f", "#f08c00", "#8a2be2"};
  return colours[int(kind)];
}

// The projected edges, clipped to the near plane, as one SVG path per kind.
std::string svg_drawing(const std::vector<edges::SceneEdge>& found, const View& view) {
  const ViewFrame frame(view);
  std::vector<std::ostringstream> paths(edges::kEdgeKindCount);
  const glm::dvec3 eye(frame.eye()), forward(frame.forward());
  const double near = std::max(1e-6, double(view.camera.znear));
  for (const edges::SceneEdge& e : found) {
    glm::dvec3 a = e.a, b = e.b;
    const double da = glm::dot(a - eye, forward), db = glm::dot(b - eye, forward);
    if (da < near && db < near) continue;
    if (da < near) a = a + (b - a) * ((near - da) / (db - da));
    if (db < near) b = b + (a - b) * ((near - db) / (da - db));
    const Projection pa = frame.project(glm::vec3(a)), pb = frame.project(glm::vec3(b));
    paths[int(e.kind)] << "M" << pa.pixel.x << " " << pa.pixel.y << "L" << pb.pixel.x << " " << pb.pixel.y;
  }
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << view.width << "\" height=\"" << view.height
      << "\" viewBox=\"0 0 " << view.width << " " << view.height << "\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (int k = 0; k < edges::kEdgeKindCount; ++k) {
    const std::string d = paths[k].str();
    if (d.empty()) continue;
    svg << "<path id=\"" << edges::to_string(EdgeKind(k)) << "\" fill=\"none\" stroke=\"" << svg_colour(EdgeKind(k))
        << "\" stroke-width=\"0.6\" d=\"" << d << "\"/>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace

int run_edges(const EdgesOptions& options) {
  const auto start = Clock::now();
  check_output_file(options.output);
  if (!options.svg.empty()) check_output_file(options.svg);
  if (!options.stats.empty()) check_output_file(options.stats);
  check_distinct_outputs({options.output, options.svg, options.stats});
  std::unique_ptr<tbb::global_control> thread_limit;
  if (options.threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, options.threads);
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();

  auto stage = Clock::now();
  LoadOptions load_options;
  load_options.subdiv_level_override = options.subdiv_level;
  load_options.memory_limit = options.memory_limit;
  const Scene scene = load_scene(options.scene, load_options);
  const double load_ms = ms_since(stage);
  report_repairs(scene, false);

  View view;
  view.camera = apply_camera_override(scene, options.camera);
  view.width = options.width;
  view.height = options.height;
  const ViewFrame frame(view);  // validates the camera
  const glm::dvec3 eye(view.camera.eye);

  stage = Clock::now();
  edges::SceneEdgeSettings finder_settings;  // every tree: the tree's and brute force's times are both reported
  finder_settings.keep_unchosen_trees = true;
  edges::SceneEdgeFinder finder(scene, finder_settings);
  const double build_ms = ms_since(stage);

  // Edges from the eye with each object's chosen finder, then tree-only and brute-force-only times.
  std::vector<edges::SceneEdge> found;
  stage = Clock::now();
  finder.view_edges(scene, eye, found);
  const double view_ms = ms_since(stage);
  double tree_ms = 0.0, brute_ms = 0.0;
  {
    std::vector<uint32_t> out;
    std::vector<uint8_t> facing;
    for (const Object& object : scene.objects) {
      const edges::EdgeMesh& m = finder.edge_mesh(object.mesh);
      const glm::dvec3 local = glm::dvec3(glm::inverse(glm::dmat4(object.object_to_world)) * glm::dvec4(eye, 1.0));
      const edges::Viewpoint v = m.local_point(local);
      auto t = Clock::now();
      finder.edge_tree(object.mesh).silhouettes(m, v, out);
      tree_ms += ms_since(t);
      t = Clock::now();
      edges::brute_force_silhouettes(m, v, facing, out);
      brute_ms += ms_since(t);
    }
  }

  stage = Clock::now();
  const std::vector<edges::LightBlockerReceiver> triples = finder.find_triples(scene);
  finder.shadow_edges(scene, triples, found);
  const double shadow_ms = ms_since(stage);

  stage = Clock::now();
  nlohmann::json list = nlohmann::json::array();
  size_t counts[edges::kEdgeKindCount] = {};
  for (const edges::SceneEdge& e : found) {
    ++counts[int(e.kind)];
    nlohmann::json item = {{"kind", edges::to_string(e.kind)},
                           {"object", scene.objects[e.object].name},
                           {"a", {e.a.x, e.a.y, e.a.z}},
                           {"b", {e.b.x, e.b.y, e.b.z}}};
    if (e.blocker != kNone) {
      item["blocker"] = scene.objects[e.blocker].name;
      item["light"] = finder.light_names()[e.light];
    }
    list.push_back(std::move(item));
  }
  StagedOutputs outputs;
  outputs.add_json(options.output, nlohmann::json{{"edges", std::move(list)}});
  if (!options.svg.empty()) outputs.add_text(options.svg, svg_drawing(found, view));
  const double write_ms = ms_since(stage);
  const double total_ms = ms_since(start);

  std::printf("%s: %zu objects, %zu triangles, %zu lights, %d threads\n", options.scene.c_str(), scene.objects.size(),
              scene.triangle_count(), finder.lights().size(), threads);
  std::printf("  edges:");
  for (int k = 0; k < edges::kEdgeKindCount; ++k) std::printf(" %s %zu", edges::to_string(EdgeKind(k)), counts[k]);
  std::printf("\n  load %.0f ms | build %.1f ms | view edges %.2f ms (tree %.2f, brute force %.2f) | shadows %.1f ms (%zu triples) | write %.0f ms\n",
              load_ms, build_ms, view_ms, tree_ms, brute_ms, shadow_ms, triples.size(), write_ms);

  if (!options.stats.empty()) {
    nlohmann::json count_json, meshes = nlohmann::json::array();
    for (int k = 0; k < edges::kEdgeKindCount; ++k) count_json[edges::to_string(EdgeKind(k))] = counts[k];
    for (uint32_t i = 0; i < scene.meshes.size(); ++i) {
      const edges::FinderChoice& c = finder.choice(i);
      meshes.push_back({{"name", scene.meshes[i].name},
                        {"faces", finder.edge_mesh(i).face_count()},
                        {"edges", finder.edge_mesh(i).edge_count()},
                        {"tree_nodes", finder.edge_tree(i).nodes().size()},
                        {"finder", c.tree ? "tree" : "brute_force"},
                        {"estimated_tree_ns", c.tree_ns},
                        {"estimated_brute_force_ns", c.brute_ns}});
    }
    nlohmann::json stats = {
        {"scene", options.scene},
        {"eye", {eye.x, eye.y, eye.z}},
        {"threads", threads},
        {"triangles", scene.triangle_count()},
        {"counts", count_json},
        {"triples", triples.size()},
        {"triple_tests", finder.triple_tests()},
        {"receiver_searches", finder.receiver_searches()},
        {"meshes", meshes},
        {"memory_bytes", finder.memory_bytes()},
        {"stages_ms",
         {{"load", load_ms},
          {"tree_build", build_ms},
          {"view_edges", view_ms},
          {"tree_query", tree_ms},
          {"brute_force", brute_ms},
          {"shadows", shadow_ms},
          {"write", write_ms},
          {"total", total_ms}}},
    };
    outputs.add_json(options.stats, stats);
  }
  outputs.commit();
  std::printf("  wrote %s%s%s\n", options.output.c_str(), options.svg.empty() ? "" : " and ", options.svg.c_str());
  return 0;
}

}  // namespace epi::cli

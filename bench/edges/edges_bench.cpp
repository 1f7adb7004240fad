// Edge finding: tree build, tree query and brute force side by side (equal outputs checked) on
// smooth and noisy million-face meshes and on the largest mesh of every bundled scene.
// Run: build-*/bin/edges_bench [--benchmark_filter=...]; figures in docs/edges.md.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>

#include <tbb/global_control.h>

#include "edges/edge_tree.h"
#include "edges/scene_edges.h"
#include "edges/shadow_events.h"
#include "load_scene.h"
#include "test_meshes.h"

namespace {

using namespace epi;
using namespace epi::edges;

struct Case {
  std::string name;
  Mesh mesh;
};

// Meshes: synthetic ones, then the largest mesh of each bundled scene.
std::vector<Case>& cases() {
  static std::vector<Case> all = [] {
    std::vector<Case> list;
    list.push_back({"sphere_1M", test::uv_sphere(501, 1000)});
    list.push_back({"bumpy_1M", test::bumpy_sphere(501, 1000, 0.02f, 1)});
    list.push_back({"torus_100k", test::torus(500, 100)});
    list.push_back({"sphere_300k", test::uv_sphere(275, 546)});
    list.push_back({"sphere_100k", test::uv_sphere(159, 316)});
    list.push_back({"sphere_10k", test::uv_sphere(51, 100)});
    list.push_back({"sphere_1k", test::uv_sphere(17, 32)});
    for (const char* scene : {"cornell_box", "torus_capsule", "chains", "rooms", "grid_dragon"}) {
      const std::filesystem::path file = std::filesystem::path(EPI_SOURCE_DIR) / "scenes" / (std::string(scene) + ".gltf");
      if (!std::filesystem::exists(file)) continue;
      const Scene s = load_scene(file);
      size_t largest = 0;
      for (size_t i = 0; i < s.meshes.size(); ++i)
        if (s.meshes[i].triangles.size() > s.meshes[largest].triangles.size()) largest = i;
      list.push_back({std::string(scene) + "/" + s.meshes[largest].name, s.meshes[largest]});
    }
    return list;
  }();
  return all;
}

struct Prepared {
  EdgeMesh mesh;
  EdgeTree tree;
  std::vector<Viewpoint> views;  // around the mesh at 2 to 4 radii, deterministic
  double nodes_visited = 0.0, edges_tested = 0.0;  // per query, averaged over the views
};

Prepared& prepared(size_t i) {
  static std::map<size_t, std::unique_ptr<Prepared>> cache;
  auto& slot = cache[i];
  if (!slot) {
    slot = std::make_unique<Prepared>();
    slot->mesh = build_edge_mesh(cases()[i].mesh);
    slot->tree = EdgeTree(slot->mesh);
    double radius = 0.0;
    for (const glm::vec3& p : slot->mesh.positions) radius = std::max(radius, glm::length(glm::dvec3(p) - slot->mesh.origin));
    for (int k = 0; k < 64; ++k) {
      const double a = 2.399963 * k, z = 1.0 - (2.0 * k + 1.0) / 64.0, r = std::sqrt(1.0 - z * z);
      const glm::dvec3 dir(r * std::cos(a), z, r * std::sin(a));
      slot->views.push_back(slot->mesh.local_point(slot->mesh.origin + dir * radius * (2.0 + 2.0 * (k % 3) / 2.0)));
    }
    // The tree's work per query (the inputs of the choice rule's cost model).
    for (const Viewpoint& v : slot->views) {
      const double e[3] = {v.x, v.y, v.z};
      std::vector<uint32_t> stack = {0};
      while (!slot->tree.nodes().empty() && !stack.empty()) {
        const EdgeTreeNode& node = slot->tree.nodes()[stack.back()];
        stack.pop_back();
        slot->nodes_visited += 1.0 / slot->views.size();
        if (!EdgeTree::may_hold_silhouette(node, e, v.w)) continue;
        slot->edges_tested += double(node.count) / slot->views.size();
        if (node.left != kNone) stack.push_back(node.left), stack.push_back(node.right);
      }
    }
    // Equal outputs, checked once.
    std::vector<uint8_t> facing;
    std::vector<uint32_t> a, b;
    for (const Viewpoint& v : slot->views) {
      slot->tree.silhouettes(slot->mesh, v, a);
      brute_force_silhouettes(slot->mesh, v, facing, b);
      if (a != b) throw std::runtime_error(cases()[i].name + ": tree and brute force differ");
    }
  }
  return *slot;
}

void BM_EdgeMesh(benchmark::State& state) {
  const Case& c = cases()[state.range(0)];
  state.SetLabel(c.name);
  for (auto _ : state) benchmark::DoNotOptimize(build_edge_mesh(c.mesh));
  state.counters["faces"] = double(c.mesh.triangles.size());
}

void BM_TreeBuild(benchmark::State& state) {
  const Case& c = cases()[state.range(0)];
  state.SetLabel(c.name + (state.range(1) == 1 ? " 1 thread" : " all threads"));
  const EdgeMesh& mesh = prepared(state.range(0)).mesh;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, state.range(1) == 1 ? 1 : 64);
  for (auto _ : state) benchmark::DoNotOptimize(EdgeTree(mesh));
  state.counters["edges"] = double(mesh.edge_count());
}

void BM_TreeQuery(benchmark::State& state) {
  Prepared& p = prepared(state.range(0));
  state.SetLabel(cases()[state.range(0)].name);
  std::vector<uint32_t> out;
  size_t k = 0, found = 0;
  for (auto _ : state) {
    p.tree.silhouettes(p.mesh, p.views[k++ % p.views.size()], out);
    found += out.size();
  }
  state.counters["silhouettes"] = benchmark::Counter(double(found), benchmark::Counter::kAvgIterations);
  state.counters["nodes"] = p.nodes_visited;
  state.counters["tested"] = p.edges_tested;
}

void BM_BruteForce(benchmark::State& state) {
  Prepared& p = prepared(state.range(0));
  state.SetLabel(cases()[state.range(0)].name);
  std::vector<uint32_t> out;
  std::vector<uint8_t> facing;
  size_t k = 0;
  for (auto _ : state) brute_force_silhouettes(p.mesh, p.views[k++ % p.views.size()], facing, out);
  state.counters["faces"] = double(p.mesh.face_count());
  state.counters["edges"] = double(p.mesh.edge_count());
}

// Area-light events (VE and EV) of the mesh under a square light of half the mesh's radius, two
// radii above it, through the tree (as the finder does when its rule picks the tree) and by brute
// force over the edges.
void BM_AreaEvents(benchmark::State& state) {
  Prepared& p = prepared(state.range(0));
  const bool tree = state.range(1) != 0;
  state.SetLabel(cases()[state.range(0)].name + (tree ? " tree" : " brute force"));
  double radius = 0.0;
  for (const glm::vec3& q : p.mesh.positions) radius = std::max(radius, glm::length(glm::dvec3(q) - p.mesh.origin));
  EdgeLight light;
  light.type = EdgeLight::Type::area;
  const glm::dvec3 c = p.mesh.origin + glm::dvec3(0.3, 2.0, 0.2) * radius;
  const double h = 0.25 * radius;
  light.outlines = {{c + glm::dvec3(-h, 0, -h), c + glm::dvec3(h, 0, -h), c + glm::dvec3(h, 0, h), c + glm::dvec3(-h, 0, h)}};
  const BlockerView blocker{&p.mesh, tree ? &p.tree : nullptr, glm::dmat4(1.0), 0};
  std::vector<ShadowEvent> events;
  for (auto _ : state) {
    events.clear();
    find_shadow_events(blocker, light, 0, events);
  }
  state.counters["events"] = double(events.size());
}

// Shadow edges of a whole scene from scratch (epi edges without a shader's triples): triples by
// bounds, then every pair's events over its receivers, for n boxes on a floor (issue 14: this
// grew quadratically with instances). Counters: the work, which should grow about as n.
void BM_SceneShadows(benchmark::State& state) {
  const Scene scene = test::boxes_on_a_floor(int(state.range(0)));
  size_t triples = 0, edges = 0;
  uint64_t tests = 0, searches = 0;
  for (auto _ : state) {
    SceneEdgeFinder finder(scene);
    const auto found = finder.find_triples(scene);
    std::vector<SceneEdge> out;
    finder.shadow_edges(scene, found, out);
    triples = found.size(), edges = out.size(), tests = finder.triple_tests(), searches = finder.receiver_searches();
  }
  state.counters["objects"] = double(scene.objects.size());
  state.counters["triples"] = double(triples);
  state.counters["triple_tests"] = double(tests);
  state.counters["receiver_searches"] = double(searches);
  state.counters["shadow_edges"] = double(edges);
}

void register_all() {
  for (int n : {100, 400, 1600})
    benchmark::RegisterBenchmark("SceneShadows", BM_SceneShadows)->Arg(n)->Unit(benchmark::kMillisecond)->UseRealTime();
  for (size_t i = 0; i < cases().size(); ++i) {
    benchmark::RegisterBenchmark("EdgeMesh", BM_EdgeMesh)->Arg(int64_t(i))->Unit(benchmark::kMillisecond);
    for (int threads : {1, 2})
      benchmark::RegisterBenchmark("TreeBuild", BM_TreeBuild)->Args({int64_t(i), threads})->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark("TreeQuery", BM_TreeQuery)->Arg(int64_t(i))->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("BruteForce", BM_BruteForce)->Arg(int64_t(i))->Unit(benchmark::kMicrosecond);
    for (int tree : {1, 0})
      benchmark::RegisterBenchmark("AreaEvents", BM_AreaEvents)->Args({int64_t(i), tree})->Unit(benchmark::kMillisecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

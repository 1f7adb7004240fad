// Point processing (issue 11): the point cache's fast path against its reference path (the
// oracle of tests/render/point_cache_fast_test.cpp), in one run. A cloud is warmed by sync frames
// along the scene's camera path (budget 5% for 24 frames: about as full as render_bench's 120
// frames at 1%); then two copies of it, one on each path, process the next frames of the path in
// turn, each stage timed: projection, depth cull, occlusion test (epi mode, with the warm-up's
// last edge mask) and EPI fill. Medians over the frames; manual time = the fast path's total.
//   render_points_bench --benchmark_format=json > points.json; python3 bench/render/points_table.py points.json
// Against an earlier build (the same frames; run the two binaries one after the other):
//   python3 bench/render/points_table.py --baseline before.json after.json
// EPI_POINTS_FAST_ONLY=1 skips the reference path (profiling the fast path: perf record).
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "load_scene.h"
#include "render/camera_path.h"
#include "render/renderer.h"

namespace epi::render {
namespace {

const char* kScenes[] = {"cornell_box", "chains", "rooms", "torus_capsule", "grid_dragon"};
constexpr int kPathFrames = 120, kWarmFrames = 24;

struct Warmed {
  Warmed(int scene_index, int width, int height) {
    const Scene scene = load_scene(std::string(EPI_SOURCE_DIR) + "/scenes/" + kScenes[scene_index] + ".gltf");
    RayScene ray_scene(scene);
    const Shader shader(ray_scene, ShaderSettings{});
    FrameSettings s;
    s.width = width, s.height = height, s.sync = true, s.sample_budget = 0.05, s.stage_timings = false;
    FrameRenderer renderer(scene, ray_scene, shader, s);
    path = scene_camera_path(scene, kPathFrames);
    for (int k = 0; k < kWarmFrames; ++k) renderer.render(path.camera_at(k));
    cache = std::make_unique<PointCache>(renderer.cache());
    edge_pixels = renderer.edge_pixels();
    crossings.build(renderer.segments(), renderer.segment_kinds(), width, height);
    for (const Object& o : scene.objects) transforms.push_back(o.object_to_world);
  }
  CameraPath path;
  std::unique_ptr<PointCache> cache;
  std::vector<uint8_t> edge_pixels;
  EdgeCrossings crossings;
  std::vector<glm::mat4> transforms;
};

Warmed& warmed(int scene, int width, int height) {
  static std::map<std::tuple<int, int, int>, std::unique_ptr<Warmed>> cache;
  auto& slot = cache[{scene, width, height}];
  if (!slot) {
    cache.clear();  // one cloud in memory at a time
    return *cache.emplace(std::tuple{scene, width, height}, std::make_unique<Warmed>(scene, width, height)).first->second;
  }
  return *slot;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// args: scene, width, height, mode (0 epi, 1 render cache), threads
void BM_Points(benchmark::State& state) {
  const int width = int(state.range(1)), height = int(state.range(2));
  Warmed& w = warmed(int(state.range(0)), width, height);  // on all cores: the warm-up is not timed
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(4)));
  const bool epi = state.range(3) == 0;
  PointCache fast(*w.cache), reference(*w.cache);
  reference.use_reference_path(true);
  EpiImage epi_image(width, height);
  enum { kProject, kCull, kOcclusion, kFill, kTotal, kStages };
  std::vector<double> times[2][kStages];
  // One thread: CPU time of the thread doing the work (robust on a shared machine); more: wall time.
  const bool cpu_time = state.range(4) == 1;
  auto now_ms = [cpu_time] {
    if (!cpu_time) return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
  };
  const bool fast_only = std::getenv("EPI_POINTS_FAST_ONLY") != nullptr;  // for profiling: no reference frames
  int frame = kWarmFrames;
  std::vector<double> count_pass_ms;
  for (auto _ : state) {
    View view;
    view.camera = w.path.camera_at(frame++ % kPathFrames), view.width = width, view.height = height;
    const ViewFrame vf(view);
    for (int r = fast_only ? 1 : 0; r < 2; ++r) {  // the reference first, then the fast path, on the same frame
      PointCache& cache = r == 0 ? reference : fast;
      double t = now_ms();
      auto lap = [&](int stage) {
        const double now = now_ms();
        times[r][stage].push_back(now - t);
        t = now;
      };
      const double start = t;
      cache.project(vf, w.transforms, !epi);
      lap(kProject);
      if (epi) {
        cache.depth_cull(w.edge_pixels);
        lap(kCull);
        cache.cull_behind_surfaces(vf, w.transforms, w.crossings);
        lap(kOcclusion);
      }
      cache.fill_epi(epi_image);
      lap(kFill);
      times[r][kTotal].push_back(t - start);
      if (r == 1) state.SetIterationTime(times[r][kTotal].back() * 1e-3);
    }
    // The valid count the viewer shows every frame: kept by the cache (valid_points), against the
    // pass over every slot it made before 2026-11-29 (not part of the stages' total).
    const double before_count = now_ms();
    const size_t counted = size_t(std::count_if(fast.points().begin(), fast.points().end(), [](const CachePoint& p) { return p.valid; }));
    count_pass_ms.push_back(now_ms() - before_count);
    if (counted != fast.valid_points()) state.SkipWithError("valid_points differs from a count of the slots");
  }
  state.counters["count_pass_ms"] = median(count_pass_ms);
  const char* names[kStages] = {"project", "cull", "occlusion", "fill", "total"};
  for (int k = 0; k < kStages; ++k) {
    state.counters[std::string(names[k]) + "_ms"] = median(times[1][k]);
    state.counters[std::string("ref_") + names[k] + "_ms"] = median(times[0][k]);
  }
  state.counters["speedup"] = median(times[0][kTotal]) / std::max(median(times[1][kTotal]), 1e-9);
  state.counters["points"] = double(fast.valid_points());
  state.SetLabel(std::string(kScenes[state.range(0)]) + (epi ? " epi" : " rendercache"));
}

// 1 and 2 threads; at 1080p also 4, 8, ... up to the cores (scaling past two cores:
// bench/scaling_run.sh).
void points_args(benchmark::internal::Benchmark* b) {
  const int cores = std::max(2, tbb::this_task_arena::max_concurrency());
  for (int scene : {0, 1, 2, 3, 4})
    for (auto [w, h] : {std::pair{512, 512}, std::pair{1920, 1080}})
      for (int mode : {0, 1})
        for (int threads = 1; threads <= (w == 1920 ? cores : 2); threads *= 2) b->Args({scene, w, h, mode, threads});
}

BENCHMARK(BM_Points)->Apply(points_args)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(30);

}  // namespace
}  // namespace epi::render

BENCHMARK_MAIN();

// The paper's table 2 for the bundled scenes: per-stage ms of an EPI frame (and of a render cache
// frame) along the scene's camera path, frame rate and sparseness, and the speed-up of a frame over
// a 1-sample-per-pixel raytrace frame with the same shader. Frames run in sync mode; the time
// reported (manual time) excludes shading, which the paper runs on other processors.
// args of BM_Frame: scene, width, height, mode; of BM_FrameThreads: scene, width, height, loop
// threads; of BM_RaytraceFrame: scene, width, height, shader.
// bench/frame_tables.py turns the JSON into docs/performance.md's table 2 and its bar chart.
#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include <tbb/task_arena.h>

#include "load_scene.h"
#include "render/camera_path.h"
#include "render/renderer.h"
#include "shade/render_image.h"

namespace epi::render {
namespace {

const char* kScenes[] = {"cornell_box", "chains", "rooms", "torus_capsule", "grid_dragon"};

struct Loaded {
  explicit Loaded(const std::string& name)
      : scene(load_scene(std::string(EPI_SOURCE_DIR) + "/scenes/" + name + ".gltf")), ray_scene(scene),
        shader(ray_scene, ShaderSettings{}) {}
  Scene scene;
  RayScene ray_scene;
  Shader shader;
};

Loaded& loaded(int index) {
  static std::map<int, std::unique_ptr<Loaded>> cache;
  auto& slot = cache[index];
  if (!slot) {
    cache.clear();  // one scene in memory at a time
    return *cache.emplace(index, std::make_unique<Loaded>(kScenes[index])).first->second;
  }
  return *slot;
}

constexpr int kPathFrames = 120;

// Frames along the scene's path at mode (0 epi, 1 rendercache, 2 epi with core/epi's tiled
// reconstructor). The timed frames run in a task arena of `threads` threads (0: all cores), which
// every stage sizes its work from (the reconstructor's arena too); the warm-up uses all cores, so
// that a 1-thread case does not spend minutes warming the cache.
void frames(benchmark::State& state, int mode, int threads) {
  Loaded& l = loaded(int(state.range(0)));
  FrameSettings s;
  s.width = int(state.range(1)), s.height = int(state.range(2));
  s.mode = mode == 1 ? RenderMode::rendercache : RenderMode::epi;
  s.stage_timings = mode != 2;
  s.sync = true;
  s.sample_budget = 0.01;
  FrameRenderer renderer(l.scene, l.ray_scene, l.shader, s);
  const CameraPath path = scene_camera_path(l.scene, kPathFrames);
  int frame = 0;
  // Warm the cache over one pass of the path, so that the timed frames see a steady state (a cloud
  // covering the image, as in the paper's runs) rather than the first sparse frames.
  for (int k = 0; k < kPathFrames; ++k) renderer.render(path.camera_at(frame++ % kPathFrames));
  tbb::task_arena loop_arena(threads > 0 ? threads : int(tbb::task_arena::automatic));
  StageTimes sum;
  double samples = 0, simple = 0, complex = 0, edges = 0, culled = 0, blended = 0, integrate = 0;
  int64_t frames = 0;
  for (auto _ : state) {
    loop_arena.execute([&] { renderer.render(path.camera_at(frame++ % kPathFrames)); });
    const FrameStats& f = renderer.stats();
    state.SetIterationTime(f.ms.loop_ms() * 1e-3);
    for (size_t k = 0; k < sum.ms.size(); ++k) sum.ms[k] += f.ms.ms[k];
    sum.total += f.ms.loop_ms();
    samples += double(f.samples);
    blended += double(f.sparse_blended);
    integrate += f.integrate_ms;
    simple += double(f.pixels.simple), complex += double(f.pixels.complex);
    edges += double(f.edges.silhouette + f.edges.sharp + f.edges.border + f.edges.shadow), culled += double(f.edges.culled);
    ++frames;
  }
  const double n = double(std::max<int64_t>(frames, 1)), pixels = double(s.width) * double(s.height);
  // One counter per loop stage (frame_stages.h), named as the stats JSON's stages_ms + "_ms".
  for (const FrameStageInfo& i : kFrameStages)
    if (i.loop) state.counters[std::string(i.name) + "_ms"] = sum[i.stage] / n;
  state.counters["loop_ms"] = sum.total / n;
  state.counters["integrate_ms"] = integrate / n;  // of points_ms
  state.counters["fps"] = 1000.0 / (sum.total / n);
  state.counters["sparseness"] = pixels / std::max(1.0, samples / n);
  state.counters["simple_pct"] = 100.0 * simple / n / pixels;
  state.counters["complex_pct"] = 100.0 * complex / n / pixels;
  state.counters["sparse_blended_pct"] = 100.0 * blended / n / pixels;
  state.counters["edges"] = edges / n;
  state.counters["culled"] = culled / n;
  state.counters["loop_threads"] = renderer.stats().loop_threads;
  state.SetLabel(kScenes[state.range(0)]);
}

// args: scene index, width, height, mode.
void BM_Frame(benchmark::State& state) { frames(state, int(state.range(3)), 0); }

// The frame loop's scaling past two cores (docs/performance.md, bench/scaling_run.sh): the tiled
// path (mode 2) with the loop held to a thread count. args: scene index, width, height, threads.
void BM_FrameThreads(benchmark::State& state) { frames(state, 2, int(state.range(3))); }

// The asynchronous loop and shader sharing the cores (FrameSettings::core_split; docs/render.md,
// "Cores"): frames back to back along the path, as in the viewer without vsync. args: scene,
// width, height, shader (0 direct, 1 gi), split (0 adaptive, 1 shared). Reported: the loop's
// frame rate (manual time: the frame's wall time) and the shading throughput (results
// integrated per second of wall time), after 30 warm-up frames.
void BM_AsyncLoop(benchmark::State& state) {
  Loaded& l = loaded(int(state.range(0)));
  ShaderSettings shading;
  shading.kind = state.range(3) == 1 ? ShaderKind::gi : ShaderKind::direct;
  const Shader shader(l.ray_scene, shading);
  FrameSettings s;
  s.width = int(state.range(1)), s.height = int(state.range(2));
  s.sample_budget = 0.01;
  s.stage_timings = false;
  s.core_split = state.range(4) == 0 ? CoreSplit::adaptive : CoreSplit::shared;
  FrameRenderer renderer(l.scene, l.ray_scene, shader, s);
  const CameraPath path = scene_camera_path(l.scene, kPathFrames);
  int frame = 0;
  for (int k = 0; k < 30; ++k) renderer.render(path.camera_at(frame++ % kPathFrames));
  double samples = 0, loop_threads = 0, frames = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    renderer.render(path.camera_at(frame++ % kPathFrames));
    state.SetIterationTime(renderer.stats().ms.total * 1e-3);
    samples += double(renderer.stats().samples), loop_threads += renderer.stats().loop_threads, ++frames;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state.counters["fps"] = frames / seconds;
  state.counters["samples_per_s"] = samples / seconds;
  state.counters["samples_per_frame"] = samples / std::max(1.0, frames);
  state.counters["loop_threads"] = loop_threads / std::max(1.0, frames);
  state.SetLabel(std::string(kScenes[state.range(0)]) + (state.range(3) == 1 ? " gi" : " direct") +
                 (state.range(4) == 0 ? " adaptive" : " shared"));
}

// A 1-sample-per-pixel frame: the speed-up's denominator. args: scene, width, height, shader
// (0 direct, the frames' shader; 1 gi, the expensive shader the papers have in mind: an EPI
// frame costs the same whatever the shader, since shading runs asynchronously beside it).
void BM_RaytraceFrame(benchmark::State& state) {
  Loaded& l = loaded(int(state.range(0)));
  View view;
  view.camera = l.scene.cameras.at(0), view.width = int(state.range(1)), view.height = int(state.range(2));
  ShaderSettings settings;
  settings.kind = state.range(3) == 1 ? ShaderKind::gi : ShaderKind::direct;
  const Shader shader(l.ray_scene, settings);
  for (auto _ : state) benchmark::DoNotOptimize(render_image(shader, view, 1));
  state.SetLabel(std::string(kScenes[state.range(0)]) + (state.range(3) == 1 ? " gi" : " direct"));
}

constexpr std::pair<int, int> kSizes[] = {{512, 512}, {1920, 1080}, {3840, 2160}};

void frame_args(benchmark::internal::Benchmark* b) {
  for (int scene = 0; scene < 5; ++scene)
    for (auto [w, h] : kSizes)
      for (int mode : {0, 1, 2}) b->Args({scene, w, h, mode});
}
// No 4K ray trace: the speed-up is reported at 1080p (a 4K gi frame takes minutes here).
void raytrace_args(benchmark::internal::Benchmark* b) {
  for (int scene = 0; scene < 5; ++scene)
    for (auto [w, h] : {kSizes[0], kSizes[1]})
      for (int shader : {0, 1}) b->Args({scene, w, h, shader});
}

// 1, 2, 4, ... threads up to the cores, every scene at 1080p.
void thread_args(benchmark::internal::Benchmark* b) {
  const int cores = std::max(1, tbb::this_task_arena::max_concurrency());
  for (int scene = 0; scene < 5; ++scene)
    for (int t = 1; t <= cores; t *= 2) b->Args({scene, 1920, 1080, t});
}

void async_args(benchmark::internal::Benchmark* b) {
  for (int scene = 0; scene < 5; ++scene)
    for (int shader : {0, 1})
      for (int split : {0, 1}) b->Args({scene, 512, 512, shader, split});
}

BENCHMARK(BM_AsyncLoop)->Apply(async_args)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_Frame)->Apply(frame_args)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_FrameThreads)->Apply(thread_args)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(1.0);
// A gi frame at 1080p takes seconds: its first iteration passes MinTime and is the figure.
BENCHMARK(BM_RaytraceFrame)->Apply(raytrace_args)->Unit(benchmark::kMillisecond)->MinTime(1.0);

}  // namespace
}  // namespace epi::render

BENCHMARK_MAIN();

// Ray-tracing throughput of the shader on a ~65k-triangle scene built in code:
// primary rays, direct shading of 1% of a 512x512 view, and a 1-spp raytrace frame.
#include <benchmark/benchmark.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "shade/render_image.h"
#include "shade/sampling.h"
#include "test_scenes.h"

namespace epi {
namespace {

struct BenchScene {
  Scene scene;
  std::unique_ptr<RayScene> rays;
  View view{test::look({0, -6, 2.5f}, {0, 0, 0.8f}, 40.0f), 512, 512};

  BenchScene() {
    uint32_t grey = test::add_material(scene, glm::vec3(0.6f));
    uint32_t gold = test::add_material(scene, glm::vec3(1.0f, 0.8f, 0.3f), 1.0f, 0.3f);
    uint32_t red = test::add_material(scene, glm::vec3(0.7f, 0.1f, 0.1f), 0.0f, 0.5f);
    uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(8.0f));
    test::add_object(scene, test::quad_mesh({-6, -6, 0}, {12, 0, 0}, {0, 12, 0}, grey), "floor");
    test::add_object(scene, test::sphere_mesh({-1.0f, 0, 1.0f}, 1.0f, 128, 128, gold), "gold");
    test::add_object(scene, test::sphere_mesh({1.2f, 0.5f, 0.8f}, 0.8f, 128, 128, red), "red");
    uint32_t panel = test::add_object(scene, test::quad_mesh({-0.5f, -0.5f, 4}, {0, 1, 0}, {1, 0, 0}, emitter), "panel");
    test::add_area_light(scene, panel);
    scene.punctual_lights.push_back(test::point_light({3, -3, 4}, glm::vec3(20.0f)));
    rays = std::make_unique<RayScene>(scene);
  }
};

BenchScene& bench_scene() {
  static BenchScene s;
  return s;
}

// Runs f with `threads` TBB threads (0: all cores). One thread makes the CPU-time column the
// whole cost, which stays meaningful when other jobs share the machine.
template <class F>
void with_threads(int threads, F&& f) {
  tbb::task_arena arena(threads > 0 ? threads : int(tbb::task_arena::automatic));
  arena.execute(f);
}

void set_rate(benchmark::State& state, uint64_t rays) {
  state.counters["Mrays/s"] = benchmark::Counter(double(rays) * 1e-6, benchmark::Counter::kIsRate);
  state.counters["triangles"] = double(bench_scene().scene.triangle_count());
}

// Camera rays only, one at a time (rtcIntersect1), in parallel over rows.
void BM_PrimaryRays(benchmark::State& state) {
  BenchScene& s = bench_scene();
  ViewFrame frame(s.view);
  uint64_t rays = 0;
  for (auto _ : state) with_threads(int(state.range(0)), [&] {
    size_t hits = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, s.view.height), size_t(0),
        [&](const tbb::blocked_range<int>& rows, size_t count) {
          FlushDenormals flush;
          for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < s.view.width; ++x) count += s.rays->intersect(frame.ray(float(x) + 0.5f, float(y) + 0.5f)).hit;
          return count;
        },
        std::plus<size_t>());
    benchmark::DoNotOptimize(hits);
    rays += uint64_t(s.view.width) * uint64_t(s.view.height);
  });
  set_rate(state, rays);
}
BENCHMARK(BM_PrimaryRays)->ArgName("threads")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// Camera rays in 4x4-pixel packets (rtcIntersect16), in parallel over rows of packets.
void BM_PrimaryRaysPacket16(benchmark::State& state) {
  BenchScene& s = bench_scene();
  ViewFrame frame(s.view);
  uint64_t rays = 0;
  for (auto _ : state) with_threads(int(state.range(0)), [&] {
    size_t hits = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, s.view.height / 4), size_t(0),
        [&](const tbb::blocked_range<int>& rows, size_t count) {
          FlushDenormals flush;
          Ray packet[16];
          RayHit found[16];
          for (int by = rows.begin(); by < rows.end(); ++by)
            for (int bx = 0; bx < s.view.width / 4; ++bx) {
              for (int i = 0; i < 16; ++i)
                packet[i] = frame.ray(float(4 * bx + i % 4) + 0.5f, float(4 * by + i / 4) + 0.5f);
              s.rays->intersect16(packet, 16, found);
              for (const RayHit& h : found) count += h.hit;
            }
          return count;
        },
        std::plus<size_t>());
    benchmark::DoNotOptimize(hits);
    rays += uint64_t(s.view.width) * uint64_t(s.view.height);
  });
  set_rate(state, rays);
}
BENCHMARK(BM_PrimaryRaysPacket16)->ArgName("threads")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// The render cache's request pattern: 1% of the pixels at random positions, direct lighting
// (state.range(0) area-light samples per hit; state.range(1) threads, 0: all).
void BM_DirectShading1Percent(benchmark::State& state) {
  BenchScene& s = bench_scene();
  ShaderSettings settings;
  settings.area_light_samples = int(state.range(0));
  Shader shader(*s.rays, settings);
  std::vector<ShadeRequest> requests;
  Rng rng(42);
  for (uint32_t i = 0; i < uint32_t(s.view.width * s.view.height / 100); ++i)
    requests.push_back({i, rng.uniform() * float(s.view.width), rng.uniform() * float(s.view.height)});
  uint64_t rays = 0;
  ShadeBatch batch;
  for (auto _ : state) with_threads(int(state.range(1)), [&] {
    batch.clear();
    shader.shade(s.view, requests, batch);
    rays += batch.rays;
  });
  set_rate(state, rays);
  state.counters["requests/s"] = benchmark::Counter(double(requests.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DirectShading1Percent)
    ->ArgNames({"samples", "threads"})
    ->Args({16, 1})
    ->Args({16, 0})
    ->Args({64, 1})
    ->Args({64, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// A whole 512x512 frame at one sample per pixel: arg 0 = direct lighting (16 area samples),
// arg 1 = the baseline path of the platform notes (camera, shadow, one bounce, shadow);
// second argument: threads (0: all).
void BM_RaytraceFrame(benchmark::State& state) {
  BenchScene& s = bench_scene();
  ShaderSettings settings;
  if (state.range(0) == 1) {
    settings.kind = ShaderKind::gi;
    settings.area_light_samples = 1;
    settings.gi_paths = 1;
    settings.gi_max_bounces = 1;
    settings.gi_light_samples = 1;
  }
  Shader shader(*s.rays, settings);
  uint64_t rays = 0;
  for (auto _ : state) with_threads(int(state.range(1)), [&] {
    RenderStats stats;
    RgbImage image = render_image(shader, s.view, 1, {}, &stats);
    benchmark::DoNotOptimize(image.pixels.data());
    rays += stats.rays;
  });
  set_rate(state, rays);
}
BENCHMARK(BM_RaytraceFrame)
    ->ArgNames({"path", "threads"})
    ->Args({0, 1})
    ->Args({0, 0})
    ->Args({1, 1})
    ->Args({1, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace epi

BENCHMARK_MAIN();

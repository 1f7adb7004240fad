// The edge stage's depth filter (issue 11; docs/performance.md, "Edge stage"): filter_depth over a
// random point image, `empty` percent of its pixels without a point (drawn and empty pixels
// alternate at random, as in a frame's point image). args: width, height, empty %, threads.
//   render_raster_bench --benchmark_format=json > raster.json
// Against an earlier build: run its binary on the same arguments one after the other.
#include <limits>
#include <random>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "render/edge_projection.h"

namespace epi::render {
namespace {

PointImage random_point_image(int w, int h, double empty, uint32_t seed) {
  PointImage image;
  image.width = w, image.height = h;
  const size_t n = size_t(w) * size_t(h);
  image.point.resize(n), image.depth.resize(n), image.region.assign(n, 0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth(0.5f, 20.0f), u(0.0f, 1.0f);
  for (size_t i = 0; i < n; ++i) {
    const bool drawn = u(rng) >= empty;
    image.point[i] = drawn ? int32_t(i) : -1;
    image.depth[i] = drawn ? depth(rng) : std::numeric_limits<float>::infinity();
  }
  return image;
}

void BM_FilterDepth(benchmark::State& state) {
  const int w = int(state.range(0)), h = int(state.range(1));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(3)));
  const PointImage image = random_point_image(w, h, double(state.range(2)) / 100.0, 7);
  std::vector<float> out;
  filter_depth(image, DepthFilterSettings{}, out);  // sized once, as in the frame loop
  for (auto _ : state) {
    filter_depth(image, DepthFilterSettings{}, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(w) * int64_t(h));  // pixels per second
}
BENCHMARK(BM_FilterDepth)
    ->ArgsProduct({{512}, {512}, {10, 50}, {1, 2}})
    ->ArgsProduct({{1920}, {1080}, {10, 50}, {1, 2}})
    ->ArgsProduct({{3840}, {2160}, {10, 50}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace epi::render

BENCHMARK_MAIN();

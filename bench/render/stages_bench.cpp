// Frame-loop stages outside the point cache and the reconstruction, on synthetic inputs (issue 11;
// docs/performance.md, "Edge stage" and "Predictive sampling"):
//   BM_FilterDepth          the edge stage's depth filter over a random point image, `empty` percent
//                           of its pixels without a point (drawn and empty pixels alternate at
//                           random, as in a frame's point image). args: width, height, empty %, threads.
//   BM_PredictedOccupancy   predictive sampling's splat of 1/stride of a cloud of 1.15 points per
//                           pixel into the view a few frames ahead. args: width, height, stride, threads.
//   BM_FillHoles            the hole fill after fast motion as the renderer runs it (list_holes, then
//                           fill_listed_holes): `holes` per mille of the pixels in blobs of up to
//                           8x8, one barrier column in 16; 0: the listing pass alone, the usual frame
//                           at rest; `top` % of the other pixels at top priority with a colour,
//                           as the filters' fallback leaves them in motion. args: width, height,
//                           holes ‰, threads, top %.
//   BM_SparseBlend          the sparse regions' blend (sparse_blend.h) over an EPI holding a sample in
//                           `density` percent of its pixels at random, barriers along one row and
//                           one column in 32; kernel 0: the scalar oracle (sparse_blend_reference),
//                           1: the Highway kernels (sparse_blend), outputs checked equal first.
//                           args: width, height, density %, threads, kernel.
//   render_stages_bench --benchmark_format=json > stages.json
// Against an earlier build: run its binary on the same arguments one after the other.
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <thread>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "epi/interpolate.h"
#include "render/edge_projection.h"
#include "render/hole_fill.h"
#include "render/point_cache.h"
#include "render/sampling.h"
#include "render/sparse_blend.h"

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

// A cloud of 1.15 points per pixel on three objects in front of the camera, as insert leaves it.
struct Cloud {
  Cloud(int w, int h) : cache(w, h), transforms(3, glm::mat4(1.0f)) {
    view.camera.eye = {0, 0, 6}, view.camera.target = {0, 0, 0}, view.width = w, view.height = h;
    const ViewFrame shot(view);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    ShadeBatch batch;
    for (size_t k = 0; k < size_t(1.15 * w * h); ++k) {
      ShadeResult r;
      r.x = (u(rng) * 0.5f + 0.5f) * float(w), r.y = (u(rng) * 0.5f + 0.5f) * float(h);
      r.hit = true, r.object = uint32_t(k % 3);
      r.position = {2.0f * u(rng), 2.0f * u(rng), u(rng)};
      r.normal = {0, 0, 1};
      batch.results.push_back(r);
    }
    cache.insert(shot, batch, transforms);
    ahead = view;
    ahead.camera.eye = {0.4f, 0.1f, 5.5f};
  }
  PointCache cache;
  std::vector<glm::mat4> transforms;
  View view, ahead;
};

void BM_PredictedOccupancy(benchmark::State& state) {
  const int w = int(state.range(0)), h = int(state.range(1));
  static std::map<std::pair<int, int>, std::unique_ptr<Cloud>> clouds;  // one per size, built once
  auto& cloud = clouds[{w, h}];
  if (!cloud) cloud = std::make_unique<Cloud>(w, h);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(3)));
  const ViewFrame ahead(cloud->ahead);
  std::vector<uint8_t> occupied;
  int phase = 0;
  for (auto _ : state) {
    predicted_occupancy(cloud->cache, ahead, cloud->transforms, int(state.range(2)), phase++, int(state.range(4)), occupied);
    benchmark::DoNotOptimize(occupied.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(cloud->cache.points().size()));  // slots per second
}
// args: width, height, stride, threads, splat (FrameSettings::predict_stride, predict_splat)
BENCHMARK(BM_PredictedOccupancy)
    ->ArgsProduct({{512}, {512}, {2, 4}, {1, 2}, {3, 4}})
    ->ArgsProduct({{1920}, {1080}, {1, 2, 3}, {1, 2}, {3}})
    ->ArgsProduct({{1920}, {1080}, {4}, {1, 2}, {3, 4}})
    ->ArgsProduct({{1920}, {1080}, {8}, {1, 2}, {5}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_FillHoles(benchmark::State& state) {
  const int w = int(state.range(0)), h = int(state.range(1));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(3)));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  RgbImage image(w, h);
  for (float& v : image.pixels) v = u(rng);
  const size_t n = size_t(w) * size_t(h);
  std::vector<float> priority(n);
  // Pixels the filters' fallback left at top priority (not holes: they have a colour), as in motion.
  const float top_share = float(state.range(4)) / 100.0f;
  for (float& p : priority) p = u(rng) < top_share ? kMaxPriority : u(rng) * 8.0f;
  std::vector<uint8_t> edge_flags(n, 0), barrier;
  const size_t blobs = n * size_t(state.range(2)) / 1000 / 20;  // blobs of ~20 pixels on average
  for (size_t b = 0; b < blobs; ++b) {
    const int x0 = int(u(rng) * float(w)), y0 = int(u(rng) * float(h)), bw = 1 + int(u(rng) * 8), bh = 1 + int(u(rng) * 8);
    for (int y = y0; y < std::min(h, y0 + bh); ++y)
      for (int x = x0; x < std::min(w, x0 + bw); ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        priority[i] = kMaxPriority;  // a hole: top priority and black, as the filters leave it
        std::fill_n(image.pixels.begin() + ptrdiff_t(3 * i), 3, 0.0f);
      }
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; x += 16) edge_flags[size_t(y) * size_t(w) + size_t(x)] = kDepthEdge;
  HoleFillScratch scratch;
  RgbImage work = image;
  for (auto _ : state) {
    state.PauseTiming();
    work.pixels = image.pixels;
    state.ResumeTiming();
    list_holes(work, priority, edge_flags, kDepthEdge | kSharpEdge, barrier, scratch);
    benchmark::DoNotOptimize(scratch.holes.empty() ? 0 : fill_listed_holes(work, barrier, scratch));
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(w) * int64_t(h));  // pixels per second
}
BENCHMARK(BM_FillHoles)->ArgsProduct({{1920}, {1080}, {0, 5, 50}, {1, 2}, {0, 30}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SparseBlend(benchmark::State& state) {
  const int w = int(state.range(0)), h = int(state.range(1));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(3)));
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  EpiImage epi(w, h);
  const float density = float(state.range(2)) / 100.0f;
  for (size_t i = 0; i < epi.edge.size(); ++i)
    if (u(rng) < density) epi.edge[i] = bits::kHasSample | bits::kUsable, epi.color[i] = uint32_t(rng()) & 0xffffffu;
  std::vector<uint8_t> barrier(size_t(w) * size_t(h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) barrier[size_t(y) * size_t(w) + size_t(x)] = x % 32 == 5 || y % 32 == 9;
  RgbImage image(w, h);
  for (float& v : image.pixels) v = u(rng);
  SparseBlendScratch scratch;
  const bool kernels = state.range(4) != 0;
  auto blend = [&](RgbImage& out) {
    return kernels ? sparse_blend(out, epi, barrier, SparseBlendSettings{}, scratch)
                   : sparse_blend_reference(out, epi, barrier, SparseBlendSettings{}, scratch.sums);
  };
  RgbImage work = image, oracle = image;
  blend(work);
  sparse_blend_reference(oracle, epi, barrier, SparseBlendSettings{}, scratch.sums);
  if (work.pixels != oracle.pixels) {
    state.SkipWithError("the kernels differ from the oracle");
    return;
  }
  for (auto _ : state) {
    state.PauseTiming();
    work.pixels = image.pixels;
    state.ResumeTiming();
    benchmark::DoNotOptimize(blend(work));
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(w) * int64_t(h));  // pixels per second
  state.SetLabel(kernels ? "kernels" : "oracle");
}
BENCHMARK(BM_SparseBlend)
    ->ArgsProduct({{512}, {512}, {10}, {1, 2}, {0, 1}})
    ->ArgsProduct({{1920}, {1080}, {2, 10, 40}, {1, 2}, {0, 1}})
    ->ArgsProduct({{3840}, {2160}, {10}, {2}, {0, 1}})
    ->Apply([](benchmark::internal::Benchmark* b) {  // past two cores, where the machine has them
      for (int threads = 4; threads <= int(std::thread::hardware_concurrency()); threads *= 2)
        for (int kernels : {0, 1}) b->Args({1920, 1080, 10, threads, kernels});
    })
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace epi::render

BENCHMARK_MAIN();

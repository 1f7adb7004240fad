// The viewer's display encoding (viewer/display_encoder.h): a linear frame to RGBA8 on the frame
// thread, every frame. BM_DisplayEncode is the encoder; BM_DisplayEncodePerPixel the same output
// made a pixel at a time through io/image's tone_map (its exposure factor found for each pixel),
// the way the encoder worked until 2026-11-29: the baseline of the same run.
// Arguments: width, height, threads. Counter: Mpixel_per_s (wall).
#include <benchmark/benchmark.h>

#include <random>

#include <tbb/global_control.h>

#include "display_encoder.h"

namespace epi::viewer {
namespace {

// A frame of plausible linear colours: mostly below 1, a few highlights above the shoulder.
const RgbImage& frame(int width, int height) {
  static RgbImage image;
  if (image.width != width || image.height != height) {
    image.width = width, image.height = height;
    image.pixels.resize(size_t(width) * size_t(height) * 3);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (float& v : image.pixels) v = u(rng) < 0.05f ? 1.0f + 4.0f * u(rng) : 0.9f * u(rng) * u(rng);
  }
  return image;
}

template <bool kPerPixel>
void BM_DisplayEncode(benchmark::State& state) {
  const int w = int(state.range(0)), h = int(state.range(1));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(2)));
  const RgbImage& image = frame(w, h);
  const DisplayEncoder encoder;
  std::vector<uint32_t> rgba(size_t(w) * size_t(h));
  for (auto _ : state) {
    if constexpr (kPerPixel) {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, rgba.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          float d[3];
          tone_map(&image.pixels[3 * i], encoder.exposure(), d);
          rgba[i] = encoder.pixel(d);
        }
      });
    } else {
      encoder.encode(image, rgba.data());
    }
    benchmark::DoNotOptimize(rgba.data());
    benchmark::ClobberMemory();
  }
  state.counters["Mpixel_per_s"] = benchmark::Counter(double(rgba.size()) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (const auto& [w, h] : {std::pair{512, 512}, std::pair{1920, 1080}})
    for (int threads : {1, 2}) b->Args({w, h, threads});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK_TEMPLATE(BM_DisplayEncode, false)->Name("BM_DisplayEncode")->Apply(Sizes);
BENCHMARK_TEMPLATE(BM_DisplayEncode, true)->Name("BM_DisplayEncodePerPixel")->Apply(Sizes);

}  // namespace
}  // namespace epi::viewer

BENCHMARK_MAIN();

// The viewer's display encoding (viewer/display_encoder.h): a linear frame to RGBA8 on the frame
// thread, every frame. BM_DisplayEncode is the encoder (Highway, the best target);
// BM_DisplayEncodePerPixel the same output made a pixel at a time through io/image's tone_map
// (its exposure factor found for each pixel) and the table, the shape of the encoder until
// 2026-11-29 (with today's tone map and table index): the baseline of the same run.
// Arguments: width, height, threads. Counter: Mpixel_per_s (wall).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "display_encoder.h"
#include "image_io.h"

namespace epi::viewer {
namespace {

// A frame like a render's: smooth shading below 0.7, and a few bright discs (highlights, a lit
// emitter: about 3 % of the pixels above the tone map's knee, in clusters).
const RgbImage& frame(int width, int height) {
  static RgbImage image;
  if (image.width != width || image.height != height) {
    image.width = width, image.height = height;
    image.pixels.resize(size_t(width) * size_t(height) * 3);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        for (int c = 0; c < 3; ++c)
          image.pixels[(size_t(y) * size_t(width) + size_t(x)) * 3 + size_t(c)] =
              0.35f + 0.3f * std::sin(float(x) / (40.0f + 9.0f * float(c))) * std::cos(float(y) / 37.0f);
    std::mt19937 rng(7);
    const float radius = 0.01f * float(std::max(width, height));
    const int discs = int(0.03 * double(width) * double(height) / (3.14159 * double(radius) * double(radius)));
    for (int k = 0; k < discs; ++k) {
      const int cx = int(rng() % uint32_t(width)), cy = int(rng() % uint32_t(height));
      const float level = 1.0f + 4.0f * float(rng() % 1000) / 1000.0f;
      for (int y = std::max(0, cy - int(radius)); y <= std::min(height - 1, cy + int(radius)); ++y)
        for (int x = std::max(0, cx - int(radius)); x <= std::min(width - 1, cx + int(radius)); ++x)
          if (float((x - cx) * (x - cx) + (y - cy) * (y - cy)) <= radius * radius)
            for (int c = 0; c < 3; ++c) image.pixels[(size_t(y) * size_t(width) + size_t(x)) * 3 + size_t(c)] = level;
    }
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

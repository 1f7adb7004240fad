// The request dither (render/sampling.h) against the one it replaced (Floyd-Steinberg in
// parallel bands of 64 rows, copied below as the baseline), in one run: time, and the spread of
// the picks: mean distance to the nearest other pick over the ideal (a hexagonal lattice of the
// same density), and the fraction of 8-row strips with fewer than half their expected picks.
//   render_bench_dither --benchmark_filter=Dither   (docs/render.md, "Sampling")
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "render/sampling.h"

namespace epi::render {
namespace baseline {

uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

float unit_float(uint64_t bits) { return float(bits >> 40) * (1.0f / float(1u << 24)); }  // [0, 1)


// One band of rows: `priority` and the returned indices are the band's own (row-major, from 0).
std::vector<uint32_t> dither_band(const float* priority, bool uniform, int width, int height, size_t count) {
  const size_t pixels = size_t(width) * size_t(height);
  count = std::min(count, pixels);
  std::vector<uint32_t> picked;
  if (count == 0 || pixels == 0) return picked;
  double total = 0.0;
  for (size_t i = 0; i < pixels && !uniform; ++i) total += std::max(0.0f, priority[i]);
  uniform = uniform || !(total > 0.0);
  auto weight = [&](size_t i) { return uniform ? 1.0f : std::max(0.0f, priority[i]); };
  const double scale = double(count) / (uniform ? double(pixels) : total);

  // Floyd-Steinberg over the scaled priority, serpentine rows, two rows of error; error pushed
  // past a row's end goes to the next row's end pixel, so only the last row's error leaves the
  // band. The value at the decision is kept: it ranks pixels when the count is settled.
  std::vector<float> err_row(size_t(width) + 2), err_next(size_t(width) + 2), decision(pixels);
  std::vector<uint8_t> chosen(pixels);
  size_t chosen_count = 0;
  {
    // The first row starts with a little error (a fixed hash pattern in [0, 1/2)): without it
    // the first rows stay empty until error has accumulated.
    for (size_t x = 0; x < err_row.size(); ++x) err_row[x] = 0.5f * unit_float(splitmix64(x));
    std::fill(chosen.begin(), chosen.end(), uint8_t(0));
    chosen_count = 0;
    for (int y = 0; y < height; ++y) {
      const bool forward = (y & 1) == 0;
      const int dir = forward ? 1 : -1;
      std::fill(err_next.begin(), err_next.end(), 0.0f);
      for (int k = 0; k < width; ++k) {
        const int x = forward ? k : width - 1 - k;
        const size_t i = size_t(y) * size_t(width) + size_t(x);
        const float value = float(double(weight(i)) * scale) + err_row[size_t(x + 1)];
        decision[i] = value;
        const bool pick = value >= 0.5f && weight(i) > 0.0f;
        const float e = pick ? value - 1.0f : value;
        chosen[i] = pick, chosen_count += pick;
        err_row[size_t(x + 1 + dir)] += e * (7.0f / 16.0f);
        err_next[size_t(x + 1 - dir)] += e * (3.0f / 16.0f);
        err_next[size_t(x + 1)] += e * (5.0f / 16.0f);
        err_next[size_t(x + 1 + dir)] += e * (1.0f / 16.0f);
      }
      // Error pushed past the row's ends stays in the image: into the next row's end pixels.
      err_next[1] += err_next[0] + (forward ? 0.0f : err_row[0]);
      err_next[size_t(width)] += err_next[size_t(width) + 1] + (forward ? err_row[size_t(width) + 1] : 0.0f);
      err_next[0] = err_next[size_t(width) + 1] = 0.0f;
      std::swap(err_row, err_next);
    }
  }
  return settle_picks(uniform ? nullptr : priority, chosen, decision, count);
}

std::vector<uint32_t> dither_pixels_fs(std::span<const float> priority, int width, int height, size_t count) {
  return dither_in_bands(priority, width, height, count,
                         [](const float* p, bool uniform, int w, int rows, size_t n, uint64_t, double) {
                           return dither_band(p, uniform, w, rows, n);
                         });
}

}  // namespace baseline

namespace {

std::vector<float> smooth_priority(int w, int h, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> p(size_t(w) * size_t(h), 0.2f);
  for (int k = 0; k < 6; ++k) {
    const float cx = unit(rng) * float(w), cy = unit(rng) * float(h), r = (0.1f + 0.3f * unit(rng)) * float(w), a = 0.5f + unit(rng);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float d2 = ((float(x) - cx) * (float(x) - cx) + (float(y) - cy) * (float(y) - cy)) / (r * r);
        p[size_t(y) * size_t(w) + size_t(x)] += a * std::exp(-d2);
      }
  }
  return p;
}

// Mean distance from each pick to its nearest other pick (grid buckets), over the hexagonal
// lattice's spacing for the same density.
double nearest_ratio(const std::vector<uint32_t>& picks, int w, int h) {
  if (picks.size() < 2) return 0.0;
  const double density = double(picks.size()) / (double(w) * double(h));
  const double ideal = std::sqrt(2.0 / (std::sqrt(3.0) * density));
  const int cell = std::max(1, int(ideal));
  const int cw = (w + cell - 1) / cell, ch = (h + cell - 1) / cell;
  std::vector<std::vector<uint32_t>> grid(size_t(cw) * size_t(ch));
  for (uint32_t p : picks) grid[size_t(int(p) / w / cell) * size_t(cw) + size_t(int(p) % w / cell)].push_back(p);
  double sum = 0.0;
  for (uint32_t p : picks) {
    const int px = int(p) % w, py = int(p) / w, gx = px / cell, gy = py / cell;
    double best = std::numeric_limits<double>::infinity();
    for (int r = 1; r < std::max(cw, ch) + 1; ++r) {
      for (int y = std::max(0, gy - r); y <= std::min(ch - 1, gy + r); ++y)
        for (int x = std::max(0, gx - r); x <= std::min(cw - 1, gx + r); ++x)
          for (uint32_t q : grid[size_t(y) * size_t(cw) + size_t(x)]) {
            if (q == p) continue;
            const double dx = double(int(q) % w - px), dy = double(int(q) / w - py);
            best = std::min(best, dx * dx + dy * dy);
          }
      if (best <= double(r * cell) * double(r * cell)) break;  // nothing nearer in further rings
    }
    sum += std::sqrt(best);
  }
  return sum / double(picks.size()) / ideal;
}

double starved_strips(const std::vector<uint32_t>& picks, const std::vector<float>& priority, int w, int h) {
  const double total = std::accumulate(priority.begin(), priority.end(), 0.0);
  std::vector<double> got(size_t(h / 8), 0.0), want(size_t(h / 8), 0.0);
  for (uint32_t p : picks)
    if (int(p) / w / 8 < h / 8) got[size_t(int(p) / w / 8)] += 1.0;
  for (int y = 0; y < h / 8 * 8; ++y)
    for (int x = 0; x < w; ++x) want[size_t(y / 8)] += double(priority[size_t(y) * size_t(w) + size_t(x)]) * double(picks.size()) / total;
  size_t starved = 0;
  for (size_t s = 0; s < got.size(); ++s) starved += got[s] < 0.5 * want[s];
  return double(starved) / double(got.size());
}

// Args: which (0 new, 1 old), width, height, density in units of 0.1%, image (0 uniform, 1 smooth).
void BM_Dither(benchmark::State& state) {
  const bool old = state.range(0) == 1;
  const int w = int(state.range(1)), h = int(state.range(2));
  const double density = double(state.range(3)) * 0.001;
  const std::vector<float> priority = state.range(4) == 0 ? std::vector<float>(size_t(w) * size_t(h), 1.0f) : smooth_priority(w, h, 11);
  const size_t count = size_t(std::round(density * double(w) * double(h)));
  std::vector<uint32_t> picks;
  for (auto _ : state) {
    picks = old ? baseline::dither_pixels_fs(priority, w, h, count) : dither_pixels(priority, w, h, count);
    benchmark::DoNotOptimize(picks.data());
  }
  state.counters["nn_ratio"] = nearest_ratio(picks, w, h);
  state.counters["starved_strips"] = starved_strips(picks, priority, w, h);
  state.SetLabel(old ? "old (Floyd-Steinberg bands)" : "new (Hilbert strips)");
}

void dither_args(benchmark::internal::Benchmark* b) {
  for (auto [w, h] : {std::pair{512, 512}, std::pair{1920, 1080}})
    for (int image : {0, 1})
      for (int density : {1, 3, 5, 10, 50, 500})
        for (int which : {0, 1}) b->Args({which, w, h, density, image});
}
BENCHMARK(BM_Dither)->Apply(dither_args)->Unit(benchmark::kMillisecond)->MinTime(0.2);

}  // namespace
}  // namespace epi::render

BENCHMARK_MAIN();

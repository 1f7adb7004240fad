// core/epi filters: each stage at 512x512 and 1920x1080, oracle (one whole-image scalar loop)
// vs tiled (bands in parallel, 1 and 2 threads), in Mpixel/s, with each figure's distance from
// a plain streaming read+write of the EPI's 10 bytes per pixel ("x_floor": time / floor time).
// Also: AoS (packed 10-byte pixels) vs SoA planes, for the layout decision. docs/performance.md.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstring>
#include <map>
#include <memory>
#include <random>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "epi/antialias.h"
#include "epi/classify.h"
#include "epi/complex_filter.h"
#include "epi/fill.h"
#include "epi/interpolate.h"
#include "epi/pattern.h"
#include "epi/reachability.h"
#include "epi/reconstruct.h"
#include "epi/rendercache.h"

namespace epi {
namespace {

constexpr double kDensity = 0.5;

// A frame: one random polygon (radius 2 to 102 px) per 2600 pixels, half the pixels sampled;
// the same statistics at both sizes.
struct Frame {
  Pattern pattern;
  std::vector<Segment> edges;
  BoundaryMasks masks;
  EpiImage input;     // as sampled: the reconstruction's input
  EpiImage epi;       // classified, with reachability
  RgbImage interpolated;          // render cache colours (input of anti-aliasing and complex)
  RgbImage primary;               // EPI interpolation (input of the fill step)
  std::vector<uint8_t> found;
  std::vector<uint8_t> types;     // the pixel types (read-only plane)
  EpiRows rows() const { return whole_image_rows(epi, types.data()); }
  double floor_seconds = 0;  // streaming read+write of the 10-byte pixels, one thread
};

Pattern random_pattern(int w, int h, int count) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Pattern p;
  p.width = w, p.height = h;
  p.background = {0.2f, 0.3f, 0.4f};
  for (int i = 0; i < count; ++i) {
    Polygon poly;
    poly.color = {float(u(rng)), float(u(rng)), float(u(rng))};
    const double cx = u(rng) * w, cy = u(rng) * h, r = 2.0 + u(rng) * u(rng) * 100.0;
    const int n = 3 + int(u(rng) * 6);
    for (int k = 0; k < n; ++k) {
      const double a = 6.283185307179586 * (k + 0.8 * u(rng)) / n;
      poly.points.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
    }
    p.polygons.push_back(poly);
  }
  return p;
}

double streaming_floor(const EpiImage& epi) {
  const size_t n = epi.edge.size();
  std::vector<uint16_t> e(n);
  std::vector<uint32_t> c(n), k(n);
  double best = 1e9;
  for (int rep = 0; rep < 20; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    std::memcpy(e.data(), epi.edge.data(), n * 2);
    std::memcpy(c.data(), epi.color.data(), n * 4);
    std::memcpy(k.data(), epi.cache.data(), n * 4);
    benchmark::DoNotOptimize(e.data());
    benchmark::DoNotOptimize(c.data());
    benchmark::DoNotOptimize(k.data());
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

Frame& frame(int w, int h) {
  static std::map<int, std::unique_ptr<Frame>> frames;
  auto& f = frames[w * 100000 + h];
  if (!f) {
    f = std::make_unique<Frame>();
    f->pattern = random_pattern(w, h, w * h / 2600);
    f->edges = pattern_edges(f->pattern);
    f->masks = BoundaryMasks(w, h, true);
    rasterize_edges(f->masks, f->edges);
    f->epi = EpiImage(w, h);
    sample_pattern(f->pattern, kDensity, 7, f->epi);
    f->interpolated = reconstruct_oracle(f->epi, f->masks, {Filter::rendercache, false, false}).image;
    f->input = f->epi;
    const Reconstruction classified = reconstruct_oracle(f->epi, f->masks, {});
    f->epi.edge = classified.edge, f->epi.cache = classified.cache;  // the classified planes, for the stage benches
    f->types.resize(size_t(w) * h);
    for (size_t i = 0; i < f->types.size(); ++i) f->types[i] = uint8_t(pixel_type(f->epi.cache[i]));
    f->primary = RgbImage(w, h);
    f->found.resize(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        bool found = false;
        interpolate_pixel(f->rows(), x, y, reach_mask(f->epi.cache[f->epi.index(x, y)]), f->primary.at(x, y), &found);
        f->found[f->epi.index(x, y)] = found;
      }
    f->floor_seconds = streaming_floor(f->epi);
  }
  return *f;
}

// Runs fn(y0, y1) over bands of 32 rows: threads == 0 means one plain loop (the oracle).
template <typename Fn>
void run_rows(int threads, int h, Fn fn) {
  if (threads == 0) return fn(0, h);
  static std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  auto& arena = arenas[threads];
  if (!arena) arena = std::make_unique<tbb::task_arena>(threads);
  arena->execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, (h + 31) / 32, 1), [&](const tbb::blocked_range<int>& r) {
      for (int b = r.begin(); b != r.end(); ++b) fn(b * 32, std::min(h, b * 32 + 32));
    }, tbb::simple_partitioner());
  });
}

void report(benchmark::State& state, const Frame& f, int64_t pixels, bool label) {
  state.counters["Mpix/s"] = benchmark::Counter(double(pixels) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["floor_ms"] = f.floor_seconds * 1e3;
  if (label) state.SetLabel(state.range(2) == 0 ? "oracle" : ("tiled " + std::to_string(state.range(2)) + "T"));
}

// The time of one iteration over the floor time, set after the loop.
void ratio(benchmark::State& state, const Frame& f, double seconds) {
  state.counters["x_floor"] = seconds / double(state.iterations()) / f.floor_seconds;
}

template <typename Body>
void timed(benchmark::State& state, const Frame& f, Body body, bool label = true) {
  double seconds = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    body();
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  report(state, f, int64_t(f.epi.width) * f.epi.height, label);
  ratio(state, f, seconds);
}

void BM_Rasterize(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  BoundaryMasks masks(f.epi.width, f.epi.height, true);
  const int threads = int(state.range(2));
  timed(state, f, [&] {
    masks.clear();
    if (threads == 0) rasterize_edges(masks, f.edges);
    else rasterize_edges_parallel(masks, f.edges, 64, threads);
  });
  state.counters["edges"] = double(f.edges.size());
}

void BM_Classify(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  EpiImage epi = f.input;
  timed(state, f, [&] { run_rows(int(state.range(2)), epi.height, [&](int y0, int y1) { classify_rows(epi, f.masks, y0, y1); }); });
}

void BM_Reachability(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const int w = f.epi.width, h = f.epi.height;
  std::vector<uint32_t> out(size_t(w) * h);
  std::vector<uint8_t> types(size_t(w) * h);
  for (size_t i = 0; i < types.size(); ++i) types[i] = uint8_t(pixel_type(f.epi.cache[i]));
  const TypeRows plane{types.data(), w, h};
  const int threads = int(state.range(2));
  timed(state, f, [&] {
    run_rows(threads, h, [&](int y0, int y1) {
      std::vector<uint8_t> scratch(size_t(w) + 4);
      for (int y = y0; y < y1; ++y) {
        uint32_t* row = &out[size_t(y) * w];
        if (threads == 0) {
          for (int x = 0; x < w; ++x) row[x] = reach_full(f.epi, x, y);
        } else {  // the tiled path: empty windows skipped, symmetry from the two rows above
          const bool reuse = y >= y0 + 2;
          reach_row(plane, y, reuse ? row - w : nullptr, reuse ? row - 2 * w : nullptr, row, scratch.data());
        }
      }
    });
    benchmark::DoNotOptimize(out.data());
  });
}

void BM_Interpolate(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  RgbImage out(f.epi.width, f.epi.height);
  timed(state, f, [&] {
    run_rows(int(state.range(2)), f.epi.height, [&](int y0, int y1) {
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < f.epi.width; ++x)
          interpolate_pixel(f.rows(), x, y, reach_mask(f.epi.cache[f.epi.index(x, y)]), out.at(x, y));
    });
    benchmark::DoNotOptimize(out.pixels.data());
  });
}

void BM_Fill(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const int w = f.epi.width, h = f.epi.height;
  RgbImage out(w, h);
  timed(state, f, [&] {
    run_rows(int(state.range(2)), h, [&](int y0, int y1) {
      for (int y = y0; y < y1; ++y) {
        const float* rows[5];
        const uint8_t* found[5];
        for (int k = 0; k < 5; ++k) {
          const int ry = y - 2 + k;
          rows[k] = ry >= 0 && ry < h ? f.primary.at(0, ry) : nullptr;
          found[k] = ry >= 0 && ry < h ? &f.found[size_t(ry) * w] : nullptr;
        }
        for (int x = 0; x < w; ++x) fill_pixel(x, w, reach_mask(f.epi.cache[f.epi.index(x, y)]), rows, found, out.at(x, y));
      }
    });
    benchmark::DoNotOptimize(out.pixels.data());
  });
}

void BM_AntiAlias(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const int w = f.epi.width, h = f.epi.height;
  RgbImage out(w, h);
  timed(state, f, [&] {
    run_rows(int(state.range(2)), h, [&](int y0, int y1) {
      for (int y = y0; y < y1; ++y) {
        const float* rows[3] = {y > 0 ? f.interpolated.at(0, y - 1) : nullptr, f.interpolated.at(0, y),
                                y + 1 < h ? f.interpolated.at(0, y + 1) : nullptr};
        for (int x = 0; x < w; ++x) antialias_pixel(f.rows(), x, y, rows, out.at(x, y));
      }
    });
    benchmark::DoNotOptimize(out.pixels.data());
  });
}

void BM_Complex(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const int w = f.epi.width;
  RgbImage out(w, f.epi.height);
  int64_t complex = 0;
  for (uint32_t c : f.epi.cache) complex += pixel_type(c) == kTypeComplex;
  timed(state, f, [&] {
    run_rows(int(state.range(2)), f.epi.height, [&](int y0, int y1) {
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < w; ++x)
          if (pixel_type(f.epi.cache[f.epi.index(x, y)]) == kTypeComplex)
            complex_pixel(f.rows(), f.masks, x, y, f.interpolated.at(x, y), out.at(x, y));
    });
    benchmark::DoNotOptimize(out.pixels.data());
  });
  state.counters["complex_pixels"] = double(complex);
}

void BM_RenderCache(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  RgbImage out(f.epi.width, f.epi.height);
  timed(state, f, [&] {
    run_rows(int(state.range(2)), f.epi.height, [&](int y0, int y1) {
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < f.epi.width; ++x) rendercache_pixel(f.rows(), x, y, out.at(x, y));
    });
    benchmark::DoNotOptimize(out.pixels.data());
  });
}

// The whole reconstruction: reconstruct_oracle vs reconstruct_tiled (same result, bit for bit).
void BM_Reconstruct(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const int threads = int(state.range(2));
  Reconstruction r;
  Reconstructor reconstructor;
  timed(state, f, [&] {
    if (threads == 0) reconstructor.oracle(f.input, f.masks, {}, r);
    else reconstructor.tiled(f.input, f.masks, {}, {64, threads}, r);
    benchmark::DoNotOptimize(r.image.pixels.data());
  });
}

// The band height of the schedule, 1920x1080, 2 threads.
void BM_ReconstructBandRows(benchmark::State& state) {
  Frame& f = frame(1920, 1080);
  Reconstruction r;
  Reconstructor reconstructor;
  timed(state, f, [&] {
    reconstructor.tiled(f.input, f.masks, {}, {int(state.range(0)), 2}, r);
    benchmark::DoNotOptimize(r.image.pixels.data());
  }, false);
  state.SetLabel("rows_per_band " + std::to_string(state.range(0)));
}

void BM_StreamingFloor(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const size_t n = f.epi.edge.size();
  std::vector<uint16_t> e(n);
  std::vector<uint32_t> c(n), k(n);
  timed(state, f, [&] {
    std::memcpy(e.data(), f.epi.edge.data(), n * 2);
    std::memcpy(c.data(), f.epi.color.data(), n * 4);
    std::memcpy(k.data(), f.epi.cache.data(), n * 4);
    benchmark::DoNotOptimize(e.data());
    benchmark::DoNotOptimize(c.data());
    benchmark::DoNotOptimize(k.data());
  });
}

// Layout: a branch-free pass that reads what reachability and interpolation read over a 5x5
// window (type, usable bit, colour), over AoS packed 10-byte pixels vs the SoA planes.
void BM_LayoutAoS(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const int w = f.epi.width, h = f.epi.height;
  std::vector<EpiPixel> aos(size_t(w) * h);
  for (size_t i = 0; i < aos.size(); ++i) aos[i] = {f.epi.edge[i], f.epi.color[i], f.epi.cache[i]};
  std::vector<uint32_t> out(size_t(w) * h);
  timed(state, f, [&] {
    for (int y = 2; y < h - 2; ++y)
      for (int x = 2; x < w - 2; ++x) {
        uint32_t sum = 0;
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const EpiPixel& p = aos[size_t(y + dy) * w + x + dx];
            sum += (p.color & 0xff) * uint32_t(p.edge >> 15) + (p.cache >> 24);
          }
        out[size_t(y) * w + x] = sum;
      }
    benchmark::DoNotOptimize(out.data());
  });
}

void BM_LayoutSoA(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const int w = f.epi.width, h = f.epi.height;
  std::vector<uint32_t> out(size_t(w) * h);
  timed(state, f, [&] {
    for (int y = 2; y < h - 2; ++y)
      for (int x = 2; x < w - 2; ++x) {
        uint32_t sum = 0;
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const size_t i = size_t(y + dy) * w + x + dx;
            sum += (f.epi.color[i] & 0xff) * uint32_t(f.epi.edge[i] >> 15) + (f.epi.cache[i] >> 24);
          }
        out[size_t(y) * w + x] = sum;
      }
    benchmark::DoNotOptimize(out.data());
  });
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (auto [w, h] : {std::pair{512, 512}, {1920, 1080}})
    for (int threads : {0, 1, 2}) b->Args({w, h, threads});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
void SizesSerial(benchmark::internal::Benchmark* b) {
  for (auto [w, h] : {std::pair{512, 512}, {1920, 1080}}) b->Args({w, h, 0});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_StreamingFloor)->Apply(SizesSerial);
BENCHMARK(BM_Rasterize)->Apply(Sizes);
BENCHMARK(BM_Classify)->Apply(Sizes);
BENCHMARK(BM_Reachability)->Apply(Sizes);
BENCHMARK(BM_Interpolate)->Apply(Sizes);
BENCHMARK(BM_Fill)->Apply(Sizes);
BENCHMARK(BM_AntiAlias)->Apply(Sizes);
BENCHMARK(BM_Complex)->Apply(Sizes);
BENCHMARK(BM_RenderCache)->Apply(Sizes);
BENCHMARK(BM_Reconstruct)->Apply(Sizes);
BENCHMARK(BM_ReconstructBandRows)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LayoutAoS)->Apply(SizesSerial);
BENCHMARK(BM_LayoutSoA)->Apply(SizesSerial);

}  // namespace
}  // namespace epi

BENCHMARK_MAIN();

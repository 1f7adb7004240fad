// core/epi filters, the per-filter micro-benchmarks: each stage of the stage table (stages.h)
// timed by the staged schedule with the per-pixel oracle functions, and with the Highway row
// kernels of each compiled target (the scalar target is the scalar row kernel), on 1 and 2
// threads, at 512x512, 1920x1080 and 3840x2160, on frames with few and many edges; the outputs
// are checked equal to the oracle, bit for bit, before timing. Counters: Mpixel/s, ns/pixel and
// x_floor (time / the time of a plain streaming read+write of the EPI's 10 bytes per pixel).
// Also the whole reconstruction (oracle vs tiled row stream), the band height, rasterization
// and the AoS/SoA layout decision. bench/perf_tables.py turns the JSON into docs/performance.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

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
#include "epi/stages.h"
#include "simd/row_kernels.h"

namespace epi {
namespace {

constexpr double kDensity = 0.5;

// A frame: random polygons (radius 2 to 102 px) with half the pixels sampled, the same
// statistics at every size: "few" edges, one polygon per 2600 pixels (the figures before the
// SIMD kernels), "many", one per 650 pixels.
struct Frame {
  Pattern pattern;
  std::vector<Segment> edges;
  BoundaryMasks masks;
  EpiImage epi;       // as sampled: the reconstruction's input
  Reconstruction oracle;  // reconstruct_oracle's result, the reference every kernel must equal
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

Frame& frame(int w, int h, int edges = 0) {
  static std::map<std::tuple<int, int, int>, std::unique_ptr<Frame>> frames;
  auto& f = frames[{w, h, edges}];
  if (!f) {
    f = std::make_unique<Frame>();
    f->pattern = random_pattern(w, h, w * h / (edges == 0 ? 2600 : 650));
    f->edges = pattern_edges(f->pattern);
    f->masks = BoundaryMasks(w, h, true);
    rasterize_edges(f->masks, f->edges);
    f->epi = EpiImage(w, h);
    sample_pattern(f->pattern, kDensity, 7, f->epi);
    f->oracle = reconstruct_oracle(f->epi, f->masks, {});
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

// Kernel argument k: 0 the per-pixel oracle functions, k >= 1 the k-th compiled Highway target.
KernelChoice kernel_choice(int64_t k) {
  if (k == 0) return {true, 0};
  return {false, simd::compiled_targets()[size_t(k - 1)]};
}

bool same_result(const Reconstruction& a, const Reconstruction& b) {
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  return same(a.image.pixels, b.image.pixels) && same(a.priority, b.priority) && same(a.edge, b.edge) &&
         same(a.cache, b.cache);
}

// Each filter (stage) of the staged schedule with one kernel choice: args width, height,
// kernel (kernel_choice), threads, edges (0 few, 1 many). The iteration time is the sum of the
// stages; every stage's time is a counter.
void BM_Filters(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)), int(state.range(4)));
  const int threads = int(state.range(3));
  Reconstructor reconstructor(kernel_choice(state.range(2)));
  Reconstruction r;
  ReconstructTimes times;
  reconstructor.staged(f.epi, f.masks, {}, r, times, {64, threads});
  if (!same_result(r, f.oracle)) return state.SkipWithError("the result differs from the oracle");
  std::array<double, kStageCount> sum{}, cpu{};
  for (auto _ : state) {
    reconstructor.staged(f.epi, f.masks, {}, r, times, {64, threads});
    double total = 0;
    for (int k = 0; k < kStageCount; ++k) {
      sum[size_t(k)] += times.ms[size_t(k)], cpu[size_t(k)] += times.cpu_ms[size_t(k)];
      total += times.ms[size_t(k)];
    }
    state.SetIterationTime(total * 1e-3);
  }
  const double pixels = double(f.epi.width) * f.epi.height, n = double(state.iterations());
  for (const StageInfo& stage : kStages) {
    const double ms = sum[size_t(stage.stage)] / n;
    const std::string name = stage.name;
    state.counters[name + "_ms"] = ms;
    state.counters[name + "_ns_px"] = ms * 1e6 / pixels;
    state.counters[name + "_Mpix/s"] = ms > 0 ? pixels * 1e-3 / ms : 0.0;
    state.counters[name + "_x_floor"] = ms * 1e-3 / f.floor_seconds;
    state.counters[name + "_cpu_ms"] = cpu[size_t(stage.stage)] / n;  // the calling thread's: all of it at 1 thread
  }
  state.counters["floor_ms"] = f.floor_seconds * 1e3;
  state.counters["Mpix/s"] = benchmark::Counter(pixels * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(std::string(reconstructor.kernel_name()) + (state.range(4) ? " many" : " few") + " " +
                 std::to_string(threads) + "T");
}

// The render cache's filter (Filter::rendercache: the 3x3 comparison filter with its 7x7
// prefilter, timed as the interpolation stage; decoding is the vector kernels' extra stage):
// args width, height, kernel (0 oracle, else a target), one thread, few edges. Equal to the
// render cache oracle, bit for bit, checked before timing.
void BM_RenderCacheFilter(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  const ReconstructSettings settings{Filter::rendercache};
  static std::map<std::pair<int, int>, Reconstruction> oracles;
  Reconstruction& oracle = oracles[{f.epi.width, f.epi.height}];
  if (oracle.priority.empty()) oracle = reconstruct_oracle(f.epi, f.masks, settings);
  Reconstructor reconstructor(kernel_choice(state.range(2)));
  Reconstruction r;
  ReconstructTimes times;
  reconstructor.staged(f.epi, f.masks, settings, r, times, {64, 1});
  if (!same_result(r, oracle)) return state.SkipWithError("the result differs from the oracle");
  double filter = 0, decode = 0;
  for (auto _ : state) {
    reconstructor.staged(f.epi, f.masks, settings, r, times, {64, 1});
    filter += times.cpu_ms[size_t(Stage::interpolate)], decode += times.cpu_ms[size_t(Stage::decode)];
    state.SetIterationTime((times[Stage::interpolate] + times[Stage::decode]) * 1e-3);
  }
  const double n = double(state.iterations());
  state.counters["filter_cpu_ms"] = filter / n;
  state.counters["decode_cpu_ms"] = decode / n;
  state.counters["x_floor"] = (filter + decode) / n * 1e-3 / f.floor_seconds;
  state.SetLabel(reconstructor.kernel_name());
}

// The whole reconstruction: args width, height, kernel, threads, edges. Kernel 0 is the
// oracle schedule (one thread, whole-image stages); the others the tiled row stream (bands of
// 64 rows). Equal to the oracle, bit for bit, checked before timing.
void BM_Reconstruct(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)), int(state.range(4)));
  const int threads = int(state.range(3));
  const bool oracle = state.range(2) == 0;
  Reconstructor reconstructor(kernel_choice(state.range(2)));
  Reconstruction r;
  auto run = [&] {
    if (oracle) reconstructor.oracle(f.epi, f.masks, {}, r);
    else reconstructor.tiled(f.epi, f.masks, {}, {64, threads}, r);
  };
  run();
  if (!same_result(r, f.oracle)) return state.SkipWithError("the result differs from the oracle");
  timed(state, f, [&] {
    run();
    benchmark::DoNotOptimize(r.image.pixels.data());
  }, false);
  state.counters["ns_px"] = state.counters["x_floor"].value * f.floor_seconds * 1e9 / (double(f.epi.width) * f.epi.height);
  state.SetLabel(oracle ? std::string("oracle") + (state.range(4) ? " many" : " few")
                        : std::string("tiled ") + reconstructor.kernel_name() + (state.range(4) ? " many " : " few ") +
                              std::to_string(threads) + "T");
}

// What the row fallback saves (Schedule::row_fallback): the tiled stream, best target, one
// thread, after fast motion: only `per mille` of the pixels sampled, so many pixels reach no
// sample in their 5x5 and take the fallback. args: width, height, sampled per mille, polygons
// per megapixel (385 is BM_Filters' "few"; the bundled scenes at 1080p show 20-7000 edges),
// row fallback (0 pixel by pixel, 1 by rows). Counter fallback_pct: the pixels that took it.
void BM_Fallback(benchmark::State& state) {
  const int w = int(state.range(0)), h = int(state.range(1));
  static std::map<std::tuple<int, int, int>, std::unique_ptr<Frame>> frames;
  auto& f = frames[{w, h, int(state.range(2) * 100000 + state.range(3))}];
  if (!f) {
    f = std::make_unique<Frame>();
    f->pattern = random_pattern(w, h, int(int64_t(w) * h * state.range(3) / 1000000));
    f->edges = pattern_edges(f->pattern);
    f->masks = BoundaryMasks(w, h, true);
    rasterize_edges(f->masks, f->edges);
    f->epi = EpiImage(w, h);
    sample_pattern(f->pattern, double(state.range(2)) / 1000.0, 7, f->epi);
    f->oracle = reconstruct_oracle(f->epi, f->masks, {});
  }
  Reconstructor reconstructor;
  Schedule schedule;
  schedule.threads = 1, schedule.row_fallback = state.range(4) != 0;
  Reconstruction r;
  reconstructor.tiled(f->epi, f->masks, {}, schedule, r);
  if (!same_result(r, f->oracle)) return state.SkipWithError("the result differs from the oracle");
  for (auto _ : state) {
    reconstructor.tiled(f->epi, f->masks, {}, schedule, r);
    benchmark::DoNotOptimize(r.image.pixels.data());
  }
  const auto unreached = std::count(r.priority.begin(), r.priority.end(), kMaxPriority);
  state.counters["fallback_pct"] = 100.0 * double(unreached) / double(r.priority.size());
  std::string label = reconstructor.kernel_name();
  label += state.range(4) ? " by rows" : " per pixel";
  state.SetLabel(label);
}

// What reachability reused across rows saves: the reachability stage of the staged schedule
// (chunks of 8 rows) with the best target, one thread, few edges; arg 2: 0 nothing reused (the
// five relation rows of the window computed for every row, all 24 offsets), 1 the relation
// rows computed once per row and kept for the five rows that read them, 2 as 1 and the
// offsets towards the two rows above from those rows' masks (symmetry: 6 of 8 rows).
void BM_ReachReuse(benchmark::State& state) {
  Frame& f = frame(int(state.range(0)), int(state.range(1)));
  Reconstructor reconstructor;
  Reconstruction r;
  ReconstructTimes times;
  const int reuse = int(state.range(2));
  const Schedule schedule{64, 1, reuse >= 2, reuse >= 1};
  double wall = 0, cpu = 0;
  for (auto _ : state) {
    reconstructor.staged(f.epi, f.masks, {}, r, times, schedule);
    wall += times[Stage::reachability], cpu += times.cpu_ms[size_t(Stage::reachability)];
    state.SetIterationTime(times[Stage::reachability] * 1e-3);
  }
  if (!same_result(r, f.oracle)) return state.SkipWithError("the result differs from the oracle");
  state.counters["reachability_ms"] = wall / double(state.iterations());
  state.counters["reachability_cpu_ms"] = cpu / double(state.iterations());
  state.SetLabel(std::string(reconstructor.kernel_name()) +
                 (reuse == 0 ? " nothing reused" : reuse == 1 ? " relation rows" : " relation rows + symmetry"));
}

// The band height of the schedule, 1920x1080, 2 threads.
void BM_ReconstructBandRows(benchmark::State& state) {
  Frame& f = frame(1920, 1080);
  Reconstruction r;
  Reconstructor reconstructor;
  timed(state, f, [&] {
    reconstructor.tiled(f.epi, f.masks, {}, {int(state.range(0)), 2}, r);
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

// Thread counts of the two-and-more-thread rows: 1 and 2 unless --threads=LIST (main).
std::vector<int> g_threads = {1, 2};

void Sizes(benchmark::internal::Benchmark* b) {
  for (auto [w, h] : {std::pair{512, 512}, {1920, 1080}}) {
    b->Args({w, h, 0});
    for (int threads : g_threads) b->Args({w, h, threads});
  }
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
void SizesSerial(benchmark::internal::Benchmark* b) {
  for (auto [w, h] : {std::pair{512, 512}, {1920, 1080}}) b->Args({w, h, 0});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
constexpr std::pair<int, int> kFilterSizes[] = {{512, 512}, {1920, 1080}, {3840, 2160}};
void FilterArgs(benchmark::internal::Benchmark* b) {
  const int kernels = 1 + int(simd::compiled_targets().size());
  for (auto [w, h] : kFilterSizes)
    for (int edges : {0, 1})
      for (int k = 0; k < kernels; ++k)
        for (int threads : g_threads) b->Args({w, h, k, threads, edges});
  b->Unit(benchmark::kMillisecond)->UseManualTime();
}
// The oracle schedule, and the tiled stream with the best and the scalar target, on 1 and 2
// threads (--threads); the best target also on 4, 8, 16... up to the machine's cores
// (docs/performance.md, "Scaling past two cores").
void ReconstructArgs(benchmark::internal::Benchmark* b) {
  const int scalar = int(simd::compiled_targets().size());
  const int cores = int(std::thread::hardware_concurrency());
  for (auto [w, h] : kFilterSizes)
    for (int edges : {0, 1}) {
      b->Args({w, h, 0, 1, edges});
      for (int k : {1, scalar})
        for (int threads : g_threads) b->Args({w, h, k, threads, edges});
      for (int threads = 4; threads <= cores; threads *= 2)
        if (std::find(g_threads.begin(), g_threads.end(), threads) == g_threads.end()) b->Args({w, h, 1, threads, edges});
    }
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
void SizesAll(benchmark::internal::Benchmark* b) {
  for (auto [w, h] : kFilterSizes) b->Args({w, h, 0});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

void register_benchmarks() {
  benchmark::RegisterBenchmark("BM_StreamingFloor", BM_StreamingFloor)->Apply(SizesAll);
  benchmark::RegisterBenchmark("BM_Rasterize", BM_Rasterize)->Apply(Sizes);
  benchmark::RegisterBenchmark("BM_Filters", BM_Filters)->Apply(FilterArgs);
  benchmark::RegisterBenchmark("BM_Reconstruct", BM_Reconstruct)->Apply(ReconstructArgs);
  benchmark::RegisterBenchmark("BM_RenderCacheFilter", BM_RenderCacheFilter)->Apply([](benchmark::internal::Benchmark* b) {
    for (auto [w, h] : kFilterSizes)
      for (int k = 0; k <= int(simd::compiled_targets().size()); ++k) b->Args({w, h, k});
    b->Unit(benchmark::kMillisecond)->UseManualTime();
  });
  benchmark::RegisterBenchmark("BM_Fallback", BM_Fallback)
      ->ArgsProduct({{1920}, {1080}, {10, 30, 100}, {40, 385}, {0, 1}})
      ->Unit(benchmark::kMillisecond);
  auto* reuse = benchmark::RegisterBenchmark("BM_ReachReuse", BM_ReachReuse);
  for (auto [w, h] : {std::pair{1920, 1080}, {3840, 2160}})
    for (int level : {0, 1, 2}) reuse->Args({w, h, level});
  reuse->Unit(benchmark::kMillisecond)->UseManualTime();
  auto* band_rows = benchmark::RegisterBenchmark("BM_ReconstructBandRows", BM_ReconstructBandRows);
  for (int rows : {4, 8, 16, 32, 64, 128}) band_rows->Arg(rows);
  band_rows->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RegisterBenchmark("BM_LayoutAoS", BM_LayoutAoS)->Apply(SizesSerial);
  benchmark::RegisterBenchmark("BM_LayoutSoA", BM_LayoutSoA)->Apply(SizesSerial);
}

}  // namespace
}  // namespace epi

// Google Benchmark's flags, plus --threads=LIST (comma-separated thread counts of the
// parallel rows, default 1,2: e.g. --threads=1,2,4,8,16 on a larger machine).
int main(int argc, char** argv) {
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--threads=", 0) != 0) {
      args.push_back(argv[i]);
      continue;
    }
    epi::g_threads.clear();
    std::stringstream list(arg.substr(10));
    for (std::string item; std::getline(list, item, ',');) {
      char* end = nullptr;
      const long n = std::strtol(item.c_str(), &end, 10);
      if (item.empty() || *end != '\0' || n < 1 || n > 1024) {
        std::fprintf(stderr, "epi_bench: --threads wants positive thread counts separated by commas, got '%s'\n",
                     arg.c_str());
        return 2;
      }
      epi::g_threads.push_back(int(n));
    }
  }
  int count = int(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  epi::register_benchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

// `epi reconstruct`: the 2D harness of core/epi. A PATTERN.json of polygons is sampled at
// density D, its polygon edges rasterized, and the image reconstructed by the EPI filters or
// the render cache's interpolation (docs/epi.md).
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <tbb/info.h>

#include "commands.h"
#include "epi/pattern.h"
#include "epi/reconstruct.h"
#include "image_io.h"
#include "output.h"

namespace epi::cli {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double mean_abs_error(const RgbImage& a, const RgbImage& b, const std::vector<uint8_t>* select) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < size_t(a.width) * size_t(a.height); ++i) {
    if (select && !(*select)[i]) continue;
    for (int c = 0; c < 3; ++c) sum += std::abs(double(a.pixels[i * 3 + c]) - double(b.pixels[i * 3 + c]));
    ++n;
  }
  return n ? sum / double(3 * n) : 0.0;
}

}  // namespace

int run_reconstruct(const ReconstructOptions& options) {
  if (!(options.density >= 0.0 && options.density <= 1.0))
    throw std::invalid_argument("--density must be in [0, 1], got " + std::to_string(options.density));
  Filter filter;
  if (options.filter == "epi") filter = Filter::epi;
  else if (options.filter == "rendercache") filter = Filter::rendercache;
  else throw std::invalid_argument("--filter must be epi or rendercache, got '" + options.filter + "'");
  if (options.output.empty()) throw std::invalid_argument("missing output file (-o)");
  check_output_image(options.output);
  if (!options.stats.empty()) check_output_file(options.stats);
  check_distinct_outputs({options.output, options.stats});
  if (options.threads < 0) throw std::invalid_argument("--threads must be >= 0");

  const auto start = Clock::now();
  const Pattern pattern = load_pattern(options.pattern);
  // Masks, the edge-and-point image, samples, the result and (--stats) the exact image: ~30 bytes a
  // pixel measured (peak RSS of a 4096x4096 pattern less 1024x1024), ~44 with --stats.
  constexpr double kBytesPerPixel = 48.0;
  check_memory_estimate(options.pattern,
                        "a " + std::to_string(pattern.width) + "x" + std::to_string(pattern.height) + " pattern",
                        kBytesPerPixel * pattern.width * pattern.height, options.memory_limit);
  const bool complex_filter = filter == Filter::epi && options.complex_filter;

  auto stage = Clock::now();
  BoundaryMasks masks(pattern.width, pattern.height, complex_filter);
  const std::vector<Segment> edges = pattern_edges(pattern);
  rasterize_edges_parallel(masks, edges, 64, options.threads);
  const double rasterize_ms = ms_since(stage);

  stage = Clock::now();
  EpiImage epi(pattern.width, pattern.height);
  const int64_t samples = sample_pattern(pattern, options.density, options.seed, epi);
  const double sample_ms = ms_since(stage);

  stage = Clock::now();
  ReconstructSettings settings{filter, options.antialias, complex_filter};
  Schedule schedule;
  schedule.threads = options.threads;
  const Reconstruction result = reconstruct_tiled(epi, masks, settings, schedule);
  const double reconstruct_ms = ms_since(stage);

  stage = Clock::now();
  StagedOutputs outputs;
  outputs.add_image(options.output, result.image);
  const double write_ms = ms_since(stage);

  if (!options.stats.empty()) {
    const RgbImage exact = exact_image(pattern);
    const std::vector<uint8_t> edge_mask = edge_pixels(pattern);
    nlohmann::json stats = {
        {"pattern", options.pattern},
        {"width", pattern.width},
        {"height", pattern.height},
        {"density", options.density},
        {"filter", options.filter},
        {"seed", options.seed},
        {"antialias", options.antialias},
        {"complex_filter", complex_filter},
        {"threads", options.threads > 0 ? options.threads : tbb::info::default_concurrency()},
        {"edges", edges.size()},
        {"samples", samples},
        {"ambiguous_samples", result.counts.ambiguous},
        {"pixels", {{"empty", result.counts.empty}, {"simple", result.counts.simple}, {"complex", result.counts.complex}}},
        {"ms", {{"rasterize", rasterize_ms}, {"sample", sample_ms}, {"reconstruct", reconstruct_ms}, {"write", write_ms}}},
        {"mean_abs_error", {{"all_pixels", mean_abs_error(result.image, exact, nullptr)},
                            {"edge_pixels", mean_abs_error(result.image, exact, &edge_mask)}}},
    };
    outputs.add_json(options.stats, stats);
  }
  outputs.commit();
  if (!options.quiet)
    std::printf("%dx%d, %zu edges, %lld samples, %lld simple / %lld complex pixels: reconstructed (%s) in %.1f ms, total %.1f ms -> %s\n",
                pattern.width, pattern.height, edges.size(), (long long)samples, (long long)result.counts.simple,
                (long long)result.counts.complex, options.filter.c_str(), reconstruct_ms, ms_since(start),
                options.output.c_str());
  return 0;
}

}  // namespace epi::cli

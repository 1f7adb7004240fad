// Reconstruction of an image from the EPI: the stage table (stages.h) run by three schedules
// that agree bit for bit: the plain whole-image oracle, the timed stage-by-stage path and the
// tiled TBB-parallel row stream.
//
//   stage            file                footprint (pixels)          reads                  writes
//   classification   classify.cpp        1x1                         masks, sample          edge code, usable, type
//   reachability     reachability.cpp    5x5                         types                  24-bit reach mask
//   interpolation    interpolate.cpp     5x5 (7x7 fallback)          reach, samples         primary colour, found, priority
//   fill             fill.cpp            5x5                         reach, primary, found  primary colour where none found
//   render cache     rendercache.cpp     3x3 (7x7 prefilter)         samples                colour, priority (replaces interpolation)
//   anti-aliasing    antialias.cpp       3x3                         primary colours        output colour
//   complex pixels   complex_filter.cpp  3x3 (6x6 sub-pixels)        masks, samples, own    output colour
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "epi/classify.h"
#include "epi/epi_pixel.h"
#include "epi/rasterize.h"
#include "epi/stages.h"
#include "image/image.h"

namespace epi {

enum class Filter { epi, rendercache };

struct ReconstructSettings {
  Filter filter = Filter::epi;
  bool antialias = true;       // epi only
  bool complex_filter = true;  // epi only; needs masks with centre lines
  bool fill = true;            // epi only; the fill step (fill.h); off: "EPI without fill"
  // epi only: which pixels that reach no sample take the fallback's last resort (interpolate.h,
  // fallback_color), a blend of the samples across an edge: on, every pixel whose 5x5 holds an
  // edge; off, only the pixels an edge crosses (their output is a blend of both sides anyway).
  // Off, an edge-free pixel beside an edge stays black at top priority: a hole for a caller that
  // fills holes within their own region (the renderer's hole fill, core/render/hole_fill.h).
  bool blend_unreached_near_edges = true;
};

// What makes a pixel's output colour from its filled primary colour (the last two stages):
// the complex-pixel filter (complex pixels, when on and the masks hold centre lines),
// anti-aliasing (simple pixels, when on), or nothing (the filled colour itself). The render
// cache filter has neither. The schedules and the visualizer's trace (trace.h) both ask here.
enum class OutputFilter { filled, antialiased, complex_filter };
constexpr OutputFilter output_filter(const ReconstructSettings& s, bool centre_lines, int type) {
  if (s.filter != Filter::epi) return OutputFilter::filled;
  if (type == kTypeComplex && s.complex_filter && centre_lines) return OutputFilter::complex_filter;
  return s.antialias && type_is_simple(type) ? OutputFilter::antialiased : OutputFilter::filled;
}

// How the tiled reconstructor splits the work (measured defaults: docs/performance.md).
struct Schedule {
  int rows_per_band = 64;  // rows per parallel task (BM_ReconstructBandRows)
  int threads = 0;         // 0: all cores
  // Reachability takes the 10 offsets towards the two rows above from those rows' masks
  // (symmetry) wherever the schedule has them (docs/epi.md); false: all 24 computed (the bench's
  // measure of what the reuse saves).
  bool reach_symmetry = true;
  // The reachability kernel's neighbour relations computed once per row and kept for the five
  // rows that read them (docs/epi.md); false: the window's five rows recomputed for every row
  // (the bench's measure of what that saves).
  bool reuse_relations = true;
  // Pixels that reach no sample take the fallback row by row (fallback_row: column ORs, the
  // edge-free windows without a branch per sample); false: fallback_color pixel by pixel (the
  // bench's measure of what that saves). The same bits either way.
  bool row_fallback = true;
};

struct Reconstruction {
  RgbImage image;               // linear RGB
  std::vector<float> priority;  // sampling priority, one per pixel (interpolate.h)
  // The classified EPI (the input is never written): edge words with their codes and usable
  // bits (sample bits as in the input), and cache words with the type and reach mask (epi_pixel.h).
  std::vector<uint16_t> edge;
  std::vector<uint32_t> cache;
  ClassCounts counts;
};

// Wall time of each stage of Reconstructor::staged, ms; cpu_ms: the calling thread's CPU time
// in each stage (all of the stage's work when it runs on one thread; robust on a loaded machine).
struct ReconstructTimes {
  std::array<double, kStageCount> ms{};
  std::array<double, kStageCount> cpu_ms{};
  double& operator[](Stage s) { return ms[size_t(s)]; }
  double operator[](Stage s) const { return ms[size_t(s)]; }
  // The time of a reported series (stages.h, reported_as): its stages summed.
  double reported(Stage series) const {
    double t = 0;
    for (const StageInfo& i : kStages)
      if (reported_as(i.stage) == series) t += ms[size_t(i.stage)];
    return t;
  }
};

namespace simd {
struct RowKernels;
struct RelationTables;
}  // namespace simd

// The neighbour relation tables of the reachability kernels (simd::RelationRow), built once from
// the side descriptors (tables.h).
const simd::RelationTables& relation_tables();

// Which row kernels the fast schedules (tiled, staged) run: the per-pixel oracle functions,
// or the Highway kernels (simd/) of one target: 0 the best this CPU runs, else a single
// HWY_* target bit (it must be compiled and supported: simd::compiled_targets()).
struct KernelChoice {
  bool oracle = false;
  int64_t target = 0;
};

// Owns the scratch of all three schedules (whole-image planes, one set of rings per thread,
// the thread arena), allocated on first use and reused while the size stays; the kernels are
// chosen once, at construction. One call at a time.
class Reconstructor {
 public:
  explicit Reconstructor(KernelChoice kernels = {});
  ~Reconstructor();
  Reconstructor(const Reconstructor&) = delete;
  Reconstructor& operator=(const Reconstructor&) = delete;

  // The plain oracle: each stage over the whole image in turn, one thread, the per-pixel
  // functions of each stage (whatever the kernel choice).
  void oracle(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings,
              Reconstruction& out);
  // Each stage over the whole image in turn, rows in parallel (chunks of 8 rows), each stage
  // timed; schedule.rows_per_band is not used.
  void staged(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings,
              Reconstruction& out, ReconstructTimes& times, const Schedule& schedule = {});
  // Bands of rows in parallel, rows streamed through all stages (docs/epi.md, "Schedule").
  void tiled(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings,
             const Schedule& schedule, Reconstruction& out);

  const char* kernel_name() const;  // "oracle" or the Highway target's name

 private:
  struct Scratch;
  const simd::RowKernels* kernels_;  // nullptr: the per-pixel oracle functions
  std::unique_ptr<Scratch> scratch_;
};

// One-off conveniences (a Reconstructor per call: its scratch is allocated each time).
Reconstruction reconstruct_oracle(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings);
Reconstruction reconstruct_tiled(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings,
                                 const Schedule& schedule = {});
void reconstruct_tiled(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings,
                       const Schedule& schedule, Reconstruction& out);

}  // namespace epi

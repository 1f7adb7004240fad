// Reconstruction of an image from the EPI: the stages, the plain whole-image oracle and the
// tiled TBB-parallel version that must match it bit for bit.
//
//   stage            file                footprint (pixels)          reads                  writes
//   classification   classify.cpp        1x1                         masks, sample          edge code, usable, type
//   reachability     reachability.cpp    5x5                         types                  24-bit reach mask
//   interpolation    interpolate.cpp     5x5 (7x7 fallback)          reach, samples         primary colour, found, priority
//   fill             fill.cpp            5x5                         reach, primary, found  primary colour where none found
//   render cache     rendercache.cpp     3x3 (7x7 prefilter)         samples                colour, priority
//   anti-aliasing    antialias.cpp       3x3                         primary colours        output colour
//   complex pixels   complex_filter.cpp  3x3 (6x6 sub-pixels)        masks, samples, own    output colour
#pragma once

#include <vector>

#include "epi/classify.h"
#include "epi/epi_pixel.h"
#include "epi/rasterize.h"
#include "image/image.h"

namespace epi {

enum class Filter { epi, rendercache };

struct ReconstructSettings {
  Filter filter = Filter::epi;
  bool antialias = true;       // epi only
  bool complex_filter = true;  // epi only; needs masks with centre lines
  bool fill = true;            // epi only; the fill step (fill.h); off: "EPI without fill"
};

// How the tiled reconstructor splits the work (measured defaults: docs/performance.md).
struct Schedule {
  int rows_per_band = 64;  // rows per parallel task (BM_ReconstructBandRows)
  int threads = 0;         // 0: all cores
};

struct Reconstruction {
  RgbImage image;               // linear RGB
  std::vector<float> priority;  // sampling priority, one per pixel (interpolate.h)
  ClassCounts counts;
};

// Both classify `epi` in place (edge codes, usable bits, types, reachability masks).
Reconstruction reconstruct_oracle(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings);
Reconstruction reconstruct_tiled(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings,
                                 const Schedule& schedule = {});
// The same into `out`, whose buffers are reused when they have the right size (no per-frame
// allocation and clearing of 16 bytes per pixel).
void reconstruct_tiled(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings,
                       const Schedule& schedule, Reconstruction& out);

}  // namespace epi

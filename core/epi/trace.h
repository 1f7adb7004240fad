// What each reconstruction stage did at one pixel, for the teaching visualizer (docs/visualizer.md).
// A Tracer classifies the EPI once; trace(x, y) then re-runs the per-pixel functions that
// reconstruct_oracle runs (classify_pixel, reach_full, interpolate_pixel, fill_pixel,
// antialias_pixel, complex_pixel) over the pixel's neighbourhood, using the recording forms
// (reach_full_traced, complex_pixel_traced) where the visualizer shows a stage's inside. The fast
// path is untouched: the recording forms are separate template instances.
// tests/visualizer checks that every traced result equals the reconstruction's, pixel by pixel.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "epi/classify.h"
#include "epi/complex_filter.h"
#include "epi/epi_pixel.h"
#include "epi/rasterize.h"
#include "epi/reachability.h"
#include "epi/reconstruct.h"

namespace epi {

using Rgb = std::array<float, 3>;

struct PixelTrace {
  int x = 0, y = 0;

  // Classification (1x1).
  uint8_t sides[4] = {};  // boundary masks: top, right, bottom, left (bit m: piece m along +x / +y)
  CellKind kind = CellKind::empty;
  int code = 0;           // 10-bit edge code (0 empty, 1 complex)
  int p_low = 0, p_high = 0;  // simple: boundary positions 0..31 of the edge's ends
  bool has_sample = false, usable = false;
  int sample_region = 0;  // rx + 4 ry on the 4x4 interior grid
  int sample_side = -1;   // simple with a sample: 0 A, 1 B, 2 edge-ambiguous; -1 otherwise
  bool primary_is_b = false;
  float area_a = 1;       // simple: area of region A
  int type = 0;           // 4-bit pixel type

  // Reachability (5x5). types[k], k = (dy + 2) * 5 + dx + 2: kTypeComplex outside the image.
  uint8_t types[25] = {};
  bool inside[25] = {};
  bool reach_fast_path = false;  // the 5x5 holds only empty pixels: everything is reachable
  std::vector<ReachStep> reach_steps;
  uint32_t reach = 0;            // 24-bit primary-to-primary mask (reachability.h, reach_bit)

  // Interpolation (5x5; 7x7 fallback) and priority.
  struct Contribution {
    int dx, dy;
    float weight;  // kernel weight
    Rgb rgb;       // the sample's colour (linear)
  };
  bool complex_estimate = false;  // complex pixel: every sample of the 5x5 (the simple estimate)
  std::vector<Contribution> contributions;  // samples that count (weight > 0), in window order
  float total_weight = 0;
  bool found = false;             // the colour came from reachable samples
  bool fallback = false;          // reached no sample: fallback_color ran
  uint64_t reach7 = 0;            // fallback: 7x7 reachability (window7_bit)
  std::vector<Contribution> fallback_contributions;  // fallback: reachable usable samples of the 7x7
  Rgb interpolated{};             // interpolate_pixel's colour (the fallback's when it ran)
  float priority = 0;
  int age = 0;

  // Fill (5x5 of interpolated colours).
  bool fill_ran = false;  // reached no sample and fill is on
  std::vector<Contribution> fill_contributions;  // reachable neighbours that found samples (their colours)
  Rgb filled{};

  // Output: anti-aliasing (simple), complex filter (complex), or the filled colour.
  enum class Output { filled, antialiased, complex_filter } output = Output::filled;
  int secondary_neighbour = -1;  // antialiased: index into kNeighbourDx/Dy
  float primary_area = 1;
  Rgb secondary{};               // the neighbour's filled colour
  ComplexTrace complex;          // complex_filter
  Rgb estimate{};                // complex_filter: the pixel's simple estimate (its filled colour)
  Rgb result{};

  // For comparison: the render cache's colour from the same samples.
  Rgb rendercache{};
};

class Tracer {
 public:
  // `epi` holds the samples (classified or not); settings.filter must be Filter::epi.
  Tracer(EpiImage epi, BoundaryMasks masks, const ReconstructSettings& settings);
  PixelTrace trace(int x, int y) const;

  const EpiImage& classified() const { return epi_; }
  const BoundaryMasks& masks() const { return masks_; }
  const ReconstructSettings& settings() const { return settings_; }
  int type_at(int x, int y) const { return types_[epi_.index(x, y)]; }

 private:
  EpiRows rows() const { return whole_image_rows(epi_, types_.data()); }
  EpiImage epi_;
  BoundaryMasks masks_;
  ReconstructSettings settings_;
  std::vector<uint8_t> types_;
};

}  // namespace epi

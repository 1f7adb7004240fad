// The complex-pixel filter. Footprint: 3x3 pixels (boundary masks with the centre lines,
// samples) and the pixel's simple estimate.
// The 3x3 neighbourhood becomes a 6x6 grid of sub-pixels, each classified and given an edge
// from its four half-side masks (4 pieces of 1/8 pixel per side). Sub-pixel regions that touch
// across a shared side without an edge between them are connected; a region's colour is the
// kernel-weighted average of the samples connected to it (kernel 1/(1+d^2)^2, d in
// sub-pixels). The pixel is the average of its four sub-pixels, simple sub-pixels blending
// their two regions by area; complex sub-pixels and regions with no sample use the estimate.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "epi/geometry.h"
#include "epi/rows.h"
#include "epi/rasterize.h"

namespace epi {

// Reads rows y-1..y+1 of `epi` (samples) and of the masks.
void complex_pixel(const EpiRows& epi, const BoundaryMasks& masks, int x, int y, const float estimate[3],
                   float out[3]);

// Each pixel's sub-pixels and sample as complex_row computed them, kept for the rows after
// (one per thread; a copy starts empty). reset() before rows of another image, or of the same
// image after its rows changed: the cache only knows rows by number.
class ComplexRowCache {
 public:
  ComplexRowCache();
  ComplexRowCache(const ComplexRowCache&);
  ComplexRowCache& operator=(const ComplexRowCache&);
  ~ComplexRowCache();
  void reset();
  struct Pixel;
  struct Rows;

 private:
  friend void complex_row(const EpiRows&, const BoundaryMasks&, int, const uint8_t*, const float*, float*,
                          ComplexRowCache&, int64_t);
  std::unique_ptr<Rows> rows_;
};

// The filter's row kernel: complex_pixel for every complex pixel of row y (types[x] ==
// kTypeComplex), bit for bit, from the row's estimates (3 floats per pixel) into out; other
// pixels untouched. Each pixel's sub-pixels and sample are computed once for all the windows
// that hold it (through `cache`), joins come from bitboards (docs/epi.md, "Complex pixels").
// `target`: the Highway target (a HWY_* bit of complex_row_targets()) whose compilation runs, 0
// the best one here; the schedules pass their reconstructor's (simd::RowKernels::target). Every
// target's result is the same, bit for bit.
void complex_row(const EpiRows& epi, const BoundaryMasks& masks, int y, const uint8_t* types, const float* estimate,
                 float* out, ComplexRowCache& cache, int64_t target = 0);
// The targets complex_row is compiled for and this CPU runs, best first.
std::vector<int64_t> complex_row_targets();

// The class of a sub-pixel (n = 4) by its side masks, index top | right << 4 | bottom << 8 |
// left << 12, as complex_pixel and complex_row take it: kind in bits 0-1, p_low in 2-5, p_high in
// 6-9 of geom::classify_cell (tested against it for every index).
uint16_t sub_cell_class(uint32_t index);

// What complex_pixel did, for the visualizer's trace (trace.h). Sub-pixel (u, v), u, v in 0..5,
// covers pixel (x - 1 + u / 2, y - 1 + v / 2); the pixel's own are u, v in 2..3.
struct ComplexTrace {
  struct Sub {
    CellKind kind = CellKind::complex;  // complex also stands for "outside the image"
    int p_low = 0, p_high = 0;          // simple: the edge on the 4-piece sides
    int group[2] = {-1, -1};            // connected-region id of regions A (or the whole) and B
  };
  struct Sample {
    int qx, qy, u, v;
    int region;   // 0 A (or the whole sub-pixel), 1 B, 2 edge-ambiguous (dropped), 3 in a complex sub-pixel (dropped)
    int group;    // connected-region id, -1 when dropped
    float rgb[3];
  };
  struct Centre {  // one of the pixel's four sub-pixels, u = 2 + (k & 1), v = 2 + (k >> 1)
    float area_a = 1;
    float region_rgb[2][3] = {};
    bool region_found[2] = {};  // false: no sample joined, the estimate stands in
    float rgb[3] = {};
  };
  Sub sub[6][6];  // [v][u]
  std::vector<Sample> samples;
  Centre centre[4];
};
// complex_pixel, recording into `trace`.
void complex_pixel_traced(const EpiRows& epi, const BoundaryMasks& masks, int x, int y, const float estimate[3],
                          float out[3], ComplexTrace& trace);

}  // namespace epi

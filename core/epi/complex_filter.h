// The complex-pixel filter. Footprint: 3x3 pixels (boundary masks with the centre lines,
// samples) and the pixel's simple estimate.
// The 3x3 neighbourhood becomes a 6x6 grid of sub-pixels, each classified and given an edge
// from its four half-side masks (4 pieces of 1/8 pixel per side). Sub-pixel regions that touch
// across a shared side without an edge between them are connected; a region's colour is the
// kernel-weighted average of the samples connected to it (kernel 1/(1+d^2)^2, d in
// sub-pixels). The pixel is the average of its four sub-pixels, simple sub-pixels blending
// their two regions by area; complex sub-pixels and regions with no sample use the estimate.
#pragma once

#include "epi/rows.h"
#include "epi/rasterize.h"

namespace epi {

// Reads rows y-1..y+1 of `epi` (samples) and of the masks.
void complex_pixel(const EpiRows& epi, const BoundaryMasks& masks, int x, int y, const float estimate[3],
                   float out[3]);

}  // namespace epi

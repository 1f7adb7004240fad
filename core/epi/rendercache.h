// The render cache's own interpolation, for comparison: no edges, no reachability.
// Footprint: 3x3 samples, 7x7 where the 3x3 holds none (the uniform prefilter).
// Kernel 3x3: 1 centre, 1/2 sides, 1/4 diagonals, renormalized.
#pragma once

#include "epi/rows.h"

namespace epi {

// Colour of pixel (x, y) into rgb; returns its priority (same scale as interpolate.h).
float rendercache_pixel(const EpiRows& rows, int x, int y, float rgb[3]);

}  // namespace epi

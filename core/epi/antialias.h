// Anti-aliasing of simple pixels. Footprint: 3x3 of interpolated primary colours.
// colour = a * primary + (1 - a) * (primary colour of the neighbour the table picks for the
// secondary region), a = the primary region's area; all in linear light.
#pragma once

#include "epi/rows.h"

namespace epi {

// rows[k] = interpolated RGB of row y - 1 + k (nullptr outside the image); `epi`: pixel (x, y)'s
// type and edge code.
void antialias_pixel(const EpiRows& epi, int x, int y, const float* const rows[3], float out[3]);

}  // namespace epi

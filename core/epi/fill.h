// The fill step, after interpolation. Footprint: 5x5 of interpolated primary colours.
// A pixel that reached no sample takes the kernel-weighted mean (interpolate.h's kernel) of the
// primary colours of the pixels of its 5x5 that it reaches and that did reach samples; with
// none, it keeps its fallback colour. docs/epi.md, "Interpolation".
#pragma once

#include <cstdint>

namespace epi {

// rows[k] and found[k]: interpolated row y - 2 + k and its found flags (nullptr outside the
// image); reach: the pixel's 24-bit mask.
void fill_pixel(int x, int width, uint32_t reach, const float* const rows[5], const uint8_t* const found[5],
                float out[3]);

}  // namespace epi

// Row kernels of the point cache's window minima (issue 11): the least depth over a pixel's
// (2r+1)^2 window (PointCache::window_min) and the depths that could stand alone
// (PointCache::mark_alone), with Highway (dynamic dispatch, every target Highway builds). The
// minimum of depths (never NaN) is exact and does not depend on the order, so every target gives
// the scalar loops' bits (tests/render/depth_windows_test.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

namespace epi::render {

// out[x] = the least of in[x - r .. x + r] within [0, w).
void row_window_min(const float* in, float* out, int w, int radius);

// out[x] = the least of rows[k][x] over k < count (count >= 1).
void rows_min(const float* const* rows, int count, float* out, int w);

// Per pixel of a row: least[x] = the least depth of the other pixels of its 3x3 (+inf outside
// the image: above or below may be null), and alone[x] = row[x] where that is larger than
// row[x], +inf elsewhere (PointCache::mark_alone).
void lone_depths(const float* above, const float* row, const float* below, float* least, float* alone, int w);

// The occlusion test's sparse ring (PointCache::hidden_behind_a_neighbour) over a window of
// `rows` rows of n <= 31 pixels, the first at alone[0] and neighbour_min[0], rows `stride` apart:
// bit k of masks[r] is set where alone * scale < depth and not neighbour_min * scale < depth (a
// lone point nearer than the tested one, none of whose neighbours is). Reads up to 31 floats past
// the last pixel of each row: the arrays must be padded (kWindowPad).
inline constexpr size_t kWindowPad = 32;
void lone_window_masks(const float* alone, const float* neighbour_min, size_t stride, int rows, int n, float scale,
                       float depth, uint32_t* masks);

}  // namespace epi::render

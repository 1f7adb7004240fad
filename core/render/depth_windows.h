// Row kernels of the point cache's window minima (issue 11): the least depth over a pixel's
// (2r+1)^2 window (PointCache::window_min) and the depths that could stand alone
// (PointCache::mark_alone), with Highway (dynamic dispatch, every target Highway builds). The
// minimum of depths (never NaN) is exact and does not depend on the order, so every target gives
// the scalar loops' bits (tests/render/depth_windows_test.cpp).
#pragma once

namespace epi::render {

// out[x] = the least of in[x - r .. x + r] within [0, w).
void row_window_min(const float* in, float* out, int w, int radius);

// out[x] = the least of rows[k][x] over k < count (count >= 1).
void rows_min(const float* const* rows, int count, float* out, int w);

// Per pixel of a row: least[x] = the least depth of the other pixels of its 3x3 (+inf outside
// the image: above or below may be null), and alone[x] = row[x] where that is larger than
// row[x], +inf elsewhere (PointCache::mark_alone).
void lone_depths(const float* above, const float* row, const float* below, float* least, float* alone, int w);

}  // namespace epi::render

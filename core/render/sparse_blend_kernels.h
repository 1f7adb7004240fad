// Highway kernels of the sparse regions' blend (sparse_blend.h), dispatched at run time over every
// target Highway builds. Each does the float operations of the scalar filter and blend in
// sparse_blend.cpp, per element and in the same order, with no fused multiply-add, so every target
// gives their bits (tests/render/sparse_blend_test.cpp). docs/render.md, "Sparse regions".
#pragma once

#include <cstddef>
#include <cstdint>

namespace epi::render {

// The row pass filters kSparseRowLanes rows at once, row r of the group in lane r: `lanes` holds
// the kSparseBlendChannels values of each pixel x, channel c of row r at lanes[(x C + c) L + r]
// (C channels, L lanes); keep[x L + r] is 1 where the pixel is no barrier, else 0. The recursive
// filter along x (sparse_blend.cpp's definition) replaces `lanes` in place; `forward` is scratch
// of width x C x L floats.
inline constexpr int kSparseRowLanes = 8;
void filter_row_lanes(float* lanes, const float* keep, float* forward, int width, float a);

// A group of kSparseRowLanes rows moved into that layout and back: its `rows` rows in the image
// (rows below them are zeros, kept still) from pixel `first`, `width` apart. The values come from
// the EPI where `color` is set (the first iteration; sparse_blend.cpp's pixel_values), else from
// the planes (plane c of pixel i at planes[c * plane + i]); keep is barrier[i] == 0. On targets
// with 8 float lanes in 8 x 8 transposes, else pixel by pixel; data movement only, so every target
// gives the same bits.
struct SparseRowGroup {
  const uint16_t* edge;  // EpiImage::edge (read only with color)
  const uint32_t* color; // EpiImage::color, or nullptr: read the planes
  const float* lut;      // epi_color8_to_linear()
  float* planes;
  size_t plane;
  const uint8_t* barrier;
  int width, rows;
  size_t first;
};
void gather_row_lanes(const SparseRowGroup& group, float* lanes, float* keep);
// The filtered lanes back into the group's rows of the planes.
void scatter_row_lanes(const SparseRowGroup& group, const float* lanes);

// The column pass over the strip of columns [x0, x0 + kSparseStrip) (or to the image's right side)
// of the planes (plane c of pixel i at planes[c * plane + i], rows `width` apart), the keep flag
// being barrier[i] == 0. Without `image`, the filtered values replace the planes'; with it, they
// stay in `forward` and the strip of `image` (3 floats per pixel) is blended as sparse_blend does;
// returns the number of pixels changed. `forward`: scratch of height x channels x kSparseStrip floats.
inline constexpr int kSparseStrip = 32;
struct SparseColumnStrip {
  float* planes;
  size_t plane;
  const uint8_t* barrier;
  int width, height, x0;
  float a;
  float* forward;
  float* image;        // nullptr: write the planes back
  float dense, span;   // the blend's (SparseBlendSettings: dense, dense - sparse)
};
size_t filter_column_strip(const SparseColumnStrip& strip);

}  // namespace epi::render

// Row views of the classified EPI, as the stages after classification read it. Row y lives at
// slot y & mask: mask kWholeImage views whole-image planes (the oracle), mask 2^k - 1 a ring of
// 2^k rows (reconstruct_tiled; docs/epi.md, "Schedule"). Readers touch only rows the ring holds.
#pragma once

#include <cstddef>
#include <cstdint>

#include "epi/epi_pixel.h"

namespace epi {

constexpr int kWholeImage = ~0;

// Pixel types (epi_pixel.h), one byte per pixel.
struct TypeRows {
  const uint8_t* types;
  int width, height;
  int mask = kWholeImage;
  const uint8_t* row(int y) const { return types + size_t(y & mask) * size_t(width); }
  int at(int x, int y) const { return row(y)[x]; }
};

// Classified edge words and types (rows at slot y & mask), and sample colours (always the whole
// image: classification does not write them).
struct EpiRows {
  const uint16_t* edge;
  const uint8_t* types;
  const uint32_t* color;
  int width, height;
  int mask = kWholeImage;
  const uint16_t* edge_row(int y) const { return edge + size_t(y & mask) * size_t(width); }
  const uint32_t* color_row(int y) const { return color + size_t(y) * size_t(width); }
  uint16_t edge_at(int x, int y) const { return edge_row(y)[x]; }
  uint32_t color_at(int x, int y) const { return color_row(y)[x]; }
  int type_at(int x, int y) const { return types[size_t(y & mask) * size_t(width) + size_t(x)]; }
  TypeRows type_rows() const { return {types, width, height, mask}; }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

// The whole-image view of a classified EPI whose types are `types` (width x height).
inline EpiRows whole_image_rows(const EpiImage& epi, const uint8_t* types) {
  return {epi.edge.data(), types, epi.color.data(), epi.width, epi.height};
}

}  // namespace epi

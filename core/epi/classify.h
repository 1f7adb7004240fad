// Classification (empty / simple / complex), edge reconstruction into 10-bit codes, sample
// sidedness, primary regions. Footprint: 1x1 (the pixel's four boundary masks and its sample).
#pragma once

#include <cstdint>

#include "epi/epi_pixel.h"
#include "epi/geometry.h"
#include "epi/rasterize.h"

namespace epi {

struct ClassCounts {
  int64_t empty = 0, simple = 0, complex = 0, samples = 0, ambiguous = 0;
};

// Pixel (x, y) whose edge word is `edge`: that word with its edge code and usable bit set
// (sample bits kept; classifying a classified word gives it back unchanged), and its type.
struct PixelClass {
  uint16_t edge;
  uint8_t type;
  CellKind kind;
};
PixelClass classify_pixel(const BoundaryMasks& masks, int x, int y, uint16_t edge);

// Row y: classifies the edge words `in` into `edge` (may be `in`) and `types`; adds to `counts`.
void classify_row(const BoundaryMasks& masks, int y, const uint16_t* in, uint16_t* edge, uint8_t* types,
                  ClassCounts& counts);

// Rows [y0, y1) in place: edge plane, cache plane (type, reachability cleared) and, when given,
// `types` (width x height).
ClassCounts classify_rows(EpiImage& epi, const BoundaryMasks& masks, int y0, int y1, uint8_t* types = nullptr);

}  // namespace epi

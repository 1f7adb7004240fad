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

// Writes the edge code and usable bit (edge plane) and the type (cache plane, reachability
// cleared) of pixel (x, y). Returns the pixel's kind.
CellKind classify_pixel(EpiImage& epi, const BoundaryMasks& masks, int x, int y);

// Rows [y0, y1); also writes each pixel's type into `types` (width x height) when given.
ClassCounts classify_rows(EpiImage& epi, const BoundaryMasks& masks, int y0, int y1, uint8_t* types = nullptr);

}  // namespace epi

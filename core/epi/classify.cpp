#include "epi/classify.h"

#include "epi/geometry.h"
#include "epi/tables.h"

namespace epi {

CellKind classify_pixel(EpiImage& epi, const BoundaryMasks& masks, int x, int y) {
  const EpiTables& t = epi_tables();
  const size_t i = epi.index(x, y);
  uint8_t sides[4];
  masks.pixel_sides(x, y, sides);
  const bool no_crossing = (sides[0] | sides[1] | sides[2] | sides[3]) == 0;
  const geom::CellClass c = no_crossing ? geom::CellClass{CellKind::empty, 0, 0} : geom::classify_cell(sides, 8);
  uint16_t edge = uint16_t(epi.edge[i] & ~(bits::kCodeMask | bits::kUsable));
  int type = kTypeEmpty;
  const bool sample = edge & bits::kHasSample;
  bool usable = sample;
  if (c.kind == CellKind::complex) {
    edge |= kComplexCode;
    type = kTypeComplex;
  } else if (c.kind == CellKind::simple) {
    const int code = make_code(c.p_low, c.p_high);
    edge |= uint16_t(code);
    bool primary_is_b = t.area_a[code] < 32768;  // no usable sample: the larger region
    if (sample) {
      const int side = t.side(code, sample_region(edge));
      usable = side != 2;
      if (usable) primary_is_b = side == 1;
    }
    type = simple_type(c.p_low / 8, c.p_high / 8, primary_is_b);
  }
  if (usable) edge |= bits::kUsable;
  epi.edge[i] = edge;
  epi.cache[i] = uint32_t(type) << bits::kTypeShift;
  return c.kind;
}

ClassCounts classify_rows(EpiImage& epi, const BoundaryMasks& masks, int y0, int y1, uint8_t* types) {
  ClassCounts counts;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < epi.width; ++x) {
      const CellKind kind = classify_pixel(epi, masks, x, y);
      counts.empty += kind == CellKind::empty;
      counts.simple += kind == CellKind::simple;
      counts.complex += kind == CellKind::complex;
      const uint16_t e = epi.edge[epi.index(x, y)];
      if (types) types[epi.index(x, y)] = uint8_t(pixel_type(epi.cache[epi.index(x, y)]));
      counts.samples += has_sample(e);
      counts.ambiguous += has_sample(e) && !usable_sample(e);
    }
  return counts;
}

}  // namespace epi

#include "epi/classify.h"

#include <vector>

#include "epi/geometry.h"
#include "epi/tables.h"

namespace epi {

PixelClass classify_pixel(const BoundaryMasks& masks, int x, int y, uint16_t edge) {
  const EpiTables& t = epi_tables();
  uint8_t sides[4];
  masks.pixel_sides(x, y, sides);
  const bool no_crossing = (sides[0] | sides[1] | sides[2] | sides[3]) == 0;
  geom::CellClass c = no_crossing ? geom::CellClass{CellKind::empty, 0, 0} : geom::classify_cell(sides, 8);
  // Two crossings on different sides make a pixel simple, unless the centre lines (when
  // recorded) show the edge leaving the chord between them: a corner inside the pixel.
  if (c.kind == CellKind::simple && masks.centre_lines) {
    const size_t i = masks.index(x, y);
    const uint16_t on_chord = t.centre_on_chord[make_code(c.p_low, c.p_high)];
    if ((masks.centre_h[i] & ~on_chord) | (masks.centre_v[i] & ~(on_chord >> 8))) c = {CellKind::complex, 0, 0};
  }
  edge = uint16_t(edge & ~(bits::kCodeMask | bits::kUsable));
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
  return {edge, uint8_t(type), c.kind};
}

void classify_row(const BoundaryMasks& masks, int y, const uint16_t* in, uint16_t* edge, uint8_t* types,
                  ClassCounts& counts) {
  for (int x = 0; x < masks.width; ++x) {
    const PixelClass c = classify_pixel(masks, x, y, in[x]);
    edge[x] = c.edge;
    types[x] = c.type;
    counts.empty += c.kind == CellKind::empty;
    counts.simple += c.kind == CellKind::simple;
    counts.complex += c.kind == CellKind::complex;
    counts.samples += has_sample(c.edge);
    counts.ambiguous += has_sample(c.edge) && !usable_sample(c.edge);
  }
}

ClassCounts classify_rows(EpiImage& epi, const BoundaryMasks& masks, int y0, int y1, uint8_t* types) {
  ClassCounts counts;
  const int w = epi.width;
  std::vector<uint8_t> row(types ? 0 : size_t(w));
  for (int y = y0; y < y1; ++y) {
    uint16_t* edge = &epi.edge[epi.index(0, y)];
    uint8_t* t = types ? types + epi.index(0, y) : row.data();
    classify_row(masks, y, edge, edge, t, counts);
    uint32_t* cache = &epi.cache[epi.index(0, y)];
    for (int x = 0; x < w; ++x) cache[x] = uint32_t(t[x]) << bits::kTypeShift;
  }
  return counts;
}

}  // namespace epi

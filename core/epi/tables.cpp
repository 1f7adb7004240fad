#include "epi/tables.h"

#include <algorithm>
#include <cmath>

#include "epi/geometry.h"

namespace epi {

namespace {

// The sides of a simple type's edge and its primary side.
void decode_simple_type(int type, int& side_low, int& side_high, bool& primary_is_b) {
  static constexpr int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  const int pair = (type - 2) / 2;
  side_low = kPairs[pair][0];
  side_high = kPairs[pair][1];
  primary_is_b = (type - 2) & 1;
}

// Two pieces of a shared side, each given as the part of its pixel's side (0 whole, 1 before
// the crossing, 2 after), touch: the two sides run in opposite directions along the shared line,
// so a's part after the crossing faces b's part before it.
bool parts_touch(int part_a, int part_b) { return part_a == 0 || part_b == 0 || part_a != part_b; }

uint8_t neighbour_mask(int dir, int type_a, int type_b) {
  const int side_a = dir == kRight ? 1 : dir == kDown ? 2 : dir == kLeft ? 3 : 0;
  const int side_b = (side_a + 2) % 4;
  int ra[2], pa[2], rb[2], pb[2];
  const int na = regions_on_side(type_a, side_a, ra, pa);
  const int nb = regions_on_side(type_b, side_b, rb, pb);
  uint8_t mask = 0;
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j) {
      if (parts_touch(pa[i], pb[j])) mask |= uint8_t(1u << (ra[i] * 2 + rb[j]));
    }
  return mask;
}

uint8_t chain_mask(int ab, int bd) {
  auto bit = [](int m, int from, int to) { return (m >> (from * 2 + to)) & 1; };
  uint8_t result = 0;
  for (int a = 0; a < 2; ++a)
    for (int d = 0; d < 2; ++d) {
      int reach = 0;
      for (int b = 0; b < 2; ++b) reach |= bit(ab, a, b) & bit(bd, b, d);
      result |= uint8_t(reach << (a * 2 + d));
    }
  return result;
}

}  // namespace

int regions_on_side(int type, int side, int regions[2], int parts[2]) {
  if (type == kTypeEmpty) {
    regions[0] = 0;
    parts[0] = 0;
    return 1;
  }
  if (!type_is_simple(type)) return 0;
  int lo, hi;
  bool primary_is_b;
  decode_simple_type(type, lo, hi, primary_is_b);
  const int a = primary_is_b ? 1 : 0, b = 1 - a;  // region labels of A and B
  if (side > lo && side < hi) {
    regions[0] = a, parts[0] = 0;
    return 1;
  }
  if (side < lo || side > hi) {
    regions[0] = b, parts[0] = 0;
    return 1;
  }
  // The arc of A leaves p_low clockwise and arrives at p_high.
  regions[0] = a, parts[0] = side == lo ? 2 : 1;
  regions[1] = b, parts[1] = side == lo ? 1 : 2;
  return 2;
}

EpiTables generate_tables() {
  EpiTables t{};
  for (int code = 0; code < kCodeCount; ++code) {
    t.centre_on_chord[code] = 0xffff;
    if (!code_is_simple(code)) continue;
    const geom::CellEdge e = geom::cell_edge(code_low(code), code_high(code), 8);
    uint16_t on_chord = 0;
    const double length = std::hypot(e.b.x - e.a.x, e.b.y - e.a.y);
    for (int m = 0; m < 8; ++m) {
      const double along = (m + 0.5) / 8.0;
      if (std::abs(geom::orient(e.a, e.b, {along, 0.5})) <= kChordTolerance * length) on_chord |= uint16_t(1u << m);
      if (std::abs(geom::orient(e.a, e.b, {0.5, along})) <= kChordTolerance * length) on_chord |= uint16_t(1u << (8 + m));
    }
    t.centre_on_chord[code] = on_chord;
    for (int r = 0; r < 16; ++r) {
      const int side = geom::square_side(e, (r & 3) * 0.25, (r >> 2) * 0.25, 0.25);
      t.sidedness[code] |= uint32_t(side) << (2 * r);
    }
    t.area_a[code] = uint16_t(std::lround(std::clamp(geom::area_a(e), 0.0, 1.0) * 65535.0));
    // The secondary colour comes from the neighbour with the most area on the secondary
    // side of the edge's line; ties go to side neighbours, then to the earlier index.
    for (int region = 0; region < 2; ++region) {
      int best = 0;
      double best_fraction = -1.0;
      for (int k = 0; k < 8; ++k) {
        const double f = geom::square_fraction_on_side(e, region, kNeighbourDx[k], kNeighbourDy[k]);
        if (f > best_fraction + 1e-9) best_fraction = f, best = k;
      }
      t.secondary_neighbour[code] |= uint8_t(best << (4 * region));
    }
  }
  for (int dir = 0; dir < 4; ++dir)
    for (int a = 0; a < 16; ++a)
      for (int b = 0; b < 16; ++b) t.neighbour[dir][(a << 4) | b] = neighbour_mask(dir, a, b);
  for (int m = 0; m < 256; ++m) t.chain[m] = chain_mask(m >> 4, m & 15);
  return t;
}

// Side words (simd::ReachRow) by pixel type, and the relation of side descriptors, both from
// the same regions_on_side that generates the oracle's neighbour table (tables.cpp).
const SideDescriptors& side_descriptors() {
  static const SideDescriptors tables = [] {
    SideDescriptors t{};
    for (int type = 0; type < 16; ++type) {
      uint32_t word = type == kTypeEmpty ? 0 : kSideNonEmpty;
      for (int side = 0; side < 4; ++side) {
        int regions[2], parts[2];
        const int n = regions_on_side(type, side, regions, parts);
        if (n == 0) word |= kSideBlocked;  // complex (and the unused types)
        const uint32_t descriptor = n == 2 ? (parts[regions[0] == 0 ? 0 : 1] == 1 ? 2u : 3u) : n == 1 ? uint32_t(regions[0]) : 0u;
        word |= descriptor << (2 * side);
      }
      t.word[type] = word;
    }
    // Descriptor d as (region, part) pairs; part 0 whole, 1 before the crossing, 2 after.
    auto pairs = [](int d, int regions[2], int parts[2]) {
      if (d < 2) return regions[0] = d, parts[0] = 0, 1;
      regions[0] = 0, parts[0] = d == 2 ? 1 : 2, regions[1] = 1, parts[1] = d == 2 ? 2 : 1;
      return 2;
    };
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        int ra[2], pa[2], rb[2], pb[2];
        const int na = pairs(a, ra, pa), nb = pairs(b, rb, pb);
        uint32_t mask = 0;
        for (int i = 0; i < na; ++i)
          for (int k = 0; k < nb; ++k)
            if (parts_touch(pa[i], pb[k])) mask |= 1u << (ra[i] * 2 + rb[k]);
        const int index = 4 * a + b;
        (index < 8 ? t.relation_lo : t.relation_hi) |= mask << (4 * (index & 7));
      }
    return t;
  }();
  return tables;
}

const EpiTables& epi_tables() {
  static const EpiTables tables = generate_tables();
  return tables;
}

}  // namespace epi

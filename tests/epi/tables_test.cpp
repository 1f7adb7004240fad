// Every entry of the generated tables against a brute-force geometric computation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "epi/geometry.h"
#include "epi/tables.h"

namespace epi {
namespace {

using geom::Vec2;

std::vector<int> simple_codes() {
  std::vector<int> codes;
  for (int code = 0; code < kCodeCount; ++code)
    if (code_is_simple(code)) codes.push_back(code);
  return codes;
}

TEST(Tables, SimpleCodeCountAndReservedCodes) {
  EXPECT_EQ(simple_codes().size(), 6u * 64u);
  EXPECT_FALSE(code_is_simple(kEmptyCode));
  EXPECT_FALSE(code_is_simple(kComplexCode));
  EXPECT_LE(sizeof(EpiTables), 16u * 1024u);
}

// For one line through the two boundary segments: the sign of region A, read off the boundary
// points strictly between the segments on A's arc. When the line runs along that arc, A is
// empty and the cell's centre lies in B.
double line_sign_a(int p_low, int p_high, Vec2 p, Vec2 q) {
  for (int k = 0; k <= 16; ++k) {
    const double u = (p_low + 1) + (p_high - p_low - 1) * k / 16.0;
    const double o = geom::orient(p, q, geom::perimeter_point(u, 8));
    if (o != 0) return o > 0 ? 1.0 : -1.0;
  }
  return geom::orient(p, q, {0.5, 0.5}) > 0 ? -1.0 : 1.0;
}

TEST(Tables, SidednessMatchesEveryLineThroughTheSegments) {
  const EpiTables& t = epi_tables();
  constexpr int kSteps = 8;
  for (int code : simple_codes()) {
    const int lo = code_low(code), hi = code_high(code);
    for (int r = 0; r < 16; ++r) {
      bool all_a = true, all_b = true;
      for (int s = 0; s <= kSteps; ++s)
        for (int u = 0; u <= kSteps; ++u) {
          const Vec2 p = geom::boundary_point(lo, 8, double(s) / kSteps);
          const Vec2 q = geom::boundary_point(hi, 8, double(u) / kSteps);
          const double sign = line_sign_a(lo, hi, p, q);
          for (int i = 0; i <= 4; ++i)
            for (int j = 0; j <= 4; ++j) {
              const Vec2 x{((r & 3) + i / 4.0) * 0.25, ((r >> 2) + j / 4.0) * 0.25};
              const double o = sign * geom::orient(p, q, x);
              all_a = all_a && o > 0;
              all_b = all_b && o < 0;
            }
        }
      const int expected = all_a ? 0 : (all_b ? 1 : 2);
      ASSERT_EQ(t.side(code, r), expected) << "code " << code << " region " << r;
    }
  }
}

TEST(Tables, AmbiguousRegionsHugTheEdge) {
  // A vertical edge through the middle (top piece 3 to bottom piece 3... x in [3/8, 4/8]):
  // columns 0 and 3 are decided, columns 1 and 2 are cut by some possible edge.
  const EpiTables& t = epi_tables();
  const int code = make_code(boundary_position(0, 3, 8), boundary_position(2, 3, 8));
  for (int r = 0; r < 16; ++r) {
    const int column = r & 3;
    if (column == 0 || column == 3) {
      EXPECT_NE(t.side(code, r), 2) << r;
    }
    if (column == 1) {
      EXPECT_EQ(t.side(code, r), 2) << r;
    }
    if (column == 0) {
      EXPECT_NE(t.side(code, r), t.side(code, r + 3));
    }
  }
}

TEST(Tables, AreaMatchesSupersampling) {
  const EpiTables& t = epi_tables();
  constexpr int kGrid = 256;
  for (int code : simple_codes()) {
    const int lo = code_low(code), hi = code_high(code);
    const Vec2 a = geom::boundary_point(lo, 8, 0.5), b = geom::boundary_point(hi, 8, 0.5);
    const double sign = line_sign_a(lo, hi, a, b);
    int inside = 0;
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i)
        inside += sign * geom::orient(a, b, {(i + 0.5) / kGrid, (j + 0.5) / kGrid}) > 0;
    const double brute = double(inside) / (kGrid * kGrid);
    ASSERT_NEAR(t.area_of_a(code), brute, 2.0 / kGrid) << "code " << code;
  }
}

TEST(Tables, SecondaryNeighbourHasTheMostSecondaryArea) {
  const EpiTables& t = epi_tables();
  constexpr int kGrid = 48;
  for (int code : simple_codes()) {
    const int lo = code_low(code), hi = code_high(code);
    const Vec2 a = geom::boundary_point(lo, 8, 0.5), b = geom::boundary_point(hi, 8, 0.5);
    const double sign_a = line_sign_a(lo, hi, a, b);
    for (int secondary = 0; secondary < 2; ++secondary) {
      const double sign = secondary == 0 ? sign_a : -sign_a;
      double fraction[8], best = 0;
      for (int k = 0; k < 8; ++k) {
        int inside = 0;
        for (int j = 0; j < kGrid; ++j)
          for (int i = 0; i < kGrid; ++i)
            inside += sign * geom::orient(a, b, {kNeighbourDx[k] + (i + 0.5) / kGrid, kNeighbourDy[k] + (j + 0.5) / kGrid}) > 0;
        fraction[k] = double(inside) / (kGrid * kGrid);
        best = std::max(best, fraction[k]);
      }
      const int chosen = t.neighbour_for_secondary(code, secondary == 1);
      ASSERT_LT(chosen, 8);
      ASSERT_GE(fraction[chosen], best - 3.0 / kGrid) << "code " << code << " secondary " << secondary;
    }
  }
}

// A candidate pixel for the neighbour test: empty, complex, or a simple code.
struct Candidate {
  int kind;  // 0 empty, 1 complex, 2 simple
  int code;
};

// Bits of a candidate's crossings on `side`.
int side_bits(const Candidate& c, int side) {
  if (c.kind != 2) return 0;
  int bits = 0;
  for (int p : {code_low(c.code), code_high(c.code)}) {
    if (p / 8 != side) continue;
    const int along = p % 8;
    bits |= 1 << (side < 2 ? along : 7 - along);
  }
  return bits;
}

TEST(Tables, NeighbourReachabilityMatchesTheSharedSide) {
  const EpiTables& t = epi_tables();
  std::vector<Candidate> candidates{{0, 0}, {1, 0}};
  for (int code : simple_codes()) candidates.push_back({2, code});
  int checked = 0;
  for (int dir = 0; dir < 4; ++dir) {
    const int side_a = dir == kRight ? 1 : dir == kDown ? 2 : dir == kLeft ? 3 : 0;
    const int side_b = (side_a + 2) % 4;
    auto point_on = [](int side, double s) -> Vec2 {  // s along increasing x or y
      return side == 0 ? Vec2{s, 0} : side == 1 ? Vec2{1, s} : side == 2 ? Vec2{s, 1} : Vec2{0, s};
    };
    for (const Candidate& a : candidates)
      for (const Candidate& b : candidates) {
        if (side_bits(a, side_a) != side_bits(b, side_b)) continue;  // they share that boundary
        for (int fa = 0; fa < (a.kind == 2 ? 2 : 1); ++fa)
          for (int fb = 0; fb < (b.kind == 2 ? 2 : 1); ++fb) {
            auto type_of = [](const Candidate& c, int flip) {
              return c.kind == 0 ? kTypeEmpty
                                 : c.kind == 1 ? kTypeComplex
                                               : simple_type(code_low(c.code) / 8, code_high(c.code) / 8, flip);
            };
            const int ta = type_of(a, fa), tb = type_of(b, fb);
            uint8_t brute = 0;
            if (a.kind != 1 && b.kind != 1)
              for (int k = 0; k < 64; ++k) {
                const double s = (k + 0.5) / 64.0;  // never a piece centre, where edges meet the side
                auto label = [&](const Candidate& c, int flip, int side) {
                  if (c.kind == 0) return 0;
                  const geom::CellEdge e = geom::cell_edge(code_low(c.code), code_high(c.code), 8);
                  return geom::region_of(e, point_on(side, s)) == flip ? 0 : 1;  // 0 primary
                };
                brute |= uint8_t(1u << (label(a, fa, side_a) * 2 + label(b, fb, side_b)));
              }
            ASSERT_EQ(t.neighbour[dir][(ta << 4) | tb], brute)
                << "dir " << dir << " codes " << a.code << "," << b.code << " flips " << fa << fb;
            ++checked;
          }
      }
  }
  EXPECT_GT(checked, 10000);
}

TEST(Tables, NeighbourReachabilityIsSymmetric) {
  const EpiTables& t = epi_tables();
  auto transpose = [](int m) { return (m & 9) | ((m & 2) << 1) | ((m & 4) >> 1); };
  for (int dir = 0; dir < 2; ++dir)
    for (int a = 0; a < 16; ++a)
      for (int b = 0; b < 16; ++b)
        ASSERT_EQ(t.neighbour[dir][(a << 4) | b], transpose(t.neighbour[dir + 2][(b << 4) | a]));
}

TEST(Tables, ChainingIsRelationComposition) {
  const EpiTables& t = epi_tables();
  for (int ab = 0; ab < 16; ++ab)
    for (int bd = 0; bd < 16; ++bd) {
      int expected = 0;
      for (int a = 0; a < 2; ++a)
        for (int d = 0; d < 2; ++d) {
          bool reach = false;
          for (int b = 0; b < 2; ++b) reach = reach || (((ab >> (2 * a + b)) & 1) && ((bd >> (2 * b + d)) & 1));
          if (reach) expected |= 1 << (2 * a + d);
        }
      ASSERT_EQ(t.chain[(ab << 4) | bd], expected);
    }
}

TEST(Tables, GeneratedTwiceIdentically) {
  const EpiTables a = generate_tables(), b = generate_tables();
  EXPECT_EQ(0, std::memcmp(&a, &b, sizeof(EpiTables)));
}

}  // namespace
}  // namespace epi

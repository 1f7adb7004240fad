// Every entry of the generated tables against a brute-force geometric computation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <utility>
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

// Exact area of the unit square at (ox, oy) on the side sign * orient(a, b, x) > 0: the square
// clipped by the half-plane (Sutherland-Hodgman), then the shoelace. Independent of the
// generator's walk along the boundary arc.
double clipped_area(Vec2 a, Vec2 b, double sign, double ox, double oy) {
  const std::vector<Vec2> square = {{ox, oy}, {ox + 1, oy}, {ox + 1, oy + 1}, {ox, oy + 1}};
  std::vector<Vec2> out;
  for (size_t i = 0; i < square.size(); ++i) {
    const Vec2 p = square[i], q = square[(i + 1) % square.size()];
    const double fp = sign * geom::orient(a, b, p), fq = sign * geom::orient(a, b, q);
    if (fp >= 0) out.push_back(p);
    if ((fp > 0 && fq < 0) || (fp < 0 && fq > 0)) {
      const double t = fp / (fp - fq);
      out.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
    }
  }
  double twice = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const Vec2 p = out[i], q = out[(i + 1) % out.size()];
    twice += p.x * q.y - q.x * p.y;
  }
  return std::abs(twice) / 2;
}

// The area entry is the exact area quantized to 1/65535; the check: exact clipping, and a
// 256x256 supersampling as a second, cruder witness of the side convention.
TEST(Tables, AreaIsExactUpToQuantization) {
  const EpiTables& t = epi_tables();
  constexpr int kGrid = 256;
  for (int code : simple_codes()) {
    const int lo = code_low(code), hi = code_high(code);
    const Vec2 a = geom::boundary_point(lo, 8, 0.5), b = geom::boundary_point(hi, 8, 0.5);
    const double sign = line_sign_a(lo, hi, a, b);
    const double exact = clipped_area(a, b, sign, 0, 0);
    ASSERT_NEAR(t.area_of_a(code), exact, 1.0 / 65535 + 1e-7) << "code " << code;
    int inside = 0;
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i)
        inside += sign * geom::orient(a, b, {(i + 0.5) / kGrid, (j + 0.5) / kGrid}) > 0;
    ASSERT_NEAR(exact, double(inside) / (kGrid * kGrid), 2.0 / kGrid) << "code " << code;
  }
}

// The chosen neighbour has the largest secondary-side area of the 8 (exact clipping, equal up
// to rounding), the first such in index order on ties.
TEST(Tables, SecondaryNeighbourHasTheMostSecondaryArea) {
  const EpiTables& t = epi_tables();
  for (int code : simple_codes()) {
    const int lo = code_low(code), hi = code_high(code);
    const Vec2 a = geom::boundary_point(lo, 8, 0.5), b = geom::boundary_point(hi, 8, 0.5);
    const double sign_a = line_sign_a(lo, hi, a, b);
    for (int secondary = 0; secondary < 2; ++secondary) {
      const double sign = secondary == 0 ? sign_a : -sign_a;
      double area[8], best = 0;
      for (int k = 0; k < 8; ++k) best = std::max(best, area[k] = clipped_area(a, b, sign, kNeighbourDx[k], kNeighbourDy[k]));
      int first_best = 0;
      while (area[first_best] < best - 1e-9) ++first_best;
      const int chosen = t.neighbour_for_secondary(code, secondary == 1);
      ASSERT_LT(chosen, 8);
      ASSERT_NEAR(area[chosen], best, 1e-9) << "code " << code << " secondary " << secondary;
      ASSERT_EQ(chosen, first_best) << "code " << code << " secondary " << secondary;
    }
  }
}

// A candidate pixel for the neighbour test: empty (with no crossing, or one at boundary
// position `code`: an edge ending inside it), complex (any crossings), or a simple code.
struct Candidate {
  int kind;  // 0 empty, 1 complex, 2 simple
  int code;  // simple: the edge code; empty: the one crossing's position, or -1
};

// Bits of a candidate's crossings on `side`, along increasing x or y.
int side_bits(const Candidate& c, int side) {
  std::vector<int> positions;
  if (c.kind == 2) positions = {code_low(c.code), code_high(c.code)};
  if (c.kind == 0 && c.code >= 0) positions = {c.code};
  int bits = 0;
  for (int p : positions) {
    if (p / 8 != side) continue;
    const int along = p % 8;
    bits |= 1 << (side < 2 ? along : 7 - along);
  }
  return bits;
}

// Whether a type has a crossing on `side` (empty: may have one, from an edge ending inside).
bool simple_touches(int type, int side) {
  if (!type_is_simple(type)) return false;
  static constexpr int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  const int pair = (type - 2) / 2;
  return kPairs[pair][0] == side || kPairs[pair][1] == side;
}

// Every (direction, type, type) entry that rasterization can produce, checked against pixel
// pairs that agree on their shared side, probing 64 points along it. Pairs: every simple code
// with both primary choices, empty pixels without a crossing and with one crossing anywhere,
// complex pixels (no regions; they may hold any crossings, so they pair with everything).
// Coverage is asserted by entry: an entry can occur when the two sides can agree, i.e. unless
// exactly one of the two pixels is simple with a crossing on the shared side and the other
// is simple without one.
TEST(Tables, NeighbourReachabilityMatchesTheSharedSide) {
  const EpiTables& t = epi_tables();
  std::vector<Candidate> candidates{{0, -1}, {1, 0}};
  for (int p = 0; p < 32; ++p) candidates.push_back({0, p});
  for (int code : simple_codes()) candidates.push_back({2, code});
  bool checked[4][16][16] = {};
  for (int dir = 0; dir < 4; ++dir) {
    const int side_a = dir == kRight ? 1 : dir == kDown ? 2 : dir == kLeft ? 3 : 0;
    const int side_b = (side_a + 2) % 4;
    auto point_on = [](int side, double s) -> Vec2 {  // s along increasing x or y
      return side == 0 ? Vec2{s, 0} : side == 1 ? Vec2{1, s} : side == 2 ? Vec2{s, 1} : Vec2{0, s};
    };
    for (const Candidate& a : candidates)
      for (const Candidate& b : candidates) {
        const bool agree = a.kind == 1 || b.kind == 1 || side_bits(a, side_a) == side_bits(b, side_b);
        if (!agree) continue;
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
                << "dir " << dir << " kinds " << a.kind << "," << b.kind << " codes " << a.code << "," << b.code
                << " flips " << fa << fb;
            checked[dir][ta][tb] = true;
          }
      }
  }
  int entries = 0;
  for (int dir = 0; dir < 4; ++dir) {
    const int side_a = dir == kRight ? 1 : dir == kDown ? 2 : dir == kLeft ? 3 : 0;
    const int side_b = (side_a + 2) % 4;
    for (int ta = 0; ta < 14; ++ta)
      for (int tb = 0; tb < 14; ++tb) {
        const bool mismatch = type_is_simple(ta) && type_is_simple(tb) &&
                              simple_touches(ta, side_a) != simple_touches(tb, side_b);
        if (mismatch) continue;
        EXPECT_TRUE(checked[dir][ta][tb]) << "dir " << dir << " types " << ta << "," << tb;
        ++entries;
      }
  }
  EXPECT_GT(entries, 4 * 100);
}

TEST(Tables, NeighbourReachabilityIsSymmetric) {
  const EpiTables& t = epi_tables();
  auto transpose = [](int m) { return (m & 9) | ((m & 2) << 1) | ((m & 4) >> 1); };
  for (int dir = 0; dir < 2; ++dir)
    for (int a = 0; a < 16; ++a)
      for (int b = 0; b < 16; ++b)
        ASSERT_EQ(t.neighbour[dir][(a << 4) | b], transpose(t.neighbour[dir + 2][(b << 4) | a]));
}

// Chaining by the semantics of relations: a 4-bit mask is the set of region pairs (x, y), x of
// the first pixel, y of the second, x, y in {P, S}, bit 2x + y. The chained mask is the set of
// pairs (x, z) joined by some path x -> y -> z through the middle pixel.
using Relation = std::set<std::pair<int, int>>;
Relation as_relation(int mask) {
  Relation r;
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y)
      if (mask & (1 << (2 * x + y))) r.insert({x, y});
  return r;
}
Relation compose(const Relation& first, const Relation& second) {
  Relation r;
  for (const auto& [x, y] : first)
    for (const auto& [y2, z] : second)
      if (y == y2) r.insert({x, z});
  return r;
}

TEST(Tables, ChainingIsRelationComposition) {
  const EpiTables& t = epi_tables();
  for (int ab = 0; ab < 16; ++ab)
    for (int bd = 0; bd < 16; ++bd)
      ASSERT_EQ(as_relation(t.chain[(ab << 4) | bd]), compose(as_relation(ab), as_relation(bd))) << ab << "," << bd;
  // The algebra paths need: the identity {(P,P), (S,S)} is neutral, nothing absorbs, and
  // chaining is associative (so the order paths are extended in does not matter).
  for (int m = 0; m < 16; ++m) {
    EXPECT_EQ(t.chain[(9 << 4) | m], m);
    EXPECT_EQ(t.chain[(m << 4) | 9], m);
    EXPECT_EQ(t.chain[m << 4], 0);
    EXPECT_EQ(t.chain[m], 0);
    for (int n = 0; n < 16; ++n)
      for (int k = 0; k < 16; ++k)
        ASSERT_EQ(t.chain[(t.chain[(m << 4) | n] << 4) | k], t.chain[(m << 4) | t.chain[(n << 4) | k]]);
  }
}

TEST(Tables, GeneratedTwiceIdentically) {
  const EpiTables a = generate_tables(), b = generate_tables();
  EXPECT_EQ(0, std::memcmp(&a, &b, sizeof(EpiTables)));
}

}  // namespace
}  // namespace epi

namespace epi {
namespace {

// The vector kernel's form of the neighbour table: per (direction, type, type), the relation of
// the two facing side descriptors, or nothing when either pixel is blocked, equals the table.
TEST(SideDescriptors, ReproduceTheNeighbourTable) {
  const EpiTables& t = epi_tables();
  const SideDescriptors& d = side_descriptors();
  int simple_pairs = 0;
  for (int dir = 0; dir < 4; ++dir) {
    const int side_a = dir == kRight ? 1 : dir == kDown ? 2 : dir == kLeft ? 3 : 0, side_b = (side_a + 2) % 4;
    for (int a = 0; a < 14; ++a)
      for (int b = 0; b < 14; ++b) {
        const uint32_t wa = d.word[a], wb = d.word[b];
        const int index = int((wa >> (2 * side_a)) & 3) * 4 + int((wb >> (2 * side_b)) & 3);
        const uint32_t relation = ((index < 8 ? d.relation_lo : d.relation_hi) >> (4 * (index & 7))) & 15;
        const uint32_t expected = t.neighbour[dir][(a << 4) | b];
        ASSERT_EQ((wa | wb) & kSideBlocked ? 0u : relation, expected) << dir << " " << a << " " << b;
        simple_pairs += type_is_simple(a) && type_is_simple(b) && expected != 0;
      }
  }
  EXPECT_GT(simple_pairs, 300);
  EXPECT_EQ(d.word[kTypeEmpty], 0u);                         // empty: the primary region on every side
  EXPECT_TRUE(d.word[kTypeComplex] & kSideBlocked);
  for (int type = 2; type < 14; ++type) EXPECT_FALSE(d.word[type] & kSideBlocked) << type;
}

}  // namespace
}  // namespace epi

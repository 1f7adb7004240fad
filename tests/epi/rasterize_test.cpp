// Edge rasterization and classification: brute-force crossings, the grid-line, corner and
// endpoint rules, reconstructed edges against the true line.
#include <gtest/gtest.h>

#include <bit>
#include <random>

#include "epi/geometry.h"
#include "epi/rasterize.h"
#include "test_util.h"

namespace epi {
namespace {

using test::kind_of;

// The crossings of one segment, computed line by line in long double.
BoundaryMasks brute_masks(int w, int h, const Segment& s) {
  BoundaryMasks m(w, h, true);
  auto mark = [&](std::vector<uint8_t>& plane, long double along, int line, bool vertical) {
    const long double q = std::floor(along * 8.0L);
    const long long cell = (long long)std::floor(q / 8.0L);
    const int bit = int(q - cell * 8.0L);
    if (vertical ? (cell < 0 || cell >= h) : (cell < 0 || cell >= w)) return;
    plane[vertical ? m.index(line, int(cell)) : m.index(int(cell), line)] |= uint8_t(1 << bit);
  };
  for (int k = 0; k <= 2 * w; ++k) {
    const long double x = k * 0.5L;
    if ((s.x0 < x) == (s.x1 < x) || (k % 2 && k / 2 >= w)) continue;
    const long double t = (x - s.x0) / ((long double)s.x1 - s.x0);
    mark(k % 2 ? m.centre_v : m.left, s.y0 + t * ((long double)s.y1 - s.y0), k / 2, true);
  }
  for (int k = 0; k <= 2 * h; ++k) {
    const long double y = k * 0.5L;
    if ((s.y0 < y) == (s.y1 < y) || (k % 2 && k / 2 >= h)) continue;
    const long double t = (y - s.y0) / ((long double)s.y1 - s.y0);
    mark(k % 2 ? m.centre_h : m.top, s.x0 + t * ((long double)s.x1 - s.x0), k / 2, false);
  }
  return m;
}

TEST(Rasterize, RandomSegmentsMatchBruteForce) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-4.0, 36.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const Segment s{u(rng), u(rng), u(rng), u(rng)};
    BoundaryMasks m(32, 24, true);
    rasterize_edges(m, std::span<const Segment>(&s, 1));
    const BoundaryMasks b = brute_masks(32, 24, s);
    ASSERT_EQ(m.top, b.top) << trial;
    ASSERT_EQ(m.left, b.left) << trial;
    ASSERT_EQ(m.centre_h, b.centre_h) << trial;
    ASSERT_EQ(m.centre_v, b.centre_v) << trial;
  }
}

// The documented tie rule written independently, in exact integer arithmetic: endpoints on the
// 1/8 grid (coordinates as integers in eighths), the segment shifted by (+e, +e^2). A line is
// crossed when exactly one (shifted) endpoint lies below it; the crossing's position along the
// line is a rational number of eighths, and when it falls exactly on a piece boundary the
// shift decides: on a vertical line y moves by -e * slope (up when slope > 0, else it stays,
// the +e^2 breaking the slope-0 tie upwards); on a horizontal line x moves by +e (stays).
BoundaryMasks brute_masks_eighths(int w, int h, long long X0, long long Y0, long long X1, long long Y1) {
  BoundaryMasks m(w, h, true);
  auto floor_div = [](long long a, long long b) {  // b > 0
    return a >= 0 ? a / b : -((-a + b - 1) / b);
  };
  auto mark = [&](std::vector<uint8_t>& plane, long long q, int line, bool vertical) {  // q: eighths along the line
    const long long cell = floor_div(q, 8);
    if (cell < 0 || cell >= (vertical ? h : w)) return;
    const int bit = int(q - 8 * cell);
    plane[vertical ? m.index(line, int(cell)) : m.index(int(cell), line)] |= uint8_t(1 << bit);
  };
  for (int k = 0; k <= 2 * w; ++k) {  // vertical lines x = k/2 (odd k: centre lines), in eighths 4k
    const long long L = 4LL * k;
    // Crossed when L is in (lo, hi], and line 0 (the image border) also when lo == 0 (rasterize.cpp).
    const bool crossed = (X0 < L) != (X1 < L) || (L == 0 && std::min(X0, X1) == 0 && X0 != X1);
    if (!crossed || (k % 2 && k / 2 >= w)) continue;
    long long num = Y0 * (X1 - X0) + (L - X0) * (Y1 - Y0), den = X1 - X0;  // y (eighths) = num / den
    if (den < 0) num = -num, den = -den;
    long long q = floor_div(num, den);
    const bool on_boundary = num == q * den;
    const bool slope_positive = (Y1 - Y0) * (X1 - X0) > 0;
    if (on_boundary && slope_positive) q -= 1;  // y - e * slope: just above the boundary
    mark(k % 2 ? m.centre_v : m.left, q, k / 2, true);
  }
  for (int k = 0; k <= 2 * h; ++k) {  // horizontal lines y = k/2
    const long long L = 4LL * k;
    const bool crossed = (Y0 < L) != (Y1 < L) || (L == 0 && std::min(Y0, Y1) == 0 && Y0 != Y1);
    if (!crossed || (k % 2 && k / 2 >= h)) continue;
    long long num = X0 * (Y1 - Y0) + (L - Y0) * (X1 - X0), den = Y1 - Y0;
    if (den < 0) num = -num, den = -den;
    mark(k % 2 ? m.centre_h : m.top, floor_div(num, den), k / 2, false);  // x + e: a boundary stays
  }
  return m;
}

TEST(Rasterize, SegmentsOnTheEighthGridFollowTheTieRule) {
  std::mt19937_64 rng(11);
  const int w = 9, h = 7;
  std::uniform_int_distribution<int> ex(-16, 8 * w + 16), ey(-16, 8 * h + 16), pick(0, 5);
  int on_lines = 0, ties = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    long long c[4] = {ex(rng), ey(rng), ex(rng), ey(rng)};
    for (int i = 0; i < 4; ++i) {
      const int r = pick(rng);
      if (r == 0) c[i] = 8 * (c[i] / 8);      // on a grid line
      else if (r == 1) c[i] = 8 * (c[i] / 8) + 4;  // on a centre line
    }
    if (pick(rng) == 0) c[2] = c[0];  // vertical segment (often on a line)
    if (pick(rng) == 0) c[3] = c[1];  // horizontal
    if (pick(rng) == 0) {             // a diagonal through corners
      const long long d = 8 * (1 + pick(rng));
      c[2] = c[0] + d, c[3] = c[1] + (trial % 2 ? d : -d);
    }
    on_lines += c[0] % 8 == 0 || c[2] % 8 == 0;
    const Segment s{c[0] / 8.0, c[1] / 8.0, c[2] / 8.0, c[3] / 8.0};
    BoundaryMasks m(w, h, true);
    rasterize_edges(m, std::span<const Segment>(&s, 1));
    const BoundaryMasks b = brute_masks_eighths(w, h, c[0], c[1], c[2], c[3]);
    ASSERT_EQ(m.top, b.top) << trial << ": " << s.x0 << "," << s.y0 << " " << s.x1 << "," << s.y1;
    ASSERT_EQ(m.left, b.left) << trial << ": " << s.x0 << "," << s.y0 << " " << s.x1 << "," << s.y1;
    ASSERT_EQ(m.centre_h, b.centre_h) << trial;
    ASSERT_EQ(m.centre_v, b.centre_v) << trial;
    for (int k = 0; k <= 2 * w; ++k) {  // count exact ties on vertical lines, so the test is known to reach them
      const long long L = 4LL * k, dx = c[2] - c[0];
      if ((c[0] < L) != (c[2] < L) && ((c[1] * dx + (L - c[0]) * (c[3] - c[1])) % dx == 0)) ++ties;
    }
  }
  EXPECT_GT(on_lines, 1000);
  EXPECT_GT(ties, 1000);
}

TEST(Rasterize, ParallelBandsMatchTheSerialRasterizer) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-10.0, 90.0), v(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Segment> segments;
    for (int i = 0; i < 300; ++i) {
      const double x = u(rng), y = u(rng), len = v(rng) < 0.5 ? 3 * v(rng) : 80 * v(rng), a = 6.3 * v(rng);
      segments.push_back({x, y, x + len * std::cos(a), y + len * std::sin(a)});
    }
    segments.push_back({3.0, 5.0, 40.0, 5.0});   // on a grid line
    segments.push_back({1.0, 1.0, 60.0, 60.0});  // through corners
    BoundaryMasks serial(77, 61, true);
    rasterize_edges(serial, segments);
    for (auto [rows, threads] : {std::pair{1, 2}, {3, 1}, {7, 2}, {64, 2}, {1000, 1}}) {
      BoundaryMasks parallel(77, 61, true);
      rasterize_edges_parallel(parallel, segments, rows, threads);
      ASSERT_EQ(serial.top, parallel.top) << rows;
      ASSERT_EQ(serial.left, parallel.left) << rows;
      ASSERT_EQ(serial.centre_h, parallel.centre_h) << rows;
      ASSERT_EQ(serial.centre_v, parallel.centre_v) << rows;
    }
  }
}

// A single straight line makes every pixel empty or simple, and each simple pixel's
// reconstructed edge ends within 1/16 pixel of the true line.
TEST(Rasterize, StraightLinesReconstructWithinAnEighth) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const double a = u(rng) * 6.283185307179586;
    const double cx = 8 + 16 * u(rng), cy = 8 + 16 * u(rng);
    const Segment s{cx - 60 * std::cos(a), cy - 60 * std::sin(a), cx + 60 * std::cos(a), cy + 60 * std::sin(a)};
    BoundaryMasks m(32, 32, false);
    rasterize_edges(m, std::span<const Segment>(&s, 1));
    const double len = std::hypot(s.x1 - s.x0, s.y1 - s.y0);
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        uint8_t sides[4];
        m.pixel_sides(x, y, sides);
        const geom::CellClass c = geom::classify_cell(sides, 8);
        ASSERT_NE(c.kind, CellKind::complex) << trial << " " << x << "," << y;
        if (c.kind != CellKind::simple) continue;
        for (int p : {c.p_low, c.p_high}) {
          const geom::Vec2 e = geom::boundary_point(p, 8, 0.5);
          const double dist =
              std::abs((s.x1 - s.x0) * (y + e.y - s.y0) - (s.y1 - s.y0) * (x + e.x - s.x0)) / len;
          ASSERT_LE(dist, 1.0 / 16 + 1e-9) << trial << " " << x << "," << y;
        }
      }
  }
}

TEST(Rasterize, EdgeOnAHorizontalGridLineBelongsToTheRowBelow) {
  BoundaryMasks m(16, 16, false);
  const Segment s{2.0, 5.0, 9.0, 5.0};
  rasterize_edges(m, std::span<const Segment>(&s, 1));
  for (int x = 0; x < 16; ++x) {
    EXPECT_EQ(kind_of(m, x, 4), CellKind::empty) << x;
    EXPECT_EQ(kind_of(m, x, 5), x >= 3 && x <= 8 ? CellKind::simple : CellKind::empty) << x;
  }
  uint8_t sides[4];
  m.pixel_sides(5, 5, sides);
  EXPECT_EQ(sides[1], 1);  // right side, first eighth
  EXPECT_EQ(sides[3], 1);
  EXPECT_EQ(sides[0] | sides[2], 0);
}

TEST(Rasterize, EdgeOnAVerticalGridLineBelongsToTheColumnRight) {
  BoundaryMasks m(16, 16, false);
  const Segment s{5.0, 12.0, 5.0, 1.0};
  rasterize_edges(m, std::span<const Segment>(&s, 1));
  for (int y = 0; y < 16; ++y) {
    EXPECT_EQ(kind_of(m, 4, y), CellKind::empty) << y;
    EXPECT_EQ(kind_of(m, 5, y), y >= 2 && y <= 11 ? CellKind::simple : CellKind::empty) << y;
  }
}

TEST(Rasterize, DiagonalThroughCorners) {
  BoundaryMasks m(12, 12, false);
  const Segment s{1.0, 1.0, 9.0, 9.0};
  rasterize_edges(m, std::span<const Segment>(&s, 1));
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 12; ++x) {
      uint8_t sides[4];
      m.pixel_sides(x, y, sides);
      const geom::CellClass c = geom::classify_cell(sides, 8);
      if (x == y && x >= 2 && x <= 8) {  // the diagonal: top-left corner to bottom-right corner
        ASSERT_EQ(c.kind, CellKind::simple);
        EXPECT_EQ(c.p_low, 0);
        EXPECT_EQ(c.p_high, 15);
      } else if (x == y + 1 && x >= 2 && x <= 9) {  // the shift leaves a sliver at the corner
        ASSERT_EQ(c.kind, CellKind::simple) << x << "," << y;
        EXPECT_LT(geom::area_a(geom::cell_edge(c.p_low, c.p_high, 8)), 0.01);
      } else {
        EXPECT_EQ(c.kind, CellKind::empty) << x << "," << y;
      }
    }
}

TEST(Rasterize, EdgesShorterThanAnEighthLeavePixelsEmpty) {
  BoundaryMasks m(8, 8, true);
  std::vector<Segment> tiny{{3.2, 3.3, 3.29, 3.31}, {4.97, 2.5, 5.06, 2.52}, {2.01, 1.99, 2.03, 2.05}};
  rasterize_edges(m, tiny);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_EQ(kind_of(m, x, y), CellKind::empty) << x << "," << y;
}

TEST(Rasterize, HundredsOfEdgesInOnePixelMakeItComplex) {
  BoundaryMasks m(4, 4, true);
  std::vector<Segment> many;
  for (int i = 0; i < 300; ++i) {
    const double a = i * 0.0209;
    many.push_back({1.5 - std::cos(a), 1.5 - std::sin(a), 1.5 + std::cos(a), 1.5 + std::sin(a)});
  }
  rasterize_edges(m, many);
  EXPECT_EQ(kind_of(m, 1, 1), CellKind::complex);
}

TEST(Rasterize, NearHorizontalAndNearVerticalEdges) {
  for (int vertical = 0; vertical < 2; ++vertical) {
    BoundaryMasks m(64, 64, false);
    Segment s{-1.0, 10.3, 65.0, 10.3 + 66e-4};
    if (vertical) s = {s.y0, s.x0, s.y1, s.x1};
    rasterize_edges(m, std::span<const Segment>(&s, 1));
    for (int i = 0; i < 64; ++i) {
      uint8_t sides[4];
      vertical ? m.pixel_sides(10, i, sides) : m.pixel_sides(i, 10, sides);
      const geom::CellClass c = geom::classify_cell(sides, 8);
      ASSERT_EQ(c.kind, CellKind::simple) << i;
      // 0.3 of a pixel lies in the third eighth.
      EXPECT_EQ(c.p_low, vertical ? 2 : 8 + 2) << i;
      EXPECT_EQ(c.p_high, vertical ? 16 + 5 : 24 + 5) << i;
    }
  }
}

TEST(Rasterize, FarAwayAndHugeSegmentsAreSafe) {
  BoundaryMasks m(8, 8, true);
  std::vector<Segment> far{{-1e12, 3.5, 1e12, 3.5}, {100, 100, 200, 300}, {-1e12, -1e12, -1e11, 1e12}};
  rasterize_edges(m, far);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_EQ(kind_of(m, x, y), y == 3 ? CellKind::simple : CellKind::empty);
  const Segment bad{0, 0, std::nan(""), 1};
  EXPECT_THROW(rasterize_edges(m, std::span<const Segment>(&bad, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace epi

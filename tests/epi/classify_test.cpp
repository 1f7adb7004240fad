// Classification's corner rule (docs/epi.md, "Corners"): two crossings on different sides make a
// pixel simple unless the centre lines show the edge leaving the chord between them.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "epi/classify.h"
#include "epi/rasterize.h"
#include "epi/tables.h"

namespace epi {
namespace {

CellKind classify(const BoundaryMasks& m, int x, int y) { return classify_pixel(m, x, y, 0).kind; }

// The Cornell box's lamp corner as the renderer drew it (docs/render.md, "Bright colours"): two
// edges leave (39.494, 12.038), one to the right, one down; pixel (39, 12) has one crossing on
// its right side and one on its bottom, whose chord passes far below-right of the corner.
TEST(ClassifyCorner, TheLampCornerPixelIsComplex) {
  for (bool centre_lines : {false, true}) {
    BoundaryMasks m(64, 32, centre_lines);
    const std::vector<Segment> lamp = {{39.494, 12.038, 55.0, 12.038}, {39.494, 12.038, 40.283, 15.374}};
    rasterize_edges(m, lamp);
    // Without centre lines the paper's rule stands (nothing else to go by).
    EXPECT_EQ(classify(m, 39, 12), centre_lines ? CellKind::complex : CellKind::simple);
    // Pixels the edges cross straight stay simple.
    EXPECT_EQ(classify(m, 45, 12), CellKind::simple);
    EXPECT_EQ(classify(m, 39, 13), CellKind::simple);
  }
}

// Distance from p to the line through a and b.
double line_distance(double ax, double ay, double bx, double by, double px, double py) {
  return std::abs((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / std::hypot(bx - ax, by - ay);
}

// No straight edge is ever made complex: random segments of every slope, and the awkward ones
// (on grid lines, on centre lines, through pixel corners, at 45 degrees), one at a time.
TEST(ClassifyCorner, StraightEdgesStaySimple) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 16.0);
  std::uniform_int_distribution<int> k(1, 15);
  std::vector<Segment> cases;
  for (int i = 0; i < 3000; ++i) cases.push_back({u(rng) - 4, u(rng) - 4, u(rng) + 4, u(rng) + 4});
  for (int i = 0; i < 300; ++i) {
    const double a = k(rng), b = k(rng), c = k(rng);
    cases.push_back({a, -1.0, a, 17.0});                      // on a grid line
    cases.push_back({a + 0.5, -1.0, a + 0.5 + 1e-9 * b, 17.0});  // on a centre line, nearly
    cases.push_back({-1.0, b + 0.5, 17.0, b + 0.5 + 1e-7});
    cases.push_back({a - 8, b - 8, a + 8, b + 8});             // through pixel corners
    cases.push_back({a + c / 16.0, -1.0, a - c / 16.0 + 3.0, 17.0});
  }
  int simple_pixels = 0;
  for (const Segment& s : cases) {
    BoundaryMasks plain(16, 16, false), centre(16, 16, true);
    rasterize_edges(plain, {&s, 1});
    rasterize_edges(centre, {&s, 1});
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const CellKind expected = classify(plain, x, y);
        simple_pixels += expected == CellKind::simple;
        ASSERT_EQ(classify(centre, x, y), expected)
            << "pixel " << x << "," << y << " of segment " << s.x0 << "," << s.y0 << " - " << s.x1 << "," << s.y1;
      }
  }
  EXPECT_GT(simple_pixels, 30000);
}

// Random corners inside a pixel: a vertex c and two edges leaving it through different sides.
// Whenever an edge crosses a centre line farther from the chord of the true exit points than the
// tolerance plus the 1/8 the quantization can hide (1/16 for the chord, 1/16 for the crossing),
// the pixel must be complex; a corner whose edges stay within the tolerance everywhere stays simple.
TEST(ClassifyCorner, CornersFarFromTheirChordAreComplex) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.02, 0.98), angle(0.0, 2.0 * M_PI);
  int complex_seen = 0, simple_seen = 0;
  for (int i = 0; i < 20000; ++i) {
    const double cx = 5 + u(rng), cy = 5 + u(rng);
    const double a0 = angle(rng), a1 = angle(rng);
    const Segment e0{cx, cy, cx + 8 * std::cos(a0), cy + 8 * std::sin(a0)};
    const Segment e1{cx, cy, cx + 8 * std::cos(a1), cy + 8 * std::sin(a1)};
    // Where each edge leaves pixel (5, 5), and which side.
    auto exit = [&](const Segment& e, double& ex, double& ey) {
      const double dx = e.x1 - e.x0, dy = e.y1 - e.y0;
      double t = 1e9;
      if (dx > 0) t = std::min(t, (6 - e.x0) / dx);
      if (dx < 0) t = std::min(t, (5 - e.x0) / dx);
      if (dy > 0) t = std::min(t, (6 - e.y0) / dy);
      if (dy < 0) t = std::min(t, (5 - e.y0) / dy);
      ex = e.x0 + t * dx, ey = e.y0 + t * dy;
    };
    double x0, y0, x1, y1;
    exit(e0, x0, y0);
    exit(e1, x1, y1);
    // Keep exits clear of the pixel's corners and of each other (one crossing per side).
    auto side = [](double x, double y) { return y < 5.001 ? 0 : x > 5.999 ? 1 : y > 5.999 ? 2 : 3; };
    auto near_corner = [](double x, double y) {
      return std::min(std::abs(x - 5), std::abs(x - 6)) < 0.15 && std::min(std::abs(y - 5), std::abs(y - 6)) < 0.15;
    };
    if (side(x0, y0) == side(x1, y1) || near_corner(x0, y0) || near_corner(x1, y1)) continue;
    // The true crossings of the centre lines, and their distance from the chord.
    double worst = 0.0;
    for (const Segment& e : {e0, e1}) {
      const double dx = e.x1 - e.x0, dy = e.y1 - e.y0;
      double tx, ty;
      exit(e, tx, ty);
      const double t_exit = std::abs(dx) > std::abs(dy) ? (tx - e.x0) / dx : (ty - e.y0) / dy;
      if (dx != 0) {
        const double t = (5.5 - e.x0) / dx;
        if (t > 0 && t < t_exit) worst = std::max(worst, line_distance(x0, y0, x1, y1, 5.5, e.y0 + t * dy));
      }
      if (dy != 0) {
        const double t = (5.5 - e.y0) / dy;
        if (t > 0 && t < t_exit) worst = std::max(worst, line_distance(x0, y0, x1, y1, e.x0 + t * dx, 5.5));
      }
    }
    BoundaryMasks m(12, 12, true);
    const std::vector<Segment> corner = {e0, e1};
    rasterize_edges(m, corner);
    const CellKind kind = classify(m, 5, 5);
    if (worst > kChordTolerance + 0.125 + 1e-9) {
      ASSERT_EQ(kind, CellKind::complex) << "corner " << cx << "," << cy << " angles " << a0 << "," << a1;
      ++complex_seen;
    } else if (worst < kChordTolerance - 0.125 - 1e-9) {
      ASSERT_EQ(kind, CellKind::simple) << "corner " << cx << "," << cy << " angles " << a0 << "," << a1;
      ++simple_seen;
    }
  }
  EXPECT_GT(complex_seen, 1000);
  EXPECT_GT(simple_seen, 100);
}

// The table against its definition, from the chord's end points.
TEST(ClassifyCorner, CentreOnChordTableMatchesTheDistanceRule) {
  const EpiTables& t = epi_tables();
  int checked = 0;
  for (int code = 0; code < kCodeCount; ++code) {
    if (!code_is_simple(code)) {
      EXPECT_EQ(t.centre_on_chord[code], 0xffff) << code;
      continue;
    }
    const geom::Vec2 a = geom::boundary_point(code_low(code), 8, 0.5), b = geom::boundary_point(code_high(code), 8, 0.5);
    for (int m = 0; m < 8; ++m) {
      const double along = (m + 0.5) / 8;
      EXPECT_EQ(bool(t.centre_on_chord[code] >> m & 1), line_distance(a.x, a.y, b.x, b.y, along, 0.5) <= kChordTolerance + 1e-12)
          << code << " h " << m;
      EXPECT_EQ(bool(t.centre_on_chord[code] >> (8 + m) & 1), line_distance(a.x, a.y, b.x, b.y, 0.5, along) <= kChordTolerance + 1e-12)
          << code << " v " << m;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 8 * 384);
}

}  // namespace
}  // namespace epi

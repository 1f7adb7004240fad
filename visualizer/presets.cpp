#include "presets.h"

#include <cmath>
#include <numbers>

namespace epi::vis {

namespace {

using Point = std::array<double, 2>;
constexpr std::array<float, 3> kCream{0.85f, 0.80f, 0.62f}, kBlue{0.08f, 0.22f, 0.60f}, kRed{0.70f, 0.10f, 0.08f},
    kGreen{0.10f, 0.45f, 0.15f}, kDark{0.05f, 0.05f, 0.07f};

Polygon polygon(std::array<float, 3> color, std::vector<Point> points) { return {color, std::move(points)}; }

Polygon disc(std::array<float, 3> color, double cx, double cy, double r, int n = 64) {
  Polygon p{color, {}};
  for (int k = 0; k < n; ++k) {
    const double a = 2 * std::numbers::pi * k / n;
    p.points.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  return p;
}

Pattern checkerboard() {
  Pattern p{20, 20, kCream, {}};
  const double a = 20 * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a), size = 5;
  auto at = [&](double u, double v) { return Point{10 + c * u - s * v, 10 + s * u + c * v}; };
  for (int i = -4; i < 4; ++i)
    for (int j = -4; j < 4; ++j)
      if ((i + j) & 1)
        p.polygons.push_back(polygon(kBlue, {at(i * size, j * size), at((i + 1) * size, j * size),
                                             at((i + 1) * size, (j + 1) * size), at(i * size, (j + 1) * size)}));
  return p;
}

Pattern wedges() {
  Pattern p{24, 20, kCream, {}};
  const double cx = 2.3, cy = 17.6;
  const std::array<float, 3> colors[3] = {kBlue, kRed, kGreen};
  for (int k = 0; k < 3; ++k) {
    const double a0 = -0.12 - 0.42 * k, a1 = a0 - 0.16 - 0.05 * k;  // thin wedges fanning out
    p.polygons.push_back(polygon(colors[k], {{cx, cy}, {cx + 30 * std::cos(a0), cy + 30 * std::sin(a0)},
                                             {cx + 30 * std::cos(a1), cy + 30 * std::sin(a1)}}));
  }
  return p;
}

Pattern slivers() {
  Pattern p{24, 20, kCream, {}};
  const double widths[4] = {0.3, 0.6, 1.0, 2.0};
  double y = 3.2;
  for (double w : widths) {  // strips rising 1 px over the image width
    p.polygons.push_back(polygon(kBlue, {{0, y}, {24, y - 1.0}, {24, y - 1.0 + w}, {0, y + w}}));
    y += 4.3;
  }
  return p;
}

Pattern t_junction() {
  Pattern p{20, 20, kCream, {}};
  p.polygons.push_back(polygon(kBlue, {{0, 10.35}, {20, 9.1}, {20, 20}, {0, 20}}));
  p.polygons.push_back(polygon(kRed, {{10.2, 9.74}, {20, 9.1}, {20, 20}, {11.4, 20}}));
  return p;
}

Pattern tangent() {
  Pattern p{20, 20, kCream, {}};
  p.polygons.push_back(disc(kBlue, 9.6, 8.3, 7.0));
  p.polygons.push_back(polygon(kRed, {{0, 15.65}, {20, 15.2}, {20, 20}, {0, 20}}));  // 0.1-0.3 px below the disc
  return p;
}

Pattern corners() {
  Pattern p{20, 20, kCream, {}};
  p.polygons.push_back(polygon(kBlue, {{2, 18}, {10, 2}, {18, 18}}));  // slope 2: through corners
  p.polygons.push_back(polygon(kRed, {{6, 10}, {14, 18}, {6, 18}}));  // 45 degrees: corner to corner
  return p;
}

Pattern borders() {
  Pattern p{20, 20, kCream, {}};
  p.polygons.push_back(polygon(kBlue, {{4, 4}, {13, 4}, {13, 13}, {4, 13}}));    // on grid lines
  p.polygons.push_back(polygon(kDark, {{8, 8}, {17, 8}, {17, 8.5}, {8, 8.5}}));  // ends on the lines
  return p;
}

}  // namespace

const std::vector<Preset>& presets() {
  static const std::vector<Preset> list = {
      {"checkerboard", "A rotated checkerboard: simple pixels along straight edges, complex pixels at the corners.", 10, 7, checkerboard()},
      {"wedges", "Thin wedges from one point: many edges meet in a few pixels, so pixels turn complex.", 5, 16, wedges()},
      {"slivers", "Strips 0.3, 0.6, 1 and 2 px wide: slivers thinner than a pixel hold no sample of their own.", 11, 7, slivers()},
      {"t-junction", "A T-junction: three regions meet, the junction pixel is complex.", 10, 9, t_junction()},
      {"tangent", "Two nearly tangent edges: a disc 0.1-0.3 px above a straight edge.", 9, 15, tangent()},
      {"corners", "Edges through pixel corners: slopes 2 and 1 cut the grid exactly at corners.", 6, 14, corners()},
      {"borders", "Edges along pixel borders: a square on grid lines and a bar ending on them.", 8, 8, borders()},
  };
  return list;
}

const Preset* find_preset(const std::string& name) {
  for (const Preset& p : presets())
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace epi::vis

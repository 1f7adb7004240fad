#include "epi/geometry.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <vector>

namespace epi::geom {

Vec2 perimeter_point(double u, int n) {
  const int side = std::min(3, int(u / n));
  const double s = (u - side * n) / n;
  switch (side) {
    case 0: return {s, 0.0};
    case 1: return {1.0, s};
    case 2: return {1.0 - s, 1.0};
    default: return {0.0, 1.0 - s};
  }
}

Vec2 boundary_point(int p, int n, double t) { return perimeter_point(p + t, n); }

CellEdge cell_edge(int p_low, int p_high, int n) {
  CellEdge e{p_low, p_high, n, boundary_point(p_low, n, 0.5), boundary_point(p_high, n, 0.5), 1.0};
  // The middle of the arc from p_low to p_high is strictly inside region A.
  const Vec2 mid = perimeter_point(0.5 * (p_low + p_high + 1.0), n);
  e.sign_a = orient(e.a, e.b, mid) >= 0.0 ? 1.0 : -1.0;
  return e;
}

double area_a(const CellEdge& e) {
  // Polygon: a, the corners on the arc, b.
  Vec2 poly[5] = {e.a};
  size_t count = 1;
  const double from = e.p_low + 0.5, to = e.p_high + 0.5;
  for (int k = 1; k < 4; ++k)
    if (k * e.n > from && k * e.n < to) poly[count++] = perimeter_point(k * e.n, e.n);
  poly[count++] = e.b;
  double twice = 0.0;
  for (size_t i = 0; i < count; ++i) {
    const Vec2 p = poly[i], q = poly[(i + 1) % count];
    twice += p.x * q.y - q.x * p.y;
  }
  return std::abs(twice) * 0.5;
}

int square_side(const CellEdge& e, double x0, double y0, double size) {
  // orient(p, q, x) is affine in each of the four parameters (p along its segment, q along its
  // segment, x's two coordinates), so its extremes over the box are at the 16 vertices.
  bool all_a = true, all_b = true;
  for (int s = 0; s < 2; ++s)
    for (int t = 0; t < 2; ++t) {
      const Vec2 p = boundary_point(e.p_low, e.n, s), q = boundary_point(e.p_high, e.n, t);
      for (int c = 0; c < 4; ++c) {
        const Vec2 x{x0 + (c & 1) * size, y0 + (c >> 1) * size};
        const double o = e.sign_a * orient(p, q, x);
        all_a = all_a && o > 0.0;
        all_b = all_b && o < 0.0;
      }
    }
  return all_a ? 0 : (all_b ? 1 : 2);
}

double square_fraction_on_side(const CellEdge& e, int region, double x0, double y0) {
  // Clip the square by the half-plane (Sutherland-Hodgman against one line).
  const double sign = region == 0 ? e.sign_a : -e.sign_a;
  const std::vector<Vec2> square{{x0, y0}, {x0 + 1, y0}, {x0 + 1, y0 + 1}, {x0, y0 + 1}};
  std::vector<Vec2> out;
  for (size_t i = 0; i < 4; ++i) {
    const Vec2 p = square[i], q = square[(i + 1) % 4];
    const double fp = sign * orient(e.a, e.b, p), fq = sign * orient(e.a, e.b, q);
    if (fp >= 0) out.push_back(p);
    if ((fp >= 0) != (fq >= 0)) {
      const double t = fp / (fp - fq);
      out.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
    }
  }
  double twice = 0.0;
  for (size_t i = 0; i < out.size(); ++i) {
    const Vec2 p = out[i], q = out[(i + 1) % out.size()];
    twice += p.x * q.y - q.x * p.y;
  }
  return std::abs(twice) * 0.5;
}

CellClass classify_cell(const uint8_t masks[4], int n) {
  // Bit counts by table: the baseline x86-64 target has no popcnt instruction.
  static constexpr auto kBits = [] {
    std::array<uint8_t, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = uint8_t(std::popcount(unsigned(i)));
    return t;
  }();
  int count = 0;
  for (int s = 0; s < 4; ++s) count += kBits[masks[s]];
  if (count <= 1) return {CellKind::empty, 0, 0};  // no edge, or one that ends inside
  if (count > 2) return {CellKind::complex, 0, 0};
  int positions[2], found = 0;
  for (int s = 0; s < 4; ++s)
    for (int bit = 0; bit < n; ++bit)
      if (masks[s] >> bit & 1) positions[found++] = boundary_position(s, bit, n);
  const int lo = std::min(positions[0], positions[1]), hi = std::max(positions[0], positions[1]);
  if (lo / n == hi / n) return {CellKind::complex, 0, 0};
  return {CellKind::simple, lo, hi};
}

}  // namespace epi::geom

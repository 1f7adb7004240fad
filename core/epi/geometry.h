// Edge codes and the geometry of one boundary cell (a pixel, or a sub-pixel of the complex
// filter). A cell is the unit square [0,1]^2, y down; each side is cut into n segments
// (n = 8 for pixels, 4 for sub-pixels). Boundary positions run clockwise on screen:
//   top 0..n-1 (left to right), right n..2n-1 (top to bottom),
//   bottom 2n..3n-1 (right to left), left 3n..4n-1 (bottom to top).
// A simple cell's edge joins the centres of two segments on different sides, p_low < p_high.
// Region A is bounded by the boundary arc from p_low clockwise to p_high, region B by the rest.
// Pixel edge codes (n = 8): (p_low << 5) | p_high; same-side pairs are reserved:
//   0 = empty (both ends at position 0), 1 = complex (positions 0 and 1).
#pragma once

#include <cstdint>

namespace epi {

enum class CellKind : uint8_t { empty, simple, complex };

constexpr int kEmptyCode = 0;
constexpr int kComplexCode = 1;
constexpr int kCodeCount = 1024;

// Pixel types: the 4 bits of a code that neighbour reachability needs, plus the primary side.
constexpr int kTypeEmpty = 0;
constexpr int kTypeComplex = 1;
// Simple: 2 + 2 * side_pair + (primary is B); side pairs in order (0,1) (0,2) (0,3) (1,2) (1,3) (2,3).
constexpr int side_pair_index(int side_low, int side_high) {
  return side_low == 0 ? side_high - 1 : (side_low == 1 ? side_high + 1 : 5);
}
constexpr int simple_type(int side_low, int side_high, bool primary_is_b) {
  return 2 + 2 * side_pair_index(side_low, side_high) + (primary_is_b ? 1 : 0);
}
constexpr bool type_is_simple(int type) { return type >= 2 && type < 14; }

constexpr int code_low(int code) { return code >> 5; }
constexpr int code_high(int code) { return code & 31; }
constexpr int make_code(int p_low, int p_high) { return (p_low << 5) | p_high; }
constexpr bool code_is_simple(int code) { return code_low(code) / 8 < code_high(code) / 8; }

// Side 0 top, 1 right, 2 bottom, 3 left; mask bit m counts along increasing x or y.
constexpr int boundary_position(int side, int bit, int n) {
  return side == 0 ? bit : side == 1 ? n + bit : side == 2 ? 2 * n + (n - 1 - bit) : 3 * n + (n - 1 - bit);
}

namespace geom {

struct Vec2 {
  double x, y;
};

// The point at parameter t in [0,1] along segment p (clockwise direction).
Vec2 boundary_point(int p, int n, double t);
// The point at a continuous clockwise perimeter coordinate u in [0, 4n).
Vec2 perimeter_point(double u, int n);
// Twice the signed area of triangle (a, b, c).
inline double orient(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// A simple cell's reconstructed edge.
struct CellEdge {
  int p_low, p_high, n;
  Vec2 a, b;      // segment centres
  double sign_a;  // sign of orient(a, b, x) for x in region A
};
CellEdge cell_edge(int p_low, int p_high, int n);

// 0 region A, 1 region B (points on the edge line count as A).
inline int region_of(const CellEdge& e, Vec2 x) { return e.sign_a * orient(e.a, e.b, x) >= 0.0 ? 0 : 1; }

// Area of region A in the unit cell.
double area_a(const CellEdge& e);

// Which region the square [x0,x0+size]x[y0,y0+size] lies in for every edge whose ends lie anywhere
// in the two boundary segments: 0 A, 1 B, 2 ambiguous.
int square_side(const CellEdge& e, double x0, double y0, double size);

// Area of the part of the square [x0,x0+1]x[y0,y0+1] on region R's side of e's (extended) line.
double square_fraction_on_side(const CellEdge& e, int region, double x0, double y0);

// Classification of a cell from its four side masks (top, right, bottom, left; n bits each).
struct CellClass {
  CellKind kind;
  int p_low, p_high;
};
CellClass classify_cell(const uint8_t masks[4], int n);

}  // namespace geom
}  // namespace epi

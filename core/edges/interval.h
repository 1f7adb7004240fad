// Interval arithmetic in double, rounded outward: every computed bound moves at least one ulp away
// from the value, so an interval always contains the exact real result (see docs/edges.md).
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace epi::edges {

inline double round_down(double x) { return x - (std::fabs(x) * 0x1p-52 + DBL_TRUE_MIN); }
inline double round_up(double x) { return x + (std::fabs(x) * 0x1p-52 + DBL_TRUE_MIN); }

struct Interval {
  double lo = 0.0, hi = 0.0;
  static Interval point(double x) { return {x, x}; }
  bool contains_zero_within(double margin) const { return lo <= margin && hi >= -margin; }
};

inline Interval operator+(Interval a, Interval b) { return {round_down(a.lo + b.lo), round_up(a.hi + b.hi)}; }
inline Interval operator-(Interval a, Interval b) { return {round_down(a.lo - b.hi), round_up(a.hi - b.lo)}; }
inline Interval operator*(Interval a, Interval b) {
  const double p0 = a.lo * b.lo, p1 = a.lo * b.hi, p2 = a.hi * b.lo, p3 = a.hi * b.hi;
  return {round_down(std::min(std::min(p0, p1), std::min(p2, p3))), round_up(std::max(std::max(p0, p1), std::max(p2, p3)))};
}

}  // namespace epi::edges

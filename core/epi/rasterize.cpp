#include "epi/rasterize.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace epi {

BoundaryMasks::BoundaryMasks(int w, int h, bool with_centre_lines) : width(w), height(h), centre_lines(with_centre_lines) {
  const size_t n = size_t(w + 1) * size_t(h + 1);
  top.assign(n, 0);
  left.assign(n, 0);
  if (centre_lines) {
    centre_h.assign(n, 0);
    centre_v.assign(n, 0);
  }
}

void BoundaryMasks::clear() {
  std::fill(top.begin(), top.end(), 0);
  std::fill(left.begin(), left.end(), 0);
  std::fill(centre_h.begin(), centre_h.end(), 0);
  std::fill(centre_v.begin(), centre_v.end(), 0);
}

namespace {

// Integer range [first, last] of k with lo < k + offset <= hi, clipped to [kmin, kmax].
void crossed_lines(double lo, double hi, double offset, int kmin, int kmax, int& first, int& last) {
  const double f = std::floor(std::clamp(lo - offset, kmin - 2.0, kmax + 2.0)) + 1.0;
  const double l = std::floor(std::clamp(hi - offset, kmin - 2.0, kmax + 2.0));
  first = std::max(kmin, int(f));
  last = std::min(kmax, int(l));
}

// Eighth-pixel index of coordinate v along a line, floor(8 v); when v sits exactly on a piece
// boundary and the shift moves it backwards, the piece before.
long long eighth(double v, bool tie_goes_back) {
  const double e = v * 8.0;
  double q = std::floor(e);
  if (tie_goes_back && q == e) q -= 1.0;
  return (long long)q;
}

long long floor_div8(long long q) { return q >= 0 ? q / 8 : -((-q + 7) / 8); }

}  // namespace

void rasterize_edges(BoundaryMasks& m, std::span<const Segment> segments) {
  const int w = m.width, h = m.height;
  for (const Segment& s : segments) {
    if (!std::isfinite(s.x0) || !std::isfinite(s.y0) || !std::isfinite(s.x1) || !std::isfinite(s.y1))
      throw std::invalid_argument("edge segment with a non-finite coordinate");
    const double dx = s.x1 - s.x0, dy = s.y1 - s.y0;
    // Vertical lines x = k (and x = k + 1/2): the y of the crossing, shifted back when the
    // segment descends (the +e shift in x moves the crossing up by e * slope).
    const bool descends = (dx > 0) == (dy > 0) && dy != 0;
    auto vertical = [&](double line_x, std::vector<uint8_t>& plane, int k) {
      const double y = std::clamp(s.y0 + (line_x - s.x0) * dy / dx, -16.0, h + 16.0);
      const long long q = eighth(y, descends);
      const long long row = floor_div8(q);
      if (row < 0 || row >= h) return;
      plane[m.index(k, int(row))] |= uint8_t(1u << (q - row * 8));
    };
    auto horizontal = [&](double line_y, std::vector<uint8_t>& plane, int j) {
      const double x = std::clamp(s.x0 + (line_y - s.y0) * dx / dy, -16.0, w + 16.0);
      const long long q = eighth(x, false);
      const long long col = floor_div8(q);
      if (col < 0 || col >= w) return;
      plane[m.index(int(col), j)] |= uint8_t(1u << (q - col * 8));
    };
    const double xlo = std::min(s.x0, s.x1), xhi = std::max(s.x0, s.x1);
    const double ylo = std::min(s.y0, s.y1), yhi = std::max(s.y0, s.y1);
    int first, last;
    if (dx != 0) {
      crossed_lines(xlo, xhi, 0.0, 0, w, first, last);
      for (int k = first; k <= last; ++k) vertical(k, m.left, k);
      if (m.centre_lines) {
        crossed_lines(xlo, xhi, 0.5, 0, w - 1, first, last);
        for (int k = first; k <= last; ++k) vertical(k + 0.5, m.centre_v, k);
      }
    }
    if (dy != 0) {
      crossed_lines(ylo, yhi, 0.0, 0, h, first, last);
      for (int j = first; j <= last; ++j) horizontal(j, m.top, j);
      if (m.centre_lines) {
        crossed_lines(ylo, yhi, 0.5, 0, h - 1, first, last);
        for (int j = first; j <= last; ++j) horizontal(j + 0.5, m.centre_h, j);
      }
    }
  }
}

}  // namespace epi

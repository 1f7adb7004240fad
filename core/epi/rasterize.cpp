#include "epi/rasterize.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

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

// Integer range [first, last] of k with lo < k + offset <= hi, clipped to [kmin, kmax]; and line 0
// (the image's top or left border) when lo lies exactly on it: a segment that starts on the border
// (a clipped edge, a pattern's edge) must separate the first row or column as well
// (tests/extremes/large_image_test.cpp; before, the first row leaked across such an edge).
void crossed_lines(double lo, double hi, double offset, int kmin, int kmax, int& first, int& last) {
  const double f = offset == 0.0 && lo == 0.0 ? 0.0 : std::floor(std::clamp(lo - offset, kmin - 2.0, kmax + 2.0)) + 1.0;
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

namespace {

// The crossings whose cell row lies in [row_begin, row_end) (for the top line: lines
// row_begin .. row_end - 1, and line h too when row_end == h). Bands of rows own disjoint
// bytes, so they can run in parallel; each segment is clipped to the band's rows first.
void rasterize_rows(BoundaryMasks& m, std::span<const Segment> segments, int row_begin, int row_end) {
  const int w = m.width, h = m.height;
  const int last_top_line = row_end == h ? h : row_end - 1;
  for (const Segment& s : segments) {
    if (!std::isfinite(s.x0) || !std::isfinite(s.y0) || !std::isfinite(s.x1) || !std::isfinite(s.y1))
      throw std::invalid_argument("edge segment with a non-finite coordinate");
    const double dx = s.x1 - s.x0, dy = s.y1 - s.y0;
    const double ylo = std::min(s.y0, s.y1), yhi = std::max(s.y0, s.y1);
    if (yhi < row_begin - 1.0 || ylo > row_end + 1.0) continue;
    // Vertical lines x = k (and x = k + 1/2): the y of the crossing, shifted back when the
    // segment descends (the +e shift in x moves the crossing up by e * slope).
    const bool descends = (dx > 0) == (dy > 0) && dy != 0;
    auto vertical = [&](double line_x, std::vector<uint8_t>& plane, int k) {
      const double y = std::clamp(s.y0 + (line_x - s.x0) * dy / dx, -16.0, h + 16.0);
      const long long q = eighth(y, descends);
      const long long row = floor_div8(q);
      if (row < row_begin || row >= row_end) return;
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
    int first, last;
    if (dx != 0) {
      // The x-range of the part within a row of the band, widened by a pixel: only a bound
      // on which lines to try; the crossing test below uses the whole segment.
      double clip_lo = xlo, clip_hi = xhi;
      if (dy != 0) {
        const double ta = std::clamp((row_begin - 1.0 - s.y0) / dy, 0.0, 1.0);
        const double tb = std::clamp((row_end + 1.0 - s.y0) / dy, 0.0, 1.0);
        const double xa = s.x0 + ta * dx, xb = s.x0 + tb * dx;
        clip_lo = std::min(xa, xb) - 1.0, clip_hi = std::max(xa, xb) + 1.0;
      }
      const int clip_first = int(std::clamp(std::floor(clip_lo), -1.0, w + 1.0));
      const int clip_last = int(std::clamp(std::ceil(clip_hi), -1.0, w + 1.0));
      crossed_lines(xlo, xhi, 0.0, 0, w, first, last);
      first = std::max(first, clip_first), last = std::min(last, clip_last);
      for (int k = first; k <= last; ++k) vertical(k, m.left, k);
      if (m.centre_lines) {
        crossed_lines(xlo, xhi, 0.5, 0, w - 1, first, last);
        first = std::max(first, clip_first), last = std::min(last, clip_last);
        for (int k = first; k <= last; ++k) vertical(k + 0.5, m.centre_v, k);
      }
    }
    if (dy != 0) {
      crossed_lines(ylo, yhi, 0.0, row_begin, last_top_line, first, last);
      for (int j = first; j <= last; ++j) horizontal(j, m.top, j);
      if (m.centre_lines) {
        crossed_lines(ylo, yhi, 0.5, row_begin, row_end - 1, first, last);
        for (int j = first; j <= last; ++j) horizontal(j + 0.5, m.centre_h, j);
      }
    }
  }
}

}  // namespace

void rasterize_edges(BoundaryMasks& m, std::span<const Segment> segments) {
  rasterize_rows(m, segments, 0, m.height);
}

void rasterize_edges_parallel(BoundaryMasks& m, std::span<const Segment> segments, int rows_per_band, int threads) {
  for (const Segment& s : segments)  // fail before any thread starts
    if (!std::isfinite(s.x0) || !std::isfinite(s.y0) || !std::isfinite(s.x1) || !std::isfinite(s.y1))
      throw std::invalid_argument("edge segment with a non-finite coordinate");
  const int band_rows = std::max(1, rows_per_band);
  const int bands = (m.height + band_rows - 1) / band_rows;
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const tbb::blocked_range<int>& r) {
      for (int b = r.begin(); b != r.end(); ++b)
        rasterize_rows(m, segments, b * band_rows, std::min(m.height, (b + 1) * band_rows));
    }, tbb::simple_partitioner());
  });
}

}  // namespace epi

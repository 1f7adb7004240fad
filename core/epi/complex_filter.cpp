#include "epi/complex_filter.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <vector>
#include <utility>

#include "epi/complex_internal.h"
#include "epi/geometry.h"

namespace epi {

namespace complex_detail {

// The geometry of every simple sub-pixel edge, probed with kProbe (complex_internal.h).
const std::array<SubPixelGeometry, 256>& sub_pixel_geometry() {
  static const std::array<SubPixelGeometry, 256> table = [] {
    std::array<SubPixelGeometry, 256> t{};
    for (int lo = 0; lo < 16; ++lo)
      for (int hi = lo + 1; hi < 16; ++hi) {
        if (lo / 4 == hi / 4) continue;
        const geom::CellEdge e = geom::cell_edge(lo, hi, 4);
        SubPixelGeometry& g = t[size_t(lo * 16 + hi)];
        for (int k = 0; k < 2; ++k) {
          const double p = kProbe[k];
          g.probe[0][k] = uint8_t(geom::region_of(e, {1, p}));
          g.probe[1][k] = uint8_t(geom::region_of(e, {p, 1}));
          g.probe[2][k] = uint8_t(geom::region_of(e, {0, p}));
          g.probe[3][k] = uint8_t(geom::region_of(e, {p, 0}));
        }
        for (int side = 0; side < 4; ++side)
          for (int k = 0; k < 2; ++k) g.probe_bits = uint8_t(g.probe_bits | g.probe[side][k] << (2 * side + k));
        for (int q = 0; q < 4; ++q) g.quarter[q] = uint8_t(geom::square_side(e, (q & 1) * 0.5, (q >> 1) * 0.5, 0.5));
        g.area = float(geom::area_a(e));
      }
    return t;
  }();
  return table;
}

const std::array<float, 51>& sample_weights() {
  static const std::array<float, 51> table = [] {
    std::array<float, 51> t{};
    for (size_t i = 0; i < t.size(); ++i) {
      const float d2 = float(i);
      t[i] = 1.0f / ((1.0f + d2) * (1.0f + d2));
    }
    return t;
  }();
  return table;
}

const std::array<F8, 36>& window_weights() {
  static const std::array<F8, 36> table = [] {
    std::array<F8, 36> t{};
    for (int v = 0; v < kGrid; ++v)
      for (int u = 0; u < kGrid; ++u)
        for (int r = 0; r < 8; ++r) {
          const int du = u - (2 + (r & 1)), dv = v - (2 + ((r & 3) >> 1));
          t[size_t(v * kGrid + u)][r] = sample_weights()[size_t(du * du + dv * dv)];
        }
    return t;
  }();
  return table;
}

const std::array<uint64_t, 256>& spread_bits_to_bytes() {
  static const std::array<uint64_t, 256> table = [] {
    std::array<uint64_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i)
      for (int k = 0; k < 8; ++k) t[i] |= uint64_t((i >> k) & 1) << (8 * k);
    return t;
  }();
  return table;
}

const std::array<SubCell, 512>& sub_cells() {
  static const std::array<SubCell, 512> table = [] {
    std::array<SubCell, 512> t{};
    for (size_t k = 0; k < 256; ++k) t[k] = {0, uint16_t(CellKind::empty), uint8_t(CellKind::empty), 0, 0};
    for (size_t k = 256; k < 512; ++k) t[k] = {0, uint16_t(CellKind::complex), uint8_t(CellKind::complex), 0, 0xff};
    const auto& spread = spread_bits_to_bytes();
    const auto& geometry = sub_pixel_geometry();
    for (int a = 0; a < 16; ++a)
      for (int b = a + 1; b < 16; ++b) {
        const uint32_t i = 1u << a | 1u << b;
        const uint8_t sides[4] = {uint8_t(i & 15), uint8_t((i >> 4) & 15), uint8_t((i >> 8) & 15), uint8_t(i >> 12)};
        const geom::CellClass c = geom::classify_cell(sides, 4);
        const uint8_t code = c.kind == CellKind::simple ? uint8_t(c.p_low * 16 + c.p_high) : 0;
        uint8_t quarters = 0xff;
        if (c.kind != CellKind::complex) {
          quarters = 0;
          for (int q = 0; q < 4; ++q) quarters = uint8_t(quarters | geometry[code].quarter[q] << (2 * q));
        }
        t[size_t(a * 16 + b)] = {spread[geometry[code].probe_bits], uint16_t(int(c.kind) | c.p_low << 2 | c.p_high << 6),
                                 uint8_t(c.kind), code, quarters};
      }
    return t;
  }();
  return table;
}
}  // namespace complex_detail

using namespace complex_detail;

namespace {

struct SubPixel {
  CellKind kind = CellKind::complex;  // complex also stands for "outside the image"
  const SubPixelGeometry* geometry = nullptr;
  uint8_t probe_bits = 0;  // the geometry's (empty: 0, region 0 everywhere)
};


// The connected set of region `region` of `cell`: grown through the joins until it stops.
Regions connected(const Joins& joins, int cell, int region) {
  uint64_t c0 = region == 0 ? 1ull << cell : 0, c1 = region == 1 ? 1ull << cell : 0;
  for (;;) {
    uint64_t n0 = c0, n1 = c1;
    for (int dir = 0; dir < 2; ++dir) {
      const int s = dir == 0 ? 1 : kGrid;
      const std::array<uint64_t, 4>& m = joins[size_t(dir)];
      n0 |= ((c0 & m[0]) << s) | ((c1 & m[2]) << s) | ((c0 >> s) & m[0]) | ((c1 >> s) & m[1]);
      n1 |= ((c0 & m[1]) << s) | ((c1 & m[3]) << s) | ((c0 >> s) & m[2]) | ((c1 >> s) & m[3]);
    }
    if (n0 == c0 && n1 == c1) return {{c0, c1}};
    c0 = n0, c1 = n1;
  }
}

// The filter; with kTrace it records into *trace (complex_pixel_traced), without it compiles
// to the plain filter.
template <bool kTrace>
void complex_impl(const EpiRows& epi, const BoundaryMasks& masks, int x, int y, const float estimate[3], float out[3],
                  ComplexTrace* trace) {
  // Classify the 6x6 sub-pixels: each pixel's six mask bytes read once for its four.
  const std::array<SubPixelGeometry, 256>& geometry = sub_pixel_geometry();
  SubPixel sub[kGrid][kGrid];
  const size_t row_stride = size_t(masks.width) + 1;
  for (int py = y - 1; py <= y + 1; ++py)
    for (int px = x - 1; px <= x + 1; ++px) {
      if (!epi.inside(px, py)) continue;
      const size_t i = masks.index(px, py);
      const uint32_t top = masks.top[i], bottom = masks.top[i + row_stride], left = masks.left[i],
                     right = masks.left[i + 1], centre_h = masks.centre_h[i], centre_v = masks.centre_v[i];
      for (int sy = 0; sy < 2; ++sy)
        for (int sx = 0; sx < 2; ++sx) {
          const int u = 2 * (px - x + 1) + sx, v = 2 * (py - y + 1) + sy;
          const uint32_t t = half(sy == 0 ? top : centre_h, sx), r = half(sx == 0 ? centre_v : right, sy);
          const uint32_t b = half(sy == 0 ? centre_h : bottom, sx), l = half(sx == 0 ? left : centre_v, sy);
          const uint16_t c = sub_cell_class(t | r << 4 | b << 8 | l << 12);  // geom::classify_cell(sides, 4)
          SubPixel& s = sub[v][u];
          s.kind = CellKind(c & 3);
          if (s.kind == CellKind::simple) {
            s.geometry = &geometry[size_t(((c >> 2) & 15) * 16 + (c >> 6))];
            s.probe_bits = s.geometry->probe_bits;
          }
          if constexpr (kTrace)
            trace->sub[v][u].kind = CellKind(c & 3), trace->sub[v][u].p_low = (c >> 2) & 15, trace->sub[v][u].p_high = c >> 6;
        }
    }

  // Regions touching across a shared side are connected. A shared side holds at most one
  // crossing, at a piece centre in [1/8, 7/8]: probing both ends of the side meets every
  // region that touches it. Complex sub-pixels (and outside) join nothing.
  Joins joins{};
  for (int v = 0; v < kGrid; ++v)
    for (int u = 0; u < kGrid; ++u) {
      const SubPixel& a = sub[v][u];
      if (a.kind == CellKind::complex) continue;
      const uint64_t bit = 1ull << (v * kGrid + u);
      for (int dir = 0; dir < 2; ++dir) {
        const int bu = u + (dir == 0), bv = v + (dir == 1);
        if (bu >= kGrid || bv >= kGrid || sub[bv][bu].kind == CellKind::complex) continue;
        const int a_side = dir == 0 ? 0 : 1, b_side = dir == 0 ? 2 : 3;  // a's right (bottom) meets b's left (top)
        const uint32_t pa = a.probe_bits, pb = sub[bv][bu].probe_bits;
        for (int k = 0; k < 2; ++k)
          joins[size_t(dir)][((pa >> (2 * a_side + k)) & 1) * 2 + ((pb >> (2 * b_side + k)) & 1)] |= bit;
      }
    }
  // The connected sets asked for so far (each found once).
  Regions found[kGrid * kGrid * 2];
  int found_count = 0;
  auto regions_of = [&](int cell, int region) -> const Regions& {
    for (int k = 0; k < found_count; ++k)
      if (found[k].has(cell, region)) return found[k];
    found[found_count] = connected(joins, cell, region);
    return found[found_count++];
  };

  // Samples of the 3x3, placed in their sub-pixel region (edge-ambiguous ones left out).
  struct Placed {
    int cell, region, u, v;
    float rgb[3];
  };
  Placed samples[9];
  int count = 0;
  for (int qy = y - 1; qy <= y + 1; ++qy)
    for (int qx = x - 1; qx <= x + 1; ++qx) {
      if (!epi.inside(qx, qy)) continue;
      const uint16_t e = epi.edge_at(qx, qy);
      if (!has_sample(e)) continue;
      const int r = sample_region(e), rx = r & 3, ry = r >> 2;
      const int u = 2 * (qx - x + 1) + (rx >> 1), v = 2 * (qy - y + 1) + (ry >> 1);
      const SubPixel& s = sub[v][u];
      int region = s.kind == CellKind::complex ? 3 : 0;
      if (s.kind == CellKind::simple) region = s.geometry->quarter[(rx & 1) + 2 * (ry & 1)];
      if constexpr (kTrace) {
        ComplexTrace::Sample traced{qx, qy, u, v, region, region < 2 ? regions_of(v * kGrid + u, region).id() : -1, {}};
        decode_color(epi.color_at(qx, qy), traced.rgb);
        trace->samples.push_back(traced);
      }
      if (region >= 2) continue;
      Placed& p = samples[count++];
      p.cell = v * kGrid + u, p.region = region, p.u = u, p.v = v;
      decode_color(epi.color_at(qx, qy), p.rgb);
    }

  if constexpr (kTrace)
    for (int v = 0; v < kGrid; ++v)
      for (int u = 0; u < kGrid; ++u)
        if (sub[v][u].kind != CellKind::complex)
          for (int region = 0; region < (sub[v][u].kind == CellKind::simple ? 2 : 1); ++region)
            trace->sub[v][u].group[region] = regions_of(v * kGrid + u, region).id();

  // Colour of one region of a centre sub-pixel; false when no sample reaches it (the estimate).
  auto region_color = [&](int u, int v, int region, float rgb[3]) -> bool {
    const Regions& connected_to = regions_of(v * kGrid + u, region);
    float sum[3] = {0, 0, 0}, total = 0;
    for (int k = 0; k < count; ++k) {
      if (!connected_to.has(samples[k].cell, samples[k].region)) continue;
      const float d2 = float((samples[k].u - u) * (samples[k].u - u) + (samples[k].v - v) * (samples[k].v - v));
      const float w = 1.0f / ((1.0f + d2) * (1.0f + d2));
      for (int c = 0; c < 3; ++c) sum[c] += w * samples[k].rgb[c];
      total += w;
    }
    for (int c = 0; c < 3; ++c) rgb[c] = total > 0 ? sum[c] / total : estimate[c];
    return total > 0;
  };

  out[0] = out[1] = out[2] = 0;
  for (int v = 2; v <= 3; ++v)
    for (int u = 2; u <= 3; ++u) {
      const SubPixel& s = sub[v][u];
      float rgb[3] = {estimate[0], estimate[1], estimate[2]};
      [[maybe_unused]] ComplexTrace::Centre traced;
      if (s.kind == CellKind::empty) {
        const bool found = region_color(u, v, 0, rgb);
        if constexpr (kTrace) traced.region_found[0] = found, std::copy(rgb, rgb + 3, traced.region_rgb[0]);
      } else if (s.kind == CellKind::simple) {
        float a_rgb[3], b_rgb[3];
        const bool found_a = region_color(u, v, 0, a_rgb);
        const bool found_b = region_color(u, v, 1, b_rgb);
        const float a = s.geometry->area;
        for (int c = 0; c < 3; ++c) rgb[c] = a * a_rgb[c] + (1.0f - a) * b_rgb[c];
        if constexpr (kTrace) {
          traced.area_a = a, traced.region_found[0] = found_a, traced.region_found[1] = found_b;
          std::copy(a_rgb, a_rgb + 3, traced.region_rgb[0]), std::copy(b_rgb, b_rgb + 3, traced.region_rgb[1]);
        }
      }
      if constexpr (kTrace) std::copy(rgb, rgb + 3, traced.rgb), trace->centre[(v - 2) * 2 + (u - 2)] = traced;
      for (int c = 0; c < 3; ++c) out[c] += 0.25f * rgb[c];
    }
}

}  // namespace

uint16_t sub_cell_class(uint32_t index) { return sub_cells()[sub_cell_entry(index)].cls; }

ComplexRowCache::ComplexRowCache() : rows_(std::make_unique<Rows>()) {}
ComplexRowCache::ComplexRowCache(const ComplexRowCache&) : ComplexRowCache() {}
ComplexRowCache& ComplexRowCache::operator=(const ComplexRowCache&) {
  reset();
  return *this;
}
ComplexRowCache::~ComplexRowCache() = default;
void ComplexRowCache::reset() { ++rows_->generation; }

void complex_pixel(const EpiRows& epi, const BoundaryMasks& masks, int x, int y, const float estimate[3],
                   float out[3]) {
  complex_impl<false>(epi, masks, x, y, estimate, out, nullptr);
}

void complex_pixel_traced(const EpiRows& epi, const BoundaryMasks& masks, int x, int y, const float estimate[3],
                          float out[3], ComplexTrace& trace) {
  trace = {};
  complex_impl<true>(epi, masks, x, y, estimate, out, &trace);
}

}  // namespace epi

#include "epi/complex_filter.h"

#include <algorithm>
#include <numeric>

#include "epi/geometry.h"

namespace epi {

namespace {

constexpr int kGrid = 6;

struct SubPixel {
  CellKind kind = CellKind::complex;  // complex also stands for "outside the image"
  geom::CellEdge edge{};
};

uint8_t half(uint8_t mask, int h) { return uint8_t((mask >> (4 * h)) & 15); }

int find(int* parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Region of a sub-pixel at local point p (empty: region 0).
int region_at(const SubPixel& s, geom::Vec2 p) { return s.kind == CellKind::simple ? geom::region_of(s.edge, p) : 0; }

// The filter; with kTrace it records into *trace (complex_pixel_traced), without it compiles
// to the plain filter.
template <bool kTrace>
void complex_impl(const EpiRows& epi, const BoundaryMasks& masks, int x, int y, const float estimate[3], float out[3],
                  ComplexTrace* trace) {
  // Classify the 6x6 sub-pixels.
  SubPixel sub[kGrid][kGrid];
  for (int v = 0; v < kGrid; ++v)
    for (int u = 0; u < kGrid; ++u) {
      const int px = x - 1 + u / 2, py = y - 1 + v / 2, sx = u & 1, sy = v & 1;
      if (!epi.inside(px, py)) continue;
      uint8_t sides[4];
      sides[0] = half(sy == 0 ? masks.top[masks.index(px, py)] : masks.centre_h[masks.index(px, py)], sx);
      sides[1] = half(sx == 0 ? masks.centre_v[masks.index(px, py)] : masks.left[masks.index(px + 1, py)], sy);
      sides[2] = half(sy == 0 ? masks.centre_h[masks.index(px, py)] : masks.top[masks.index(px, py + 1)], sx);
      sides[3] = half(sx == 0 ? masks.left[masks.index(px, py)] : masks.centre_v[masks.index(px, py)], sy);
      const geom::CellClass c = geom::classify_cell(sides, 4);
      sub[v][u].kind = c.kind;
      if (c.kind == CellKind::simple) sub[v][u].edge = geom::cell_edge(c.p_low, c.p_high, 4);
      if constexpr (kTrace) trace->sub[v][u].kind = c.kind, trace->sub[v][u].p_low = c.p_low, trace->sub[v][u].p_high = c.p_high;
    }

  // Connect regions across shared sides: nodes (v * 6 + u) * 2 + region.
  int parent[kGrid * kGrid * 2];
  std::iota(parent, parent + kGrid * kGrid * 2, 0);
  auto node = [](int u, int v, int region) { return (v * kGrid + u) * 2 + region; };
  for (int v = 0; v < kGrid; ++v)
    for (int u = 0; u < kGrid; ++u) {
      const SubPixel& a = sub[v][u];
      if (a.kind == CellKind::complex) continue;
      for (int dir = 0; dir < 2; ++dir) {
        const int bu = u + (dir == 0), bv = v + (dir == 1);
        if (bu >= kGrid || bv >= kGrid || sub[bv][bu].kind == CellKind::complex) continue;
        const SubPixel& b = sub[bv][bu];
        if (a.kind == CellKind::empty && b.kind == CellKind::empty) {
          const int ra = find(parent, node(u, v, 0)), rb = find(parent, node(bu, bv, 0));
          if (ra != rb) parent[ra] = rb;
          continue;
        }
        // A shared side holds at most one crossing, at a piece centre in [1/8, 7/8]: probing
        // both ends of the side meets every region that touches it.
        for (const double t : {1.0 / 16.0, 15.0 / 16.0}) {
          const geom::Vec2 pa = dir == 0 ? geom::Vec2{1, t} : geom::Vec2{t, 1};
          const geom::Vec2 pb = dir == 0 ? geom::Vec2{0, t} : geom::Vec2{t, 0};
          const int ra = find(parent, node(u, v, region_at(a, pa)));
          const int rb = find(parent, node(bu, bv, region_at(b, pb)));
          if (ra != rb) parent[ra] = rb;
        }
      }
    }

  // Samples of the 3x3, placed in their sub-pixel region (edge-ambiguous ones left out).
  struct Placed {
    int root, u, v;
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
      if (s.kind == CellKind::simple) region = geom::square_side(s.edge, (rx & 1) * 0.5, (ry & 1) * 0.5, 0.5);
      if constexpr (kTrace) {
        ComplexTrace::Sample traced{qx, qy, u, v, region, region < 2 ? find(parent, node(u, v, region)) : -1, {}};
        decode_color(epi.color_at(qx, qy), traced.rgb);
        trace->samples.push_back(traced);
      }
      if (region >= 2) continue;
      Placed& p = samples[count++];
      p.root = find(parent, node(u, v, region));
      p.u = u, p.v = v;
      decode_color(epi.color_at(qx, qy), p.rgb);
    }
  if constexpr (kTrace)
    for (int v = 0; v < kGrid; ++v)
      for (int u = 0; u < kGrid; ++u)
        if (sub[v][u].kind != CellKind::complex)
          for (int region = 0; region < (sub[v][u].kind == CellKind::simple ? 2 : 1); ++region)
            trace->sub[v][u].group[region] = find(parent, node(u, v, region));

  // Colour of one region of a centre sub-pixel.
  auto region_color = [&](int u, int v, int region, float rgb[3]) -> bool {
    const int root = find(parent, node(u, v, region));
    float sum[3] = {0, 0, 0}, total = 0;
    for (int k = 0; k < count; ++k) {
      if (samples[k].root != root) continue;
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
        const float a = float(geom::area_a(s.edge));
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

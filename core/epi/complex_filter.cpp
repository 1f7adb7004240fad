#include "epi/complex_filter.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <utility>

#include "epi/geometry.h"

namespace epi {

namespace {

constexpr int kGrid = 6;

// Per simple sub-pixel edge (n = 4: code 16 p_low + p_high), the geometry the filter asks for,
// computed once with the same double arithmetic (so results are as if computed each time):
// the region at the eight probe points of the shared sides, the side of each quarter square,
// the area of region A.
constexpr double kProbe[2] = {1.0 / 16.0, 15.0 / 16.0};
struct SubPixelGeometry {
  uint8_t probe[4][2];  // [side: right (1,t), bottom (t,1), left (0,t), top (t,0)][t index]
  uint8_t quarter[4];   // square_side of the quarter (qx, qy) at index qx + 2 qy
  float area;
};
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
        for (int q = 0; q < 4; ++q) g.quarter[q] = uint8_t(geom::square_side(e, (q & 1) * 0.5, (q >> 1) * 0.5, 0.5));
        g.area = float(geom::area_a(e));
      }
    return t;
  }();
  return table;
}

// geom::classify_cell(sides, 4) for every combination of the four 4-bit side masks (index
// top | right << 4 | bottom << 8 | left << 12): kind in bits 0-1, p_low in 2-5, p_high in 6-9.
// Built from classify_cell itself, so equal to it by construction (128 KB).
const std::array<uint16_t, 65536>& sub_cell_classes() {
  static const std::array<uint16_t, 65536> table = [] {
    std::array<uint16_t, 65536> t{};
    for (uint32_t i = 0; i < t.size(); ++i) {
      const uint8_t sides[4] = {uint8_t(i & 15), uint8_t((i >> 4) & 15), uint8_t((i >> 8) & 15), uint8_t(i >> 12)};
      const geom::CellClass c = geom::classify_cell(sides, 4);
      t[i] = uint16_t(int(c.kind) | c.p_low << 2 | c.p_high << 6);
    }
    return t;
  }();
  return table;
}

struct SubPixel {
  CellKind kind = CellKind::complex;  // complex also stands for "outside the image"
  const SubPixelGeometry* geometry = nullptr;
};

uint8_t half(uint8_t mask, int h) { return uint8_t((mask >> (4 * h)) & 15); }

int find(int* parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Region of a sub-pixel at probe k of its side (0 right, 1 bottom, 2 left, 3 top; empty: region 0).
int region_at(const SubPixel& s, int side, int k) { return s.kind == CellKind::simple ? s.geometry->probe[side][k] : 0; }

// The filter; with kTrace it records into *trace (complex_pixel_traced), without it compiles
// to the plain filter.
template <bool kTrace>
void complex_impl(const EpiRows& epi, const BoundaryMasks& masks, int x, int y, const float estimate[3], float out[3],
                  ComplexTrace* trace) {
  // Classify the 6x6 sub-pixels.
  const std::array<SubPixelGeometry, 256>& geometry = sub_pixel_geometry();
  const std::array<uint16_t, 65536>& classes = sub_cell_classes();
  SubPixel sub[kGrid][kGrid];
  for (int v = 0; v < kGrid; ++v)
    for (int u = 0; u < kGrid; ++u) {
      const int px = x - 1 + u / 2, py = y - 1 + v / 2, sx = u & 1, sy = v & 1;
      if (!epi.inside(px, py)) continue;
      const uint32_t top = half(sy == 0 ? masks.top[masks.index(px, py)] : masks.centre_h[masks.index(px, py)], sx);
      const uint32_t right = half(sx == 0 ? masks.centre_v[masks.index(px, py)] : masks.left[masks.index(px + 1, py)], sy);
      const uint32_t bottom = half(sy == 0 ? masks.centre_h[masks.index(px, py)] : masks.top[masks.index(px, py + 1)], sx);
      const uint32_t left = half(sx == 0 ? masks.left[masks.index(px, py)] : masks.centre_v[masks.index(px, py)], sy);
      const uint16_t c = classes[top | right << 4 | bottom << 8 | left << 12];  // geom::classify_cell(sides, 4)
      sub[v][u].kind = CellKind(c & 3);
      if (sub[v][u].kind == CellKind::simple) sub[v][u].geometry = &geometry[size_t(((c >> 2) & 15) * 16 + (c >> 6))];
      if constexpr (kTrace) trace->sub[v][u].kind = CellKind(c & 3), trace->sub[v][u].p_low = (c >> 2) & 15, trace->sub[v][u].p_high = c >> 6;
    }

  // Connect regions across shared sides: nodes (v * 6 + u) * 2 + region.
  // Union by size keeps the trees shallow; only the partition matters (region_color compares roots).
  int parent[kGrid * kGrid * 2], size[kGrid * kGrid * 2];
  std::iota(parent, parent + kGrid * kGrid * 2, 0);
  std::fill(size, size + kGrid * kGrid * 2, 1);
  auto unite = [&](int a, int b) {
    int ra = find(parent, a), rb = find(parent, b);
    if (ra == rb) return;
    if (size[ra] < size[rb]) std::swap(ra, rb);
    parent[rb] = ra, size[ra] += size[rb];
  };
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
          unite(node(u, v, 0), node(bu, bv, 0));
          continue;
        }
        // A shared side holds at most one crossing, at a piece centre in [1/8, 7/8]: probing
        // both ends of the side meets every region that touches it.
        for (int k = 0; k < 2; ++k) {  // a's right (bottom) side meets b's left (top) side
          unite(node(u, v, region_at(a, dir == 0 ? 0 : 1, k)), node(bu, bv, region_at(b, dir == 0 ? 2 : 3, k)));
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
      if (s.kind == CellKind::simple) region = s.geometry->quarter[(rx & 1) + 2 * (ry & 1)];
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

  // Colour of one region of a centre sub-pixel; false when no sample reaches it (the estimate).
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

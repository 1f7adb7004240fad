#include "epi/complex_filter.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <vector>
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
  uint8_t probe_bits;   // probe[side][k] at bit 2 side + k
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
        for (int side = 0; side < 4; ++side)
          for (int k = 0; k < 2; ++k) g.probe_bits = uint8_t(g.probe_bits | g.probe[side][k] << (2 * side + k));
        for (int q = 0; q < 4; ++q) g.quarter[q] = uint8_t(geom::square_side(e, (q & 1) * 0.5, (q >> 1) * 0.5, 0.5));
        g.area = float(geom::area_a(e));
      }
    return t;
  }();
  return table;
}

struct SubPixel {
  CellKind kind = CellKind::complex;  // complex also stands for "outside the image"
  const SubPixelGeometry* geometry = nullptr;
  uint8_t probe_bits = 0;  // the geometry's (empty: 0, region 0 everywhere)
};

uint32_t half(uint32_t mask, int h) { return (mask >> (4 * h)) & 15; }

// A connected set of regions as two 6x6 bitboards (bit v * 6 + u): regions 0 (A, or the whole
// of an empty sub-pixel) and 1 (B) of each sub-pixel.
struct Regions {
  uint64_t board[2];
  bool has(int cell, int region) const { return (board[region] >> cell) & 1; }
  // The smallest node index (2 cell + region) in the set: an id of the connected region.
  int id() const {
    const int a = board[0] ? 2 * __builtin_ctzll(board[0]) : 1000, b = board[1] ? 2 * __builtin_ctzll(board[1]) + 1 : 1000;
    return std::min(a, b);
  }
};

// Where regions of neighbouring sub-pixels touch: bit i of joins[dir][2 ra + rb] joins region
// ra of cell i with region rb of cell i + 1 (dir 0, its right neighbour) or i + 6 (dir 1, below).
using Joins = std::array<std::array<uint64_t, 4>, 2>;

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

// ---- The row kernel (complex_row): the same filter, restructured (docs/epi.md, "Complex pixels").
// Boards here are 6 rows of 8 bits (bit v * 8 + u, columns 6 and 7 empty), so a window's board
// is three 2-column strips side by side, each strip that of one pixel column.
constexpr int kStride = 8;

// A colour in the first three lanes of a 4-float vector (GCC/Clang vector extension): lane-wise
// products, sums and quotients round exactly as the oracle's scalar ones.
using Rgb4 = float __attribute__((vector_size(16)));

// The weight 1 / (1 + d^2)^2 by d^2 (offsets up to 5 sub-pixels each way): the oracle's expression.
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

// Spreads bit k of a byte to bit 8k (probe bits into a strip column; a 6-bit column into a board).
const std::array<uint64_t, 256>& spread_bits_to_bytes() {
  static const std::array<uint64_t, 256> table = [] {
    std::array<uint64_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i)
      for (int k = 0; k < 8; ++k) t[i] |= uint64_t((i >> k) & 1) << (8 * k);
    return t;
  }();
  return table;
}

// A sub-pixel by its crossings: geom::classify_cell(sides, 4) (no 64 Ki-entry table: its
// scattered reads missed the caches), and for the row kernel the edge's probe bits spread one per
// byte.
struct SubCell {
  uint64_t probes;  // SubPixelGeometry::probe_bits, bit k at bit 8k (0 unless simple)
  uint16_t cls;     // kind | p_low << 2 | p_high << 6
  uint8_t kind, code;  // code: 16 p_low + p_high where simple, else 0
};
// Entries 0-255: two crossings, by 16 a + b (a < b their bit indices), from classify_cell itself;
// 256: at most one crossing (empty); 257: more than two (complex): classify_cell's own rules.
const std::array<SubCell, 258>& sub_cells() {
  static const std::array<SubCell, 258> table = [] {
    std::array<SubCell, 258> t{};
    const auto& spread = spread_bits_to_bytes();
    const auto& geometry = sub_pixel_geometry();
    for (int a = 0; a < 16; ++a)
      for (int b = a + 1; b < 16; ++b) {
        const uint32_t i = 1u << a | 1u << b;
        const uint8_t sides[4] = {uint8_t(i & 15), uint8_t((i >> 4) & 15), uint8_t((i >> 8) & 15), uint8_t(i >> 12)};
        const geom::CellClass c = geom::classify_cell(sides, 4);
        const uint8_t code = c.kind == CellKind::simple ? uint8_t(c.p_low * 16 + c.p_high) : 0;
        t[size_t(a * 16 + b)] = {spread[geometry[code].probe_bits], uint16_t(int(c.kind) | c.p_low << 2 | c.p_high << 6),
                                 uint8_t(c.kind), code};
      }
    t[256] = {0, uint16_t(CellKind::empty), uint8_t(CellKind::empty), 0};
    t[257] = {0, uint16_t(CellKind::complex), uint8_t(CellKind::complex), 0};
    return t;
  }();
  return table;
}
// The entry of a sub-pixel by its side masks (index top | right << 4 | bottom << 8 | left << 12).
inline size_t sub_cell_entry(uint32_t index) {
  const uint32_t rest = index & (index - 1);  // without the lowest crossing
  const size_t pair = size_t((__builtin_ctz(index | 0x10000) & 15) * 16 + (__builtin_ctz(rest | 0x10000) & 15));
  const size_t one_or_two = rest == 0 ? 256 : pair;
  return (rest & (rest - 1)) != 0 ? 257 : one_or_two;
}

}  // namespace

uint16_t sub_cell_class(uint32_t index) { return sub_cells()[sub_cell_entry(index)].cls; }

namespace {

// One pixel column of a window (pixels (px, y - 1 .. y + 1)): its 2x6 sub-pixels and 3 samples,
// computed once per row and shared by the windows of up to three complex pixels.
struct Strip {
  int px = -2;  // the column; -2: none (never asked: columns start at -1)
  // Boards of the strip's two columns (bits v * 8 + sx): not complex (inside the image), and
  // the eight probe bits of SubPixelGeometry::probe_bits (side * 2 + k).
  uint64_t ok = 0, probe[8] = {};
  uint8_t kind[6][2];  // CellKind, complex outside the image
  uint8_t code[6][2];  // simple: the edge code 16 p_low + p_high; else 0 (no probe bits, quarters 0)
  struct Sample {
    float present;  // 1: a sample in a region (not dropped), else 0
    uint8_t sx, v, region;
    Rgb4 rgb;  // finite also when absent; lane 3 is 0
  } sample[3];
};

}  // namespace

// One pixel's sub-pixels and sample as strips take them (ComplexRowCache).
struct ComplexRowCache::Pixel {
  uint64_t stamp = 0;   // generation << 32 | row: computed for that row in that generation
  uint64_t column[2];   // column[sx]: bit 8k + sy = probe bit k of sub-pixel (sx, sy)
  uint16_t ok;          // bit 8 sy + sx: sub-pixel (sx, sy) not complex
  uint8_t kind[2][2];   // [sy][sx]
  uint8_t code[2][2];
  float present;        // the sample: 1 in a region (not dropped), else 0
  uint8_t sx, sy, region;
  Rgb4 rgb;             // finite also when absent; lane 3 is 0
};
struct ComplexRowCache::Rows {
  std::vector<Pixel> row[4];  // image row py at row[py & 3]
  uint64_t generation = 1;
  int width = -1;
};
ComplexRowCache::ComplexRowCache() : rows_(std::make_unique<Rows>()) {}
ComplexRowCache::ComplexRowCache(const ComplexRowCache&) : ComplexRowCache() {}
ComplexRowCache& ComplexRowCache::operator=(const ComplexRowCache&) {
  reset();
  return *this;
}
ComplexRowCache::~ComplexRowCache() = default;
void ComplexRowCache::reset() { ++rows_->generation; }

namespace {

using Pixel = ComplexRowCache::Pixel;

void compute_pixel(Pixel& p, const EpiRows& epi, const BoundaryMasks& masks, int px, int py,
                   const std::array<SubPixelGeometry, 256>& geometry) {
  const std::array<SubCell, 258>& cells = sub_cells();
  const size_t i = masks.index(px, py);
  const uint32_t top = masks.top[i], bottom = masks.top[i + size_t(masks.width) + 1], left = masks.left[i],
                 right = masks.left[i + 1], centre_h = masks.centre_h[i], centre_v = masks.centre_v[i];
  uint64_t column[2] = {};
  uint32_t ok = 0;
  for (int sy = 0; sy < 2; ++sy)
    for (int sx = 0; sx < 2; ++sx) {
      const uint32_t t = half(sy == 0 ? top : centre_h, sx), r = half(sx == 0 ? centre_v : right, sy);
      const uint32_t b = half(sy == 0 ? centre_h : bottom, sx), l = half(sx == 0 ? left : centre_v, sy);
      const SubCell& cell = cells[sub_cell_entry(t | r << 4 | b << 8 | l << 12)];
      p.kind[sy][sx] = cell.kind, p.code[sy][sx] = cell.code;
      ok |= uint32_t(cell.kind != uint8_t(CellKind::complex)) << (sy * kStride + sx);
      column[sx] |= cell.probes << sy;
    }
  p.column[0] = column[0], p.column[1] = column[1], p.ok = uint16_t(ok);
  const uint16_t e = epi.edge_at(px, py);
  const int r = sample_region(e), rx = r & 3, ry = r >> 2, sx = rx >> 1, sy = ry >> 1;
  const bool complex = p.kind[sy][sx] == uint8_t(CellKind::complex);
  const int region = complex ? 3 : geometry[p.code[sy][sx]].quarter[(rx & 1) + 2 * (ry & 1)];
  p.present = float(has_sample(e) && region < 2);
  p.sx = uint8_t(sx), p.sy = uint8_t(sy), p.region = uint8_t(region & 1);
  float rgb[3];
  decode_color(epi.color_at(px, py), rgb);
  p.rgb = Rgb4{rgb[0], rgb[1], rgb[2], 0.0f};
}

void fill_strip(Strip& s, const EpiRows& epi, const BoundaryMasks& masks, int px, int y,
                const std::array<SubPixelGeometry, 256>& geometry, ComplexRowCache::Rows& cache) {
  const std::array<uint64_t, 256>& spread = spread_bits_to_bytes();
  s.px = px;
  uint64_t ok = 0, column[2] = {};  // column[sx]: bit 8k + v = probe bit k of sub-pixel (sx, v)
  for (int j = 0; j < 3; ++j) {
    const int py = y - 1 + j;
    Strip::Sample& sample = s.sample[j];
    if (!epi.inside(px, py)) {
      for (int v = 2 * j; v < 2 * j + 2; ++v)
        s.kind[v][0] = s.kind[v][1] = uint8_t(CellKind::complex), s.code[v][0] = s.code[v][1] = 0;
      sample = {0.0f, 0, uint8_t(2 * j), 0, Rgb4{0, 0, 0, 0}};
      continue;
    }
    Pixel& p = cache.row[py & 3][size_t(px)];
    const uint64_t stamp = cache.generation << 32 | uint32_t(py);
    if (p.stamp != stamp) compute_pixel(p, epi, masks, px, py, geometry), p.stamp = stamp;
    for (int sy = 0; sy < 2; ++sy)
      for (int sx = 0; sx < 2; ++sx) s.kind[2 * j + sy][sx] = p.kind[sy][sx], s.code[2 * j + sy][sx] = p.code[sy][sx];
    ok |= uint64_t(p.ok) << (2 * j * kStride);
    column[0] |= p.column[0] << (2 * j), column[1] |= p.column[1] << (2 * j);
    sample.present = p.present, sample.sx = p.sx, sample.v = uint8_t(2 * j + p.sy), sample.region = p.region;
    sample.rgb = p.rgb;
  }
  s.ok = ok;
  for (int k = 0; k < 8; ++k)
    s.probe[k] = spread[(column[0] >> (8 * k)) & 63] | spread[(column[1] >> (8 * k)) & 63] << 1;
}

// connected() on the boards of this kernel (stride 8).
Regions connected_strided(const Joins& joins, int cell, int region) {
  uint64_t c0 = region == 0 ? 1ull << cell : 0, c1 = region == 1 ? 1ull << cell : 0;
  const std::array<uint64_t, 4>&h = joins[0], &d = joins[1];
  for (;;) {
    const uint64_t n0 = c0 | ((c0 & h[0]) << 1) | ((c1 & h[2]) << 1) | ((c0 >> 1) & h[0]) | ((c1 >> 1) & h[1]) |
                        ((c0 & d[0]) << kStride) | ((c1 & d[2]) << kStride) | ((c0 >> kStride) & d[0]) |
                        ((c1 >> kStride) & d[1]);
    const uint64_t n1 = c1 | ((c0 & h[1]) << 1) | ((c1 & h[3]) << 1) | ((c0 >> 1) & h[2]) | ((c1 >> 1) & h[3]) |
                        ((c0 & d[1]) << kStride) | ((c1 & d[3]) << kStride) | ((c0 >> kStride) & d[2]) |
                        ((c1 >> kStride) & d[3]);
    if (n0 == c0 && n1 == c1) return {{c0, c1}};
    c0 = n0, c1 = n1;
  }
}

// complex_impl<false> for the window of strips w (columns x - 1, x, x + 1).
void complex_window(const Strip* const w[3], const float estimate[3], float out[3],
                    const std::array<SubPixelGeometry, 256>& geometry) {
  uint64_t ok = 0, probe[8] = {};
  for (int i = 0; i < 3; ++i) {
    ok |= w[i]->ok << (2 * i);
    for (int b = 0; b < 8; ++b) probe[b] |= w[i]->probe[b] << (2 * i);
  }
  // The oracle's joins, as board operations: bit i of joins[dir][2 ra + rb] where both cells are
  // usable and a probe k of the shared side sees region ra in cell i and rb in its neighbour.
  Joins joins{};
  for (int dir = 0; dir < 2; ++dir) {
    const int s = dir == 0 ? 1 : kStride, a_side = dir == 0 ? 0 : 1, b_side = dir == 0 ? 2 : 3;
    const uint64_t valid = ok & (ok >> s);
    std::array<uint64_t, 4>& j = joins[size_t(dir)];
    for (int k = 0; k < 2; ++k) {
      const uint64_t a = probe[2 * a_side + k], b = probe[2 * b_side + k] >> s;
      j[0] |= valid & ~a & ~b, j[1] |= valid & ~a & b, j[2] |= valid & a & ~b, j[3] |= valid & a & b;
    }
  }
  Regions found[8];
  int found_count = 0;
  auto regions_of = [&](int cell, int region) -> const Regions& {
    for (int k = 0; k < found_count; ++k)
      if (found[k].has(cell, region)) return found[k];
    found[found_count] = connected_strided(joins, cell, region);
    return found[found_count++];
  };

  // The samples in the oracle's order; one not joined to a region weighs 0 there (adding +0
  // changes no sum).
  struct Placed {
    int cell, region, u, v;
    Rgb4 rgb;
  };
  Placed samples[9];
  int count = 0;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const Strip::Sample& s = w[i]->sample[j];
      const int u = 2 * i + s.sx;
      samples[count] = {s.v * kStride + u, s.region, u, s.v, s.rgb};
      count += s.present != 0;
    }
  const std::array<float, 51>& weights = sample_weights();
  const Rgb4 own = {estimate[0], estimate[1], estimate[2], 0.0f};
  auto region_color = [&](int u, int v, int region) -> Rgb4 {
    const Regions& connected_to = regions_of(v * kStride + u, region);
    Rgb4 sum = {0, 0, 0, 0};
    float total = 0;
    for (int k = 0; k < count; ++k) {
      const Placed& s = samples[k];
      const float in = float((connected_to.board[s.region] >> s.cell) & 1);
      const float wk = in * weights[size_t((s.u - u) * (s.u - u) + (s.v - v) * (s.v - v))];
      sum += wk * s.rgb;
      total += wk;
    }
    return total > 0 ? sum / total : own;
  };

  // Each centre sub-pixel: its region colours, blended by area where simple; complex: the estimate.
  Rgb4 result = {0, 0, 0, 0};
  for (int v = 2; v <= 3; ++v)
    for (int u = 2; u <= 3; ++u) {
      const CellKind kind = CellKind(w[1]->kind[v][u - 2]);
      Rgb4 rgb = own;
      if (kind == CellKind::empty) {
        rgb = region_color(u, v, 0);
      } else if (kind == CellKind::simple) {
        const Rgb4 a_rgb = region_color(u, v, 0), b_rgb = region_color(u, v, 1);
        const float a = geometry[w[1]->code[v][u - 2]].area;
        rgb = a * a_rgb + (1.0f - a) * b_rgb;
      }
      result += 0.25f * rgb;
    }
  out[0] = result[0], out[1] = result[1], out[2] = result[2];
}

// Prefetches what the window of complex pixel (x, y) reads: in the staged schedule its planes
// are cold, and complex pixels are scattered, so without it the filter waits on memory. Always
// inlined: GCC deletes calls of a function that only prefetches (it has no side effects).
[[gnu::always_inline]] inline void prefetch_window(const EpiRows& epi, const BoundaryMasks& masks, int x, int y,
                                                   const float* estimate, const float* out) {
  const int x0 = std::max(x - 1, 0);
  for (int py = std::max(y - 1, 0); py <= std::min(y + 1, epi.height - 1); ++py) {
    const size_t i = masks.index(x0, py);
    __builtin_prefetch(&masks.top[i]), __builtin_prefetch(&masks.left[i]);
    __builtin_prefetch(&masks.centre_h[i]), __builtin_prefetch(&masks.centre_v[i]);
    __builtin_prefetch(&masks.top[i + size_t(masks.width) + 1]);
    __builtin_prefetch(epi.edge_row(py) + x0), __builtin_prefetch(epi.color_row(py) + x0);
  }
  __builtin_prefetch(estimate + 3 * x), __builtin_prefetch(out + 3 * x, 1);
}

}  // namespace

void complex_row(const EpiRows& epi, const BoundaryMasks& masks, int y, const uint8_t* types, const float* estimate,
                 float* out, ComplexRowCache& row_cache) {
  const std::array<SubPixelGeometry, 256>& geometry = sub_pixel_geometry();
  ComplexRowCache::Rows& rows = *row_cache.rows_;
  if (rows.width != epi.width) {
    for (std::vector<Pixel>& r : rows.row) r.assign(size_t(epi.width), Pixel{});
    rows.width = epi.width, ++rows.generation;
  }
  Strip cache[3];
  // The row's complex pixels, found by memchr a chunk at a time, each prefetched kAhead before.
  constexpr int kChunk = 64, kAhead = 6;
  int xs[kChunk];
  const size_t w = size_t(epi.width);
  const uint8_t* p = static_cast<const uint8_t*>(std::memchr(types, kTypeComplex, w));
  while (p) {
    int n = 0;
    for (; p && n < kChunk; p = static_cast<const uint8_t*>(std::memchr(p + 1, kTypeComplex, w - size_t(p + 1 - types))))
      xs[n++] = int(p - types);
    for (int k = 0; k < std::min(n, kAhead); ++k) prefetch_window(epi, masks, xs[k], y, estimate, out);
    for (int k = 0; k < n; ++k) {
      if (k + kAhead < n) prefetch_window(epi, masks, xs[k + kAhead], y, estimate, out);
      const int x = xs[k];
      // The strips of columns x - 1 .. x + 1: kept from the window before where it had them.
      const Strip* window[3] = {};
      bool taken[3] = {};
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c)
          if (cache[c].px == x - 1 + i) window[i] = &cache[c], taken[c] = true;
      for (int i = 0; i < 3; ++i) {
        if (window[i]) continue;
        int c = 0;
        while (taken[c]) ++c;
        fill_strip(cache[c], epi, masks, x - 1 + i, y, geometry, rows);
        window[i] = &cache[c], taken[c] = true;
      }
      complex_window(window, estimate + 3 * x, out + 3 * x, geometry);
    }
  }
}

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

// The complex filter's row kernel (complex_row, complex_filter.h), compiled once per Highway
// target (foreach_target.h, as simd/row_kernels.cpp): the same C++ in each, the GCC/Clang vector
// extension's lanes taking each target's registers. The oracle and the tables it shares with the
// kernel are in complex_filter.cpp (docs/epi.md, "Complex pixels").
#include "epi/complex_filter.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "epi/complex_internal.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "epi/complex_row.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace epi {
namespace HWY_NAMESPACE {
namespace {

using namespace complex_detail;

// 1: a window's eight region sets in lanes (complex_window below), on targets with 32-byte
// vectors or wider (AVX2, AVX3); 0: the sets one by one (SSE4, SSSE3, scalar).
#undef EPI_COMPLEX_LANES
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
#define EPI_COMPLEX_LANES 1
#else
#define EPI_COMPLEX_LANES 0
#endif

// One pixel column of a window (pixels (px, y - 1 .. y + 1)): its 2x6 sub-pixels and 3 samples,
// computed once per row and shared by the windows of up to three complex pixels.
struct Strip {
  int px = -2;  // the column; -2: none (never asked: columns start at -1)
  // Boards of the strip's two columns (bits v * 8 + sx): not complex (inside the image), and
  // the eight probe bits of SubPixelGeometry::probe_bits (side * 2 + k).
  uint64_t ok = 0, probe[8] = {};
  // Of the middle pixel (px, y), the one window that has the strip in its middle asks for:
  // Pixel::kinds and Pixel::codes (complex, 0 outside the image).
  uint32_t kinds, codes;
  struct Sample {
    float present;  // 1: a sample in a region (not dropped), else 0
    uint8_t sx, v, region;
    Rgb4 rgb;  // finite also when absent; lane 3 is 0
  } sample[3];
};

using Pixel = ComplexRowCache::Pixel;

// The record of pixel (px, py) (ComplexRowCache::Pixel): its four sub-pixels by the 512-entry
// table, their probe bits spread into its two columns, its sample's region and colour.
[[gnu::always_inline]] inline void compute_pixel(Pixel& p, const EpiRows& epi, const BoundaryMasks& masks, int px, int py) {
  const std::array<SubCell, 512>& cells = sub_cells();
  const size_t i = masks.index(px, py);
  const uint32_t top = masks.top[i], bottom = masks.top[i + size_t(masks.width) + 1], left = masks.left[i],
                 right = masks.left[i + 1], centre_h = masks.centre_h[i], centre_v = masks.centre_v[i];
  uint64_t column[2] = {};
  uint32_t ok = 0, kinds = 0, codes = 0, quarters = 0;
  for (int sy = 0; sy < 2; ++sy)
    for (int sx = 0; sx < 2; ++sx) {
      const uint32_t t = half(sy == 0 ? top : centre_h, sx), r = half(sx == 0 ? centre_v : right, sy);
      const uint32_t b = half(sy == 0 ? centre_h : bottom, sx), l = half(sx == 0 ? left : centre_v, sy);
      const SubCell& cell = cells[sub_cell_entry(t | r << 4 | b << 8 | l << 12)];
      const int byte = 8 * (2 * sy + sx);
      kinds |= uint32_t(cell.kind) << byte, codes |= uint32_t(cell.code) << byte;
      quarters |= uint32_t(cell.quarters) << byte;
      ok |= uint32_t(cell.kind != uint8_t(CellKind::complex)) << (sy * kStride + sx);
      column[sx] |= cell.probes << sy;
    }
  p.column[0] = column[0], p.column[1] = column[1], p.ok = uint16_t(ok), p.kinds = kinds, p.codes = codes;
  // The sample's region from its quarter of its sub-pixel (3: dropped, the sub-pixel complex).
  const uint16_t e = epi.edge_at(px, py);
  const uint32_t r = uint32_t(sample_region(e)), rx = r & 3, ry = r >> 2, sx = rx >> 1, sy = ry >> 1;
  const uint32_t region = (quarters >> (8 * (2 * sy + sx) + 2 * ((rx & 1) + 2 * (ry & 1)))) & 3;
  p.present = float(has_sample(e) && region < 2);
  p.sx = uint8_t(sx), p.sy = uint8_t(sy), p.region = uint8_t(region & 1);
  float rgb[3];
  decode_color(epi.color_at(px, py), rgb);
  p.rgb = Rgb4{rgb[0], rgb[1], rgb[2], 0.0f};
}

void fill_strip(Strip& s, const EpiRows& epi, int px, int y, const ComplexRowCache::Rows& cache) {
  const std::array<uint64_t, 256>& spread = spread_bits_to_bytes();
  s.px = px;
  uint64_t ok = 0, column[2] = {};  // column[sx]: bit 8k + v = probe bit k of sub-pixel (sx, v)
  for (int j = 0; j < 3; ++j) {
    const int py = y - 1 + j;
    Strip::Sample& sample = s.sample[j];
    if (!epi.inside(px, py)) {
      if (j == 1) s.kinds = uint8_t(CellKind::complex) * 0x01010101u, s.codes = 0;
      sample = {0.0f, 0, uint8_t(2 * j), 0, Rgb4{0, 0, 0, 0}};
      continue;
    }
    const Pixel& p = cache.row[py & 3][size_t(px)];  // computed (ComplexRowKernel)
    if (j == 1) s.kinds = p.kinds, s.codes = p.codes;
    ok |= uint64_t(p.ok) << (2 * j * kStride);
    column[0] |= p.column[0] << (2 * j), column[1] |= p.column[1] << (2 * j);
    sample.present = p.present, sample.sx = p.sx, sample.v = uint8_t(2 * j + p.sy), sample.region = p.region;
    sample.rgb = p.rgb;
  }
  s.ok = ok;
  for (int k = 0; k < 8; ++k)
    s.probe[k] = spread[(column[0] >> (8 * k)) & 63] | spread[(column[1] >> (8 * k)) & 63] << 1;
}

#if EPI_COMPLEX_LANES
// mask ? a : b lane by lane, mask lanes all ones or zero, bitwise (a vector ?: of 8 lanes went
// lane by lane on the SSE targets).
inline F8 select8(U32x8 mask, F8 a, F8 b) { return (F8)(((U32x8)a & mask) | ((U32x8)b & ~mask)); }
inline Rgb4 select4(I4 mask, Rgb4 a, Rgb4 b) { return (Rgb4)(((I4)a & mask) | ((I4)b & ~mask)); }

// complex_impl<false> for the window of strips w (columns x - 1, x, x + 1): the eight region sets
// in lanes (AVX2, AVX3: 4 or 8 64-bit lanes a step).
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
  // The connected sets of the centre sub-pixels' regions, all eight grown in lockstep (no
  // branch per set): lane r < 4 holds region A (0) of centre sub-pixel r (u = 2 + (r & 1),
  // v = 2 + (r >> 1)), lane 4 + r its region B; a region the sub-pixel lacks starts (and stays)
  // empty. Growth stops when no lane changes: each set is then its region's connected set.
  uint64_t c0[8], c1[8];
  for (int r = 0; r < 4; ++r) {
    const int u = 2 + (r & 1), v = 2 + (r >> 1);
    const uint8_t kind = uint8_t(w[1]->kinds >> (8 * (2 * (v - 2) + u - 2)));
    const uint64_t bit = 1ull << (v * kStride + u);
    c0[r] = kind != uint8_t(CellKind::complex) ? bit : 0, c1[r] = 0;
    c0[r + 4] = 0, c1[r + 4] = kind == uint8_t(CellKind::simple) ? bit : 0;
  }
  const std::array<uint64_t, 4>&h = joins[0], &d = joins[1];
  for (;;) {
    uint64_t changed = 0;
    for (int r = 0; r < 8; ++r) {
      const uint64_t a = c0[r], b = c1[r];
      const uint64_t n0 = a | ((a & h[0]) << 1) | ((b & h[2]) << 1) | ((a >> 1) & h[0]) | ((b >> 1) & h[1]) |
                          ((a & d[0]) << kStride) | ((b & d[2]) << kStride) | ((a >> kStride) & d[0]) |
                          ((b >> kStride) & d[1]);
      const uint64_t n1 = b | ((a & h[1]) << 1) | ((b & h[3]) << 1) | ((a >> 1) & h[2]) | ((b >> 1) & h[3]) |
                          ((a & d[1]) << kStride) | ((b & d[3]) << kStride) | ((a >> kStride) & d[2]) |
                          ((b >> kStride) & d[3]);
      changed |= (n0 ^ a) | (n1 ^ b);
      c0[r] = n0, c1[r] = n1;
    }
    if (!changed) break;
  }

  // The present samples' cells by region (one sample per pixel: no two share a cell); lane r's
  // board of the samples its set holds.
  uint64_t p0 = 0, p1 = 0;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const Strip::Sample& s = w[i]->sample[j];
      const uint64_t bit = uint64_t(s.present != 0) << (s.v * kStride + 2 * i + s.sx);
      p0 |= s.region == 0 ? bit : 0, p1 |= s.region == 1 ? bit : 0;
    }
  // As two 32-bit halves (a cell's bit read with 32-bit lane shifts: no 64-bit lane
  // conversions, which SSE targets do lane by lane).
  U32x8 held_low, held_high;
  for (int r = 0; r < 8; ++r) {
    const uint64_t held = (c0[r] & p0) | (c1[r] & p1);
    held_low[r] = uint32_t(held), held_high[r] = uint32_t(held >> 32);
  }

  // Region colours, the eight in lanes: the samples in the oracle's order, each weighted by its
  // distance to lane r's centre sub-pixel where lane r's set holds it, else by +0 (adding +0
  // changes no sum: sums start at +0 and add products >= 0).
  const std::array<F8, 36>& centre_weights = window_weights();
  F8 sum0 = {}, sum1 = {}, sum2 = {}, total = {};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const Strip::Sample& s = w[i]->sample[j];
      const int u = 2 * i + s.sx;
      const uint32_t cell = uint32_t(s.v * kStride + u), high = cell >> 5, shift = cell & 31;
      const U32x8 in = ((held_low >> shift) & (high ^ 1)) | ((held_high >> shift) & high);  // 0 or 1
      const F8 wk = select8(0u - in, centre_weights[size_t(s.v * kGrid + u)], F8{});
      sum0 += wk * s.rgb[0], sum1 += wk * s.rgb[1], sum2 += wk * s.rgb[2];
      total += wk;
    }
  const U32x8 found = (U32x8)(total > 0);
  const F8 col0 = select8(found, sum0 / total, F8{} + estimate[0]);
  const F8 col1 = select8(found, sum1 / total, F8{} + estimate[1]);
  const F8 col2 = select8(found, sum2 / total, F8{} + estimate[2]);

  // Each centre sub-pixel: region A where empty, A and B blended by area where simple, the
  // estimate where complex; the pixel their mean, summed in the oracle's order.
  Rgb4 area = {}, own = {estimate[0], estimate[1], estimate[2], 0.0f};
  I4 simple = {}, empty = {};
  for (int r = 0; r < 4; ++r) {
    const int u = 2 + (r & 1), v = 2 + (r >> 1);
    const uint8_t kind = uint8_t(w[1]->kinds >> (8 * (2 * (v - 2) + u - 2)));
    area[r] = geometry[(w[1]->codes >> (8 * (2 * (v - 2) + u - 2))) & 255].area;
    simple[r] = -int(kind == uint8_t(CellKind::simple)), empty[r] = -int(kind == uint8_t(CellKind::empty));
  }
  const F8* cols[3] = {&col0, &col1, &col2};
  float result[3];
  for (int c = 0; c < 3; ++c) {
    const Rgb4 a = __builtin_shufflevector(*cols[c], *cols[c], 0, 1, 2, 3);
    const Rgb4 b = __builtin_shufflevector(*cols[c], *cols[c], 4, 5, 6, 7);
    const Rgb4 blend = area * a + (1.0f - area) * b;
    const Rgb4 sub = select4(simple, blend, select4(empty, a, Rgb4{} + own[c]));
    const Rgb4 quarter = 0.25f * sub;
    result[c] = ((0.0f + quarter[0]) + quarter[1] + quarter[2]) + quarter[3];
  }
  out[0] = result[0], out[1] = result[1], out[2] = result[2];
}
#else
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

// complex_impl<false> for the window of strips w (columns x - 1, x, x + 1): the targets with
// 16-byte vectors grow only the distinct sets, one by one, and sum only the present samples (eight
// sets in lanes were slower there: 2 lanes a step).
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
      const CellKind kind = CellKind(uint8_t(w[1]->kinds >> (8 * (2 * (v - 2) + u - 2))));
      Rgb4 rgb = own;
      if (kind == CellKind::empty) {
        rgb = region_color(u, v, 0);
      } else if (kind == CellKind::simple) {
        const Rgb4 a_rgb = region_color(u, v, 0), b_rgb = region_color(u, v, 1);
        const float a = geometry[(w[1]->codes >> (8 * (2 * (v - 2) + u - 2))) & 255].area;
        rgb = a * a_rgb + (1.0f - a) * b_rgb;
      }
      result += 0.25f * rgb;
    }
  out[0] = result[0], out[1] = result[1], out[2] = result[2];
}

#endif


// Prefetches what the window of complex pixel (x, y) reads: in the staged schedule its planes
// are cold, and complex pixels are scattered, so without it the filter waits on memory. Always
// inlined: GCC deletes calls of a function that only prefetches (it has no side effects).
[[gnu::always_inline]] inline void prefetch_window(const EpiRows& epi, const BoundaryMasks& masks, int x, int y) {
  const int x0 = std::max(x - 1, 0);
  for (int py = std::max(y - 1, 0); py <= std::min(y + 1, epi.height - 1); ++py) {
    const size_t i = masks.index(x0, py);
    __builtin_prefetch(&masks.top[i]), __builtin_prefetch(&masks.left[i]);
    __builtin_prefetch(&masks.centre_h[i]), __builtin_prefetch(&masks.centre_v[i]);
    __builtin_prefetch(&masks.top[i + size_t(masks.width) + 1]);
    __builtin_prefetch(epi.edge_row(py) + x0), __builtin_prefetch(epi.color_row(py) + x0);
  }
}


}  // namespace

void ComplexRowKernel(const EpiRows& epi, const BoundaryMasks& masks, int y, const uint8_t* types, const float* estimate,
                      float* out, ComplexRowCache::Rows& rows) {
  const std::array<SubPixelGeometry, 256>& geometry = sub_pixel_geometry();
  if (rows.width != epi.width) {
    for (std::vector<Pixel>& r : rows.row) r.assign(size_t(epi.width), Pixel{});
    for (std::vector<uint64_t>& d : rows.done) d.assign((size_t(epi.width) + 63) / 64, 0);
    rows.width = epi.width, ++rows.generation;
  }
  // The row's complex pixels (memchr), and the columns of their windows.
  const size_t w = size_t(epi.width), words = (w + 63) / 64;
  std::vector<int>& xs = rows.xs;
  xs.clear();
  for (auto* p = static_cast<const uint8_t*>(std::memchr(types, kTypeComplex, w)); p;
       p = static_cast<const uint8_t*>(std::memchr(p + 1, kTypeComplex, w - size_t(p + 1 - types))))
    xs.push_back(int(p - types));
  if (xs.empty()) return;
  std::vector<uint64_t>& needed = rows.needed;
  needed.assign(words, 0);
  for (const int x : xs) {
    prefetch_window(epi, masks, x, y);
    __builtin_prefetch(estimate + 3 * x), __builtin_prefetch(out + 3 * x, 1);
    for (int px = std::max(x - 1, 0); px <= std::min(x + 1, epi.width - 1); ++px) needed[size_t(px) >> 6] |= 1ull << (px & 63);
  }

  // The pixel records of those columns in rows y - 1 .. y + 1, each computed once for all the
  // rows that read it (a bitmap per cached row, no test per record: the records of a row are
  // computed in one loop, without branches that depend on the data).
  for (int py = std::max(y - 1, 0); py <= std::min(y + 1, epi.height - 1); ++py) {
    const size_t slot = size_t(py & 3);
    const uint64_t id = rows.generation << 32 | uint32_t(py);
    if (rows.slot_row[slot] != id) std::fill(rows.done[slot].begin(), rows.done[slot].end(), 0), rows.slot_row[slot] = id;
    uint64_t* done = rows.done[slot].data();
    Pixel* record = rows.row[slot].data();
    for (size_t k = 0; k < words; ++k) {
      uint64_t todo = needed[k] & ~done[k];
      done[k] |= needed[k];
      for (; todo; todo &= todo - 1) {
        const int px = int(k * 64) + __builtin_ctzll(todo);
        compute_pixel(record[px], epi, masks, px, py);
      }
    }
  }

  // The windows, left to right (their estimates and outputs prefetched with the lines above:
  // with few edges, most rows have fewer complex pixels than any distance ahead).
  Strip ring[4];
  for (size_t k = 0; k < xs.size(); ++k) {
    const int x = xs[k];
    // The strips of columns x - 1 .. x + 1, column px at ring[px & 3]: kept from the windows
    // before where they had them (windows go left to right: a ring of four never drops one
    // still needed).
    const Strip* window[3];
    for (int i = 0; i < 3; ++i) {
      Strip& s = ring[size_t((x - 1 + i) & 3)];
      if (s.px != x - 1 + i) fill_strip(s, epi, x - 1 + i, y, rows);
      window[i] = &s;
    }
    complex_window(window, estimate + 3 * x, out + 3 * x, geometry);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace epi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace epi {

HWY_EXPORT(ComplexRowKernel);

std::vector<int64_t> complex_row_targets() { return hwy::SupportedAndGeneratedTargets(); }

void complex_row(const EpiRows& epi, const BoundaryMasks& masks, int y, const uint8_t* types, const float* estimate,
                 float* out, ComplexRowCache& cache, int64_t target) {
  if (target == 0) return HWY_DYNAMIC_DISPATCH(ComplexRowKernel)(epi, masks, y, types, estimate, out, *cache.rows_);
  // hwy::SupportedTargets() runs CPUID (a trap to the hypervisor in a VM): asked once.
  static const int64_t supported = hwy::SupportedTargets() & HWY_TARGETS;
  if ((target & (target - 1)) != 0 || (target & supported) == 0)
    throw std::invalid_argument(std::string("complex_row: Highway target not compiled or not supported here: ") +
                                hwy::TargetName(target));
  // The dispatch table's index of a single target, as hwy::ChosenTarget computes it.
  const int64_t chosen = HWY_CHOSEN_TARGET_SHIFT(target) | HWY_CHOSEN_TARGET_MASK_SCALAR;
  HWY_DISPATCH_TABLE(ComplexRowKernel)[hwy::Num0BitsBelowLS1Bit_Nonzero64(uint64_t(chosen))](
      epi, masks, y, types, estimate, out, *cache.rows_);
}

}  // namespace epi
#endif  // HWY_ONCE

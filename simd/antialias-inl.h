// The anti-aliasing row kernel (per target; included by row_kernels.cpp through
// foreach_target.h): antialias_pixel (core/epi/antialias.cpp) lane by lane. The secondary
// colour is gathered from the neighbour the table names; colour = a * own + (1 - a) * secondary
// with the oracle's float operations in its order (no fused multiply-add), so every lane
// equals the oracle bit for bit. Non-simple pixels, and those whose neighbour lies outside the
// image, keep their own colour.
#if defined(EPI_SIMD_ANTIALIAS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_ANTIALIAS_INL_H_
#undef EPI_SIMD_ANTIALIAS_INL_H_
#else
#define EPI_SIMD_ANTIALIAS_INL_H_
#endif

#include <cstring>

#include <hwy/highway.h>

#include "simd/common-inl.h"
#include "simd/row_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// kNeighbourDx/Dy (tables.h) + 1 as 2-bit fields: dx 1,0,-1,0,1,-1,-1,1; dy 0,1,0,-1,1,1,-1,-1.
constexpr uint32_t kNeighbourDx = 2 | 1 << 2 | 0 << 4 | 1 << 6 | 2 << 8 | 0 << 10 | 0 << 12 | 2 << 14;
constexpr uint32_t kNeighbourDy = 1 | 2 << 2 | 1 << 4 | 0 << 6 | 2 << 8 | 2 << 10 | 0 << 12 | 0 << 14;

// One simple pixel x (type, code), the operations of one lane of AntialiasLanes in its order
// (so the same bits); `out` holds the own colour already.
inline void AntialiasPixel(const AntialiasRow& row, int x, uint32_t type, uint32_t code, const float* own, float* out) {
  const uint32_t packed = row.area_and_secondary[code];
  const bool primary_is_b = ((type - 2) & 1) != 0;
  const uint32_t secondary = packed >> 16;
  const uint32_t k = (primary_is_b ? secondary : secondary >> 4) & 15;
  const int dx = int((kNeighbourDx >> (2 * k)) & 3) - 1, dy = int((kNeighbourDy >> (2 * k)) & 3) - 1;
  const int nx = x + dx;
  const float* from = dy < 0 ? row.rows[0] : dy > 0 ? row.rows[2] : row.rows[1];
  if (nx < 0 || nx >= row.width || !from) return;
  const float* s = from + 3 * nx;
  const float area = float(int32_t(packed & 0xffffu)) * (1.0f / 65535.0f);
  const float a = primary_is_b ? 1.0f - area : area;
  const float not_a = 1.0f - a;
  for (int c = 0; c < 3; ++c) out[c] = a * own[c] + not_a * s[c];
}

// Lanes x .. x + N - 1; `types`, `edge`, `own` (the own colours) and `out` start at x; the
// secondary colours are gathered from the rows, or, for a vector with few simple pixels, read
// pixel by pixel (gathers cost per lane: on Zen 4 four gathers cost more than a few pixels).
template <class DF>
HWY_INLINE void AntialiasLanes(DF df, const AntialiasRow& row, int x, const uint8_t* types, const uint16_t* edge,
                               const float* own, float* out) {
  const hn::RebindToUnsigned<DF> du;
  const hn::RebindToSigned<DF> di;
  const hn::Rebind<uint8_t, DF> d8;
  const hn::Rebind<uint16_t, DF> d16;
  using VU = hn::Vec<decltype(du)>;
  using VI = hn::Vec<decltype(di)>;
  const VU type = hn::PromoteTo(du, hn::LoadU(d8, types));
  const VU code = hn::And(hn::PromoteTo(du, hn::LoadU(d16, edge)), hn::Set(du, 0x3ffu));
  const VU two = hn::Set(du, 2u), one = hn::Set(du, 1u);
  // Simple: 2 <= type < 14, i.e. (type - 2) < 12 unsigned; as an integer range on small values.
  const auto simple = hn::And(hn::Ne(hn::ShiftRight<1>(type), hn::Zero(du)),
                              hn::Eq(hn::And(hn::Add(type, two), hn::Set(du, ~15u)), hn::Zero(du)));
  if (hn::AllFalse(du, simple)) return CopyPixels(df, own, out);  // most vectors: the colours pass through
  const size_t simple_count = hn::CountTrue(du, simple);
  if (simple_count <= 4) {
    CopyPixels(df, own, out);
    HWY_ALIGN uint32_t t[HWY_LANES(uint32_t)], c[HWY_LANES(uint32_t)];
    hn::Store(type, du, t), hn::Store(code, du, c);
    for (size_t i = 0, found = 0; found < simple_count; ++i)
      if (t[i] >= 2 && t[i] < 14) AntialiasPixel(row, x + int(i), t[i], c[i], own + 3 * i, out + 3 * i), ++found;
    return;
  }
  hn::Vec<DF> r, g, b;
  hn::LoadInterleaved3(df, own, r, g, b);
  const auto primary_is_b = hn::RebindMask(df, hn::Ne(hn::And(hn::Sub(type, two), one), hn::Zero(du)));
  const VI code_i = hn::BitCast(di, code);
  // One gather: area of A in bits 0-15, the secondary neighbours in bits 16-23.
  const VU packed = hn::GatherIndex(du, row.area_and_secondary, code_i);
  const VU secondary = hn::ShiftRight<16>(packed);
  // The neighbour for the secondary region: B's nibble when B is secondary (A primary).
  const VU k = hn::And(hn::IfThenElse(hn::RebindMask(du, primary_is_b), secondary, hn::ShiftRight<4>(secondary)),
                       hn::Set(du, 15u));
  const VU shift = hn::ShiftLeft<1>(k);
  const VI dx = hn::Sub(hn::BitCast(di, hn::And(hn::Shr(hn::Set(du, kNeighbourDx), shift), hn::Set(du, 3u))), hn::Set(di, 1));
  const VI dy = hn::Sub(hn::BitCast(di, hn::And(hn::Shr(hn::Set(du, kNeighbourDy), shift), hn::Set(du, 3u))), hn::Set(di, 1));
  const VI nx = hn::Add(hn::Iota(di, x), dx);
  const auto up = hn::Eq(dy, hn::Set(di, -1)), down = hn::Eq(dy, hn::Set(di, 1));
  auto usable = hn::And(hn::RebindMask(di, simple),
                        hn::And(hn::Not(hn::Lt(nx, hn::Zero(di))), hn::Lt(nx, hn::Set(di, row.width))));
  if (!row.rows[0]) usable = hn::AndNot(up, usable);
  if (!row.rows[2]) usable = hn::AndNot(down, usable);
  // Gather offsets relative to the own row (the three rows lie in one allocation).
  const int32_t off_up = row.rows[0] ? int32_t(row.rows[0] - row.rows[1]) : 0;
  const int32_t off_down = row.rows[2] ? int32_t(row.rows[2] - row.rows[1]) : 0;
  const VI row_offset = hn::IfThenElse(up, hn::Set(di, off_up), hn::IfThenElseZero(down, hn::Set(di, off_down)));
  const VI index = hn::IfThenElseZero(usable, hn::Add(row_offset, hn::Mul(nx, hn::Set(di, 3))));
  const auto sr = hn::GatherIndex(df, row.rows[1], index);
  const auto sg = hn::GatherIndex(df, row.rows[1] + 1, index);
  const auto sb = hn::GatherIndex(df, row.rows[1] + 2, index);
  const auto area = hn::Mul(hn::ConvertTo(df, hn::BitCast(di, hn::And(packed, hn::Set(du, 0xffffu)))),
                            hn::Set(df, 1.0f / 65535.0f));
  const auto a = hn::IfThenElse(primary_is_b, hn::Sub(hn::Set(df, 1.0f), area), area);
  const auto not_a = hn::Sub(hn::Set(df, 1.0f), a);
  const auto blend = hn::RebindMask(df, usable);
  const auto br = hn::Add(hn::Mul(a, r), hn::Mul(not_a, sr));
  const auto bg = hn::Add(hn::Mul(a, g), hn::Mul(not_a, sg));
  const auto bb = hn::Add(hn::Mul(a, b), hn::Mul(not_a, sb));
  hn::StoreInterleaved3(hn::IfThenElse(blend, br, r), hn::IfThenElse(blend, bg, g), hn::IfThenElse(blend, bb, b), df,
                        out);
}

inline void AntialiasRowKernel(const AntialiasRow& row) {
  const hn::ScalableTag<float> df;
  const int n = int(hn::Lanes(df));
  int x = 0;
  for (; x + n <= row.width; x += n)
    AntialiasLanes(df, row, x, row.types + x, row.edge + x, row.rows[1] + 3 * x, row.out + 3 * x);
  if (x == row.width) return;
  // The last, partial vector: the own colours and outputs through buffers (lanes beyond the
  // row are not simple: type 0, so they gather nothing).
  constexpr int kMax = HWY_LANES(float);
  const int rest = row.width - x;
  uint8_t types[kMax] = {};
  uint16_t edge[kMax] = {};
  HWY_ALIGN float own[3 * kMax] = {}, out[3 * kMax];
  std::memcpy(types, row.types + x, size_t(rest));
  std::memcpy(edge, row.edge + x, size_t(rest) * sizeof(uint16_t));
  std::memcpy(own, row.rows[1] + 3 * x, size_t(rest) * 3 * sizeof(float));
  AntialiasLanes(df, row, x, types, edge, own, out);
  std::memcpy(row.out + 3 * x, out, size_t(rest) * 3 * sizeof(float));
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_ANTIALIAS_INL_H_

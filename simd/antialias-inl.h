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

#include <hwy/cache_control.h>
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

// One simple pixel x (type, code): antialias_pixel's operations in its order (so the same
// bits), without branches on the data but the rare one at the image border; `out` holds the
// own colour already. rows[k]: row y - 1 + k, nullptr outside the image.
inline void AntialiasPixel(const AntialiasRow& row, int x, uint32_t type, uint32_t code, float* out) {
  const uint32_t packed = row.area_and_secondary[code];
  const uint32_t primary_is_b = (type - 2) & 1;
  // The neighbour for the secondary region: B's nibble (bits 16-19) when B is secondary.
  const uint32_t k = (packed >> (16 + 4 * (primary_is_b ^ 1))) & 15;
  const int dx = int((kNeighbourDx >> (2 * k)) & 3) - 1, dy = int((kNeighbourDy >> (2 * k)) & 3);
  const int nx = x + dx;
  const float* from = row.rows[dy];
  if (unsigned(nx) >= unsigned(row.width) || !from) return;  // outside: keeps its own colour
  const float* own = row.rows[1] + 3 * x;
  const float* s = from + 3 * nx;
  const float area = float(int32_t(packed & 0xffffu)) * (1.0f / 65535.0f);
  const float not_area = 1.0f - area;
  // a = primary_is_b ? 1 - area : area, selected on the bits.
  uint32_t area_bits, not_area_bits;
  std::memcpy(&area_bits, &area, 4), std::memcpy(&not_area_bits, &not_area, 4);
  const uint32_t pick = 0u - primary_is_b;
  const uint32_t a_bits = (not_area_bits & pick) | (area_bits & ~pick);
  float a;
  std::memcpy(&a, &a_bits, 4);
  const float not_a = 1.0f - a;
  const float r = a * own[0] + not_a * s[0], g = a * own[1] + not_a * s[1], b = a * own[2] + not_a * s[2];
  out[0] = r, out[1] = g, out[2] = b;
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

// The simple pixels (2 <= type < 14) among types[0 .. kAntialiasChunk), one bit each.
constexpr int kAntialiasChunk = 64;
HWY_INLINE uint64_t SimpleBits(const uint8_t* types) {
  const hn::ScalableTag<uint8_t> d8;
  constexpr int kMaxLanes = HWY_LANES(uint8_t) < kAntialiasChunk ? HWY_LANES(uint8_t) : kAntialiasChunk;
  const int n = int(hn::Lanes(d8)) < kAntialiasChunk ? int(hn::Lanes(d8)) : kAntialiasChunk;
  const hn::CappedTag<uint8_t, kMaxLanes> dc;
  uint64_t bits = 0;
  for (int i = 0; i < kAntialiasChunk; i += n) {
    const auto t = hn::Sub(hn::LoadU(dc, types + i), hn::Set(dc, uint8_t{2}));  // wraps below 2
    const auto simple = hn::Eq(hn::Min(t, hn::Set(dc, uint8_t{11})), t);        // t - 2 <= 11, unsigned
    uint8_t stored[8] = {};
    hn::StoreMaskBits(dc, simple, stored);
    uint64_t b;
    std::memcpy(&b, stored, 8);
    bits |= (n == 64 ? b : b & ((uint64_t{1} << n) - 1)) << i;
  }
  return bits;
}

// The row in chunks of 64 pixels: the own colours copied as they are (most pixels pass
// through), then each simple pixel of the chunk blended, found by its bit; a float vector
// with more than kGatherFrom simple pixels is blended in lanes (gathers) instead.
constexpr size_t kGatherFrom = 8;
constexpr int kPrefetchAhead = 8 * kAntialiasChunk;  // pixels
inline void AntialiasRowKernel(const AntialiasRow& row) {
  const hn::ScalableTag<float> df;
  const int nf = int(hn::Lanes(df));
  const float* own = row.rows[1];
  float* const out = row.out;
  for (int x0 = 0; x0 < row.width; x0 += kAntialiasChunk) {
    const int chunk = row.width - x0 < kAntialiasChunk ? row.width - x0 : kAntialiasChunk;
    // Row y + 1 is read only where a secondary neighbour lies below: scattered loads that the
    // hardware prefetcher does not follow, each a miss in the staged schedule (whole-image
    // planes). It is the next row's own row, so bringing it in now costs no extra traffic.
    if (row.rows[2])
      for (int i = 0; i < 3 * kAntialiasChunk; i += 16) hwy::Prefetch(row.rows[2] + 3 * (x0 + kPrefetchAhead) + i);
    // The edge words too: read only at simple pixels.
    hwy::Prefetch(row.edge + x0 + kPrefetchAhead), hwy::Prefetch(row.edge + x0 + kPrefetchAhead + 32);
    uint64_t bits;
    if (chunk == kAntialiasChunk) {
      for (int i = 0; i < 3 * kAntialiasChunk; i += nf) hn::StoreU(hn::LoadU(df, own + 3 * x0 + i), df, out + 3 * x0 + i);
      bits = SimpleBits(row.types + x0);
    } else {
      std::memcpy(out + 3 * x0, own + 3 * x0, size_t(chunk) * 3 * sizeof(float));
      uint8_t types[kAntialiasChunk] = {};  // type 0 beyond the row: not simple
      std::memcpy(types, row.types + x0, size_t(chunk));
      bits = SimpleBits(types);
    }
    if (nf > 1) {
      // Dense vectors in lanes; their bits cleared.
      const uint64_t lanes = nf == 64 ? ~uint64_t{0} : (uint64_t{1} << nf) - 1;
      for (int i = 0; i + nf <= chunk; i += nf)
        if (size_t(hwy::PopCount((bits >> i) & lanes)) > kGatherFrom) {
          const int x = x0 + i;
          AntialiasLanes(df, row, x, row.types + x, row.edge + x, own + 3 * x, out + 3 * x);
          bits &= ~(lanes << i);
        }
    }
    for (; bits; bits &= bits - 1) {
      const int x = x0 + int(hwy::Num0BitsBelowLS1Bit_Nonzero64(bits));
      AntialiasPixel(row, x, row.types[x], row.edge[x] & 0x3ffu, out + 3 * x);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_ANTIALIAS_INL_H_

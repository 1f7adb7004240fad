// The anti-aliasing row kernel (per target; included by row_kernels.cpp through
// foreach_target.h): antialias_pixel (core/epi/antialias.cpp) over a row. Most pixels pass
// through: the row is copied in vectors, a chunk of 64 pixels at a time, and the simple pixels
// of the chunk, found by the bits of a vector compare of their types, are then blended one by
// one: colour = a * own + (1 - a) * secondary with the oracle's float operations in its order
// (no fused multiply-add), so every pixel equals the oracle bit for bit. Non-simple pixels,
// and those whose neighbour lies outside the image, keep their own colour.
#if defined(EPI_SIMD_ANTIALIAS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_ANTIALIAS_INL_H_
#undef EPI_SIMD_ANTIALIAS_INL_H_
#else
#define EPI_SIMD_ANTIALIAS_INL_H_
#endif

#include <cstring>

#include <hwy/cache_control.h>
#include <hwy/highway.h>

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

// The simple pixels (2 <= type < 14) among types[0 .. kAntialiasChunk), one bit each.
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
// through), then each simple pixel of the chunk blended, found by its bit. (Blending dense
// vectors in lanes, with the secondary colours gathered, was slower even with many edges:
// docs/epi.md, "SIMD kernels".)
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

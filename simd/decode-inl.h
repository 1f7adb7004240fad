// The decode row kernel (per target; included by row_kernels.cpp through foreach_target.h):
// a classified row into the planes the other kernels read (DecodeRow). Table lookups only.
#if defined(EPI_SIMD_DECODE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_DECODE_INL_H_
#undef EPI_SIMD_DECODE_INL_H_
#else
#define EPI_SIMD_DECODE_INL_H_
#endif

#include <cstring>

#include <hwy/highway.h>

#include "simd/row_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class DF>
HWY_INLINE void DecodeLanes(DF df, const DecodeRow& row, const uint16_t* edge_in,
                            const uint32_t* color_in, float* red, float* green, float* blue, float* usable,
                            float* sampled) {
  const hn::RebindToUnsigned<DF> du;
  const hn::RebindToSigned<DF> di;
  const hn::Rebind<uint16_t, DF> d16;
  const auto byte = hn::Set(du, 255u);
  const auto color = hn::LoadU(du, color_in);
  const auto r = hn::GatherIndex(df, row.lut, hn::BitCast(di, hn::And(color, byte)));
  hn::StoreU(hn::GatherIndex(df, row.lut, hn::BitCast(di, hn::And(hn::ShiftRight<8>(color), byte))), df, green);
  hn::StoreU(hn::GatherIndex(df, row.lut, hn::BitCast(di, hn::And(hn::ShiftRight<16>(color), byte))), df, blue);
  const auto edge = hn::PromoteTo(du, hn::LoadU(d16, edge_in));
  const auto one = hn::Set(df, 1.0f);
  const auto use = hn::RebindMask(df, hn::Ne(hn::And(edge, hn::Set(du, 0x8000u)), hn::Zero(du)));
  hn::StoreU(hn::IfThenElseZero(use, one), df, usable);
  hn::StoreU(hn::Or(r, hn::IfThenZeroElse(use, hn::Set(df, -0.0f))), df, red);  // the sign: not usable
  hn::StoreU(hn::IfThenElseZero(hn::RebindMask(df, hn::Ne(hn::And(edge, hn::Set(du, 0x4000u)), hn::Zero(du))), one),
             df, sampled);
}

// At most 8 lanes: the colour lookups are gathers, and on Zen 4 a 16-lane gather costs more than
// two of 8 lanes (1080p, AVX3: 4.3-4.8 ms with 16 lanes, about AVX2's 3 ms with 8).
inline void DecodeRowKernel(const DecodeRow& row) {
  const hn::CappedTag<float, 8> df;
  const int n = int(hn::Lanes(df));
  int x = 0;
  for (; x + n <= row.width; x += n)
    DecodeLanes(df, row, row.edge + x, row.color + x, row.red + x, row.green + x, row.blue + x,
                row.usable + x, row.sampled + x);
  if (x == row.width) return;
  // The last, partial vector through buffers: the planes' padding must stay as it is.
  constexpr int kMax = HWY_LANES(float);
  const int rest = row.width - x;
  uint16_t edge[kMax] = {};
  uint32_t color[kMax] = {};
  float red[kMax], green[kMax], blue[kMax], usable[kMax], sampled[kMax];
  std::memcpy(edge, row.edge + x, size_t(rest) * sizeof(uint16_t));
  std::memcpy(color, row.color + x, size_t(rest) * sizeof(uint32_t));
  DecodeLanes(df, row, edge, color, red, green, blue, usable, sampled);
  const size_t bytes = size_t(rest) * sizeof(float);
  std::memcpy(row.red + x, red, bytes), std::memcpy(row.green + x, green, bytes), std::memcpy(row.blue + x, blue, bytes);
  std::memcpy(row.usable + x, usable, bytes), std::memcpy(row.sampled + x, sampled, bytes);
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_DECODE_INL_H_

// The fill row kernel (per target; included by row_kernels.cpp through foreach_target.h):
// fill_pixel (core/epi/fill.cpp) lane by lane. Vectors whose pixels all found samples pass
// their colours through; the others sum the 5x5 in the oracle's order, skipped taps weighing
// 0 (padding holds zeros), so every lane equals the oracle bit for bit.
#if defined(EPI_SIMD_FILL_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_FILL_INL_H_
#undef EPI_SIMD_FILL_INL_H_
#else
#define EPI_SIMD_FILL_INL_H_
#endif

#include <cstring>

#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include "simd/interpolate-inl.h"
#include "simd/common-inl.h"
#include "simd/row_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Lanes x .. x + N - 1; `reach` and `out` start at x.
template <class DF>
HWY_INLINE void FillLanes(DF df, const FillRow& row, int x, const uint32_t* reach, float* out) {
  const hn::RebindToUnsigned<DF> du;
  const hn::Rebind<uint8_t, DF> d8;
  const auto found = hn::Ne(hn::PromoteTo(du, hn::LoadU(d8, row.found[2] + x)), hn::Zero(du));
  if (hn::AllTrue(du, found)) {  // nothing to fill
    if (out != row.rows[2] + 3 * x) CopyPixels(df, row.rows[2] + 3 * x, out);
    return;
  }
  hn::Vec<DF> r, g, b;
  hn::LoadInterleaved3(df, row.rows[2] + 3 * x, r, g, b);
  // The 24-bit mask spread over the 25 window positions, the centre left out.
  const auto rm = hn::LoadU(du, reach);
  const auto take = hn::Or(hn::And(rm, hn::Set(du, 0xfffu)), hn::ShiftLeft<1>(hn::And(rm, hn::Set(du, 0xfff000u))));
  auto sr = hn::Zero(df), sg = hn::Zero(df), sb = hn::Zero(df), total = hn::Zero(df);
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int k = (dy + 2) * 5 + dx + 2;
      const auto use = hn::And(hn::Ne(hn::And(take, hn::Set(du, 1u << k)), hn::Zero(du)),
                               hn::Ne(hn::PromoteTo(du, hn::LoadU(d8, row.found[dy + 2] + x + dx)), hn::Zero(du)));
      const auto w = hn::IfThenElseZero(hn::RebindMask(df, use), hn::Set(df, InterpolationWeight(dx, dy)));
      hn::Vec<DF> cr, cg, cb;
      hn::LoadInterleaved3(df, row.rows[dy + 2] + 3 * (x + dx), cr, cg, cb);
      sr = hn::Add(sr, hn::Mul(w, cr));
      sg = hn::Add(sg, hn::Mul(w, cg));
      sb = hn::Add(sb, hn::Mul(w, cb));
      total = hn::Add(total, w);
    }
  const auto fill = hn::And(hn::RebindMask(df, hn::Not(found)), hn::Gt(total, hn::Zero(df)));
  const auto safe = hn::IfThenElse(fill, total, hn::Set(df, 1.0f));
  hn::StoreInterleaved3(hn::IfThenElse(fill, hn::Div(sr, safe), r), hn::IfThenElse(fill, hn::Div(sg, safe), g),
                        hn::IfThenElse(fill, hn::Div(sb, safe), b), df, out);
}

// The colours and found flags of rows y + 1 and y + 2 at pixels x .. x + kFillPrefetchStep - 1.
constexpr int kFillPrefetchStep = 64, kFillPrefetchAhead = 8 * kFillPrefetchStep;
inline void PrefetchRowsBelow(const FillRow& row, int x) {
  for (int k = 3; k < 5; ++k) {
    for (int i = 0; i < 3 * kFillPrefetchStep; i += 16) hwy::Prefetch(row.rows[k] + 3 * x + i);
    hwy::Prefetch(row.found[k] + x);
  }
}

inline void FillRowKernel(const FillRow& row) {
  const hn::ScalableTag<float> df;
  const int n = int(hn::Lanes(df));
  int x = 0;
  if (row.out == row.rows[2]) {
    // In place: found pixels stay as they are, so 64 pixels whose flags are all set are skipped
    // on one compare of their flags (most of them).
    const hn::ScalableTag<uint8_t> d8;
    const int n8 = int(hn::Lanes(d8));
    for (; x + n8 <= row.width; x += n8)
      if (!hn::AllTrue(d8, hn::Ne(hn::LoadU(d8, row.found[2] + x), hn::Zero(d8))))
        for (int i = x; i < x + n8; i += n) FillLanes(df, row, i, row.reach + i, row.out + 3 * i);
  }
  for (; x + n <= row.width; x += n) {
    // Rows y + 1 and y + 2 are read only by vectors with a pixel to fill: scattered loads the
    // hardware prefetcher does not follow, each a miss in the staged schedule (whole-image
    // planes). They are the next rows' own rows, so bringing them in now costs no extra traffic.
    if ((x & (kFillPrefetchStep - 1)) == 0) PrefetchRowsBelow(row, x + kFillPrefetchAhead);
    FillLanes(df, row, x, row.reach + x, row.out + 3 * x);
  }
  if (x == row.width) return;
  constexpr int kMax = HWY_LANES(float);
  const int rest = row.width - x;
  uint32_t reach[kMax] = {};
  HWY_ALIGN float out[3 * kMax];
  std::memcpy(reach, row.reach + x, size_t(rest) * sizeof(uint32_t));
  FillLanes(df, row, x, reach, out);  // the padded rows hold zeros beyond the row
  std::memcpy(row.out + 3 * x, out, size_t(rest) * 3 * sizeof(float));
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_FILL_INL_H_

// The interpolation row kernel (per target; included by row_kernels.cpp through
// foreach_target.h). The same sums as core/epi's weighted_sum, lane by lane: taps in the
// oracle's order (dy, then dx), each weight multiplied by 0 or 1 and the products added
// separately (no fused multiply-add: the project builds with -ffp-contract=off), so every
// lane equals the oracle bit for bit. Pixels outside the image are padded zeros: weight 0
// adds +0, as the oracle's skipped taps add nothing.
#if defined(EPI_SIMD_INTERPOLATE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_INTERPOLATE_INL_H_
#undef EPI_SIMD_INTERPOLATE_INL_H_
#else
#define EPI_SIMD_INTERPOLATE_INL_H_
#endif

#include <algorithm>
#include <cstring>

#include <hwy/highway.h>

#include "simd/row_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// w(dx, dy) = 1 / (1 + dx^2 + dy^2)^2, in the oracle's float constants (interpolate.cpp).
inline float InterpolationWeight(int dx, int dy) {
  static constexpr float kWeights[25] = {
      1.0f / 81, 1.0f / 36, 1.0f / 25, 1.0f / 36, 1.0f / 81,  //
      1.0f / 36, 1.0f / 9,  1.0f / 4,  1.0f / 9,  1.0f / 36,  //
      1.0f / 25, 1.0f / 4,  1.0f,      1.0f / 4,  1.0f / 25,  //
      1.0f / 36, 1.0f / 9,  1.0f / 4,  1.0f / 9,  1.0f / 36,  //
      1.0f / 81, 1.0f / 36, 1.0f / 25, 1.0f / 36, 1.0f / 81};
  return kWeights[(dy + 2) * 5 + dx + 2];
}

// The outputs of a weighted mean (interpolate.h): the colour where something was found (the
// rest is left to the caller's fallback), found (total weight > 0) as a byte, and the
// priority: the age of an own sample (`own`: 1 or 0) / 16, else 1 / total capped at 15.
template <class DF>
HWY_INLINE void StoreMean(DF df, const float* own, const uint32_t* color, hn::Vec<DF> sr, hn::Vec<DF> sg,
                          hn::Vec<DF> sb, hn::Vec<DF> total, float* rgb, uint8_t* found_out, float* priority_out) {
  const hn::RebindToUnsigned<DF> du;
  const hn::RebindToSigned<DF> di;
  const auto found = hn::Gt(total, hn::Zero(df));
  const auto safe = hn::IfThenElse(found, total, hn::Set(df, 1.0f));  // division only where found
  hn::StoreInterleaved3(hn::Div(sr, safe), hn::Div(sg, safe), hn::Div(sb, safe), df, rgb);
  hn::StoreU(hn::DemoteTo(hn::Rebind<uint8_t, DF>(), hn::IfThenElseZero(hn::RebindMask(di, found), hn::Set(di, 1))),
             hn::Rebind<uint8_t, DF>(), found_out);
  const auto own_sample = hn::Gt(hn::LoadU(df, own), hn::Zero(df));
  const auto age = hn::Mul(hn::ConvertTo(df, hn::BitCast(di, hn::ShiftRight<24>(hn::LoadU(du, color)))),
                           hn::Set(df, 1.0f / 16.0f));
  const auto by_weight = hn::IfThenElse(hn::Gt(hn::Mul(total, hn::Set(df, 15.0f)), hn::Set(df, 1.0f)),
                                        hn::Div(hn::Set(df, 1.0f), safe), hn::Set(df, 15.0f));
  hn::StoreU(hn::IfThenElse(own_sample, age, by_weight), df, priority_out);
}

// The 25 taps in the oracle's order (dy, then dx), tap k = (dy + 2) * 5 + dx + 2 taken where
// bit k of `take` is set; flags (1 or 0) from `usable`, for kComplex lanes from `sampled`.
template <bool kComplex, class DF>
HWY_INLINE void SumTaps(DF df, const InterpolateRow& row, int x, hn::Vec<hn::RebindToUnsigned<DF>> take,
                        hn::Mask<DF> complex, hn::Vec<DF>& sr, hn::Vec<DF>& sg, hn::Vec<DF>& sb, hn::Vec<DF>& total) {
  const hn::RebindToUnsigned<DF> du;
  const hn::RebindToSigned<DF> di;
  for (int dy = -2; dy <= 2; ++dy) {
    const int k0 = (dy + 2) * 5;
    const float* red = row.red[dy + 2] + kPad + x;
    const float* green = row.green[dy + 2] + kPad + x;
    const float* blue = row.blue[dy + 2] + kPad + x;
    const float* usable = row.usable[dy + 2] + kPad + x;
    const float* sampled = row.sampled[dy + 2] + kPad + x;
    for (int dx = -2; dx <= 2; ++dx) {
      const auto bit = hn::RebindMask(df, hn::TestBit(take, hn::Set(du, 1u << (k0 + dx + 2))));
      if (!kComplex) {  // usable: red's sign clear; else w = +0 and +0 x -red adds -0: unchanged
        const auto r = hn::LoadU(df, red + dx);
        const auto unusable = hn::RebindMask(df, hn::Lt(hn::BitCast(di, r), hn::Zero(di)));
        const auto w = hn::IfThenElseZero(hn::AndNot(unusable, bit), hn::Set(df, InterpolationWeight(dx, dy)));
        sr = hn::Add(sr, hn::Mul(w, r));
        sg = hn::Add(sg, hn::Mul(w, hn::LoadU(df, green + dx)));
        sb = hn::Add(sb, hn::Mul(w, hn::LoadU(df, blue + dx)));
        total = hn::Add(total, w);
        continue;
      }
      const auto flag = hn::IfThenElse(complex, hn::LoadU(df, sampled + dx), hn::LoadU(df, usable + dx));
      const auto w = hn::IfThenElseZero(bit, hn::Mul(hn::Set(df, InterpolationWeight(dx, dy)), flag));
      sr = hn::Add(sr, hn::Mul(w, hn::Abs(hn::LoadU(df, red + dx))));
      sg = hn::Add(sg, hn::Mul(w, hn::LoadU(df, green + dx)));
      sb = hn::Add(sb, hn::Mul(w, hn::LoadU(df, blue + dx)));
      total = hn::Add(total, w);
    }
  }
}

// Lanes x .. x + N - 1 of the row; `types`, `reach`, `color` and the outputs start at x.
template <class DF>
HWY_INLINE void InterpolateLanes(DF df, const InterpolateRow& row, int x, const uint8_t* types,
                                 const uint32_t* reach, const uint32_t* color, float* rgb, uint8_t* found_out,
                                 float* priority_out) {
  const hn::RebindToUnsigned<DF> du;
  const hn::Rebind<uint8_t, DF> d8;
  using VU = hn::Vec<decltype(du)>;
  const auto complex = hn::Eq(hn::PromoteTo(du, hn::LoadU(d8, types)), hn::Set(du, 1u));
  const VU r = hn::LoadU(du, reach);
  // The reach mask spread over the 25 window positions (centre bit 12 always set); complex
  // pixels take every sample of the 5x5 (the simple estimate).
  const VU window = hn::Or(hn::Or(hn::And(r, hn::Set(du, 0xfffu)), hn::Set(du, 1u << 12)),
                           hn::ShiftLeft<1>(hn::And(r, hn::Set(du, 0xfff000u))));
  const VU take = hn::IfThenElse(complex, hn::Set(du, 0x1ffffffu), window);
  auto sr = hn::Zero(df), sg = hn::Zero(df), sb = hn::Zero(df), total = hn::Zero(df);
  // Most vectors hold no complex pixel: only the usable flags.
  if (hn::AllFalse(du, complex)) SumTaps<false>(df, row, x, take, hn::RebindMask(df, complex), sr, sg, sb, total);
  else SumTaps<true>(df, row, x, take, hn::RebindMask(df, complex), sr, sg, sb, total);
  // Priority from a usable own sample (an edge-ambiguous one counts as none).
  StoreMean(df, row.usable[2] + kPad + x, color, sr, sg, sb, total, rgb, found_out, priority_out);
}

// The render cache's filter (rendercache.cpp) lane by lane: the 3x3 of every sample, weights
// 1, 1/2, 1/4, in the oracle's order (dy, then dx); priority from any own sample.
template <class DF>
HWY_INLINE void RenderCacheLanes(DF df, const InterpolateRow& row, int x, const uint8_t*, const uint32_t*,
                                 const uint32_t* color, float* rgb, uint8_t* found_out, float* priority_out) {
  static constexpr float kWeights[9] = {0.25f, 0.5f, 0.25f, 0.5f, 1.0f, 0.5f, 0.25f, 0.5f, 0.25f};
  auto sr = hn::Zero(df), sg = hn::Zero(df), sb = hn::Zero(df), total = hn::Zero(df);
  for (int dy = -1; dy <= 1; ++dy) {
    const int k = dy + 2;
    for (int dx = -1; dx <= 1; ++dx) {
      const size_t i = size_t(kPad + x + dx);
      const auto w = hn::Mul(hn::Set(df, kWeights[(dy + 1) * 3 + dx + 1]), hn::LoadU(df, row.sampled[k] + i));
      sr = hn::Add(sr, hn::Mul(w, hn::Abs(hn::LoadU(df, row.red[k] + i))));
      sg = hn::Add(sg, hn::Mul(w, hn::LoadU(df, row.green[k] + i)));
      sb = hn::Add(sb, hn::Mul(w, hn::LoadU(df, row.blue[k] + i)));
      total = hn::Add(total, w);
    }
  }
  StoreMean(df, row.sampled[2] + kPad + x, color, sr, sg, sb, total, rgb, found_out, priority_out);
}

// A row of `lanes` (InterpolateLanes, RenderCacheLanes): full vectors, then the last, partial
// one with the own row's inputs and outputs through buffers of full vectors (the padded planes
// hold zeros beyond the row).
template <class Lanes>
HWY_INLINE void MeanRow(const InterpolateRow& row, Lanes lanes) {
  const hn::ScalableTag<float> df;
  const int n = int(hn::Lanes(df));
  int x = 0;
  for (; x + n <= row.width; x += n)
    lanes(df, row, x, row.types + x, row.reach + x, row.color + x, row.rgb + 3 * x, row.found + x, row.priority + x);
  if (x == row.width) return;
  constexpr int kMax = HWY_LANES(float);
  HWY_ALIGN uint8_t types[kMax] = {};
  HWY_ALIGN uint32_t reach[kMax] = {}, color[kMax] = {};
  HWY_ALIGN float rgb[3 * kMax], priority[kMax];
  HWY_ALIGN uint8_t found[kMax];
  const int rest = row.width - x;
  std::memcpy(types, row.types + x, size_t(rest));
  std::memcpy(reach, row.reach + x, size_t(rest) * 4);
  std::memcpy(color, row.color + x, size_t(rest) * 4);
  lanes(df, row, x, types, reach, color, rgb, found, priority);
  std::memcpy(row.rgb + 3 * x, rgb, size_t(rest) * 12);
  std::memcpy(row.found + x, found, size_t(rest));
  std::memcpy(row.priority + x, priority, size_t(rest) * 4);
}

inline void InterpolateRowKernel(const InterpolateRow& row) {
  MeanRow(row, [](auto... a) { InterpolateLanes(a...); });
}
inline void RenderCacheRowKernel(const InterpolateRow& row) {
  MeanRow(row, [](auto... a) { RenderCacheLanes(a...); });
}

// The fallback's whole-window mean (WindowMeanRow) for lanes x .. x + N - 1: interpolate.cpp's
// whole_window_mean lane by lane, its taps in its order (dy, then dx), a sample that is not
// usable weighing +0 (and adding -0 x colour: unchanged, as the oracle's +0). Weights as the
// oracle's window7_weights. Only the outer ring's 24 taps: a taken pixel reached no usable
// sample in its 5x5 (WindowMeanRow), so the inner 25 would each add +0 or -0 to sums that start
// at +0 and never go negative, which changes no bit. kMasked: also a sample its 7x7 mask does
// not reach weighs +0 (reachable_mean), and found gets whether any sample counted.
template <bool kMasked, class DF>
HWY_INLINE void WindowMeanLanes(DF df, const WindowMeanRow& row, int x, hn::Mask<DF> take, float* rgb,
                                const uint64_t* masks, uint8_t* found) {
  const hn::RebindToSigned<DF> di;
  const hn::RebindToUnsigned<DF> du;
  hn::Vec<decltype(du)> low, high;  // the masks' bits 0-31 and 32-63, lane by lane
  if constexpr (kMasked) hn::LoadInterleaved2(du, reinterpret_cast<const uint32_t*>(masks), low, high);
  auto sr = hn::Zero(df), sg = hn::Zero(df), sb = hn::Zero(df), total = hn::Zero(df);
  for (int dy = -3; dy <= 3; ++dy) {
    const size_t i = size_t(kPad + x - 3);
    const float* red = row.red[dy + 3] + i;
    const float* green = row.green[dy + 3] + i;
    const float* blue = row.blue[dy + 3] + i;
    for (int k = 0; k < 7; ++k) {
      if (dy > -3 && dy < 3 && k > 0 && k < 6) continue;  // the inner 5x5: no usable sample
      const float d = float(1 + (k - 3) * (k - 3) + dy * dy);
      const auto r = hn::LoadU(df, red + k);
      auto unusable = hn::RebindMask(df, hn::Lt(hn::BitCast(di, r), hn::Zero(di)));
      if constexpr (kMasked) {
        const int bit = (dy + 3) * 7 + k;
        const auto reached = bit < 32 ? hn::TestBit(low, hn::Set(du, 1u << bit)) : hn::TestBit(high, hn::Set(du, 1u << (bit - 32)));
        unusable = hn::Or(unusable, hn::Not(hn::RebindMask(df, reached)));
      }
      const auto w = hn::IfThenZeroElse(unusable, hn::Set(df, 1.0f / (d * d)));
      sr = hn::Add(sr, hn::Mul(w, r));
      sg = hn::Add(sg, hn::Mul(w, hn::LoadU(df, green + k)));
      sb = hn::Add(sb, hn::Mul(w, hn::LoadU(df, blue + k)));
      total = hn::Add(total, w);
    }
  }
  const auto some = hn::Gt(total, hn::Zero(df));
  const auto safe = hn::IfThenElse(some, total, hn::Set(df, 1.0f));
  hn::Vec<DF> r0, g0, b0;
  hn::LoadInterleaved3(df, rgb, r0, g0, b0);
  const auto keep = hn::Not(take);
  const auto mean = [&](hn::Vec<DF> sum, hn::Vec<DF> old) {
    return hn::IfThenElse(keep, old, hn::IfThenElseZero(some, hn::Div(sum, safe)));
  };
  hn::StoreInterleaved3(mean(sr, r0), mean(sg, g0), mean(sb, b0), df, rgb);
  if constexpr (kMasked) {
    const hn::Rebind<uint8_t, DF> d8;
    hn::StoreU(hn::DemoteTo(d8, hn::IfThenElseZero(hn::RebindMask(di, some), hn::Set(di, 1))), d8, found);
  }
}

// Vectors over [first, end) holding a pixel to take, the last partial one (past the row's end)
// through buffers; the planes' padding (zeros, a vector's worth and more) covers its loads.
template <bool kMasked>
void WindowMeanRowLanes(const WindowMeanRow& row) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::Rebind<uint8_t, decltype(df)> d8;
  const int n = int(hn::Lanes(df));
  // take[x] beyond `end` is not the caller's: lanes from there on are left out.
  const auto taken = [&](const uint8_t* take, int x) {
    return hn::And(hn::RebindMask(df, hn::Ne(hn::PromoteTo(di, hn::LoadU(d8, take)), hn::Zero(di))),
                   hn::FirstN(df, size_t(std::min(n, row.end - x))));
  };
  // No pixel closer than 3 to the left side is taken: vectors from there read no padding's left.
  for (int x = std::max(row.first, 3); x < row.end; x += n) {
    if (x + n <= row.width) {
      const auto take = taken(row.take + x, x);
      if (!hn::AllFalse(df, take))
        WindowMeanLanes<kMasked>(df, row, x, take, row.rgb + 3 * x, kMasked ? row.masks + x : nullptr,
                                 kMasked ? row.found + x : nullptr);  // (no offset on a null pointer)
      continue;
    }
    constexpr int kMax = HWY_LANES(float);
    const size_t rest = size_t(row.width - x);
    HWY_ALIGN uint8_t take[kMax] = {}, found[kMax] = {};
    HWY_ALIGN float rgb[3 * kMax] = {};
    HWY_ALIGN uint64_t masks[kMax] = {};
    std::memcpy(take, row.take + x, rest);
    std::memcpy(rgb, row.rgb + 3 * x, rest * 12);
    if (kMasked) std::memcpy(masks, row.masks + x, rest * sizeof(uint64_t));
    WindowMeanLanes<kMasked>(df, row, x, taken(take, x), rgb, masks, found);
    std::memcpy(row.rgb + 3 * x, rgb, rest * 12);
    if (kMasked) std::memcpy(row.found + x, found, rest);
  }
}

inline void WindowMeanRowKernel(const WindowMeanRow& row) {
  if (row.masks) WindowMeanRowLanes<true>(row);
  else WindowMeanRowLanes<false>(row);
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_INTERPOLATE_INL_H_

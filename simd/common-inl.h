// Helpers the row kernels share (per target; included by the kernels' -inl.h headers).
#if defined(EPI_SIMD_COMMON_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_COMMON_INL_H_
#undef EPI_SIMD_COMMON_INL_H_
#else
#define EPI_SIMD_COMMON_INL_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// N pixels of 3 floats from `from` to `to`, unchanged (no de-interleaving).
template <class DF>
HWY_INLINE void CopyPixels(DF df, const float* from, float* to) {
  const size_t n = hn::Lanes(df);
  hn::StoreU(hn::LoadU(df, from), df, to);
  hn::StoreU(hn::LoadU(df, from + n), df, to + n);
  hn::StoreU(hn::LoadU(df, from + 2 * n), df, to + 2 * n);
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_COMMON_INL_H_

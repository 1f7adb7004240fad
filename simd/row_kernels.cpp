// The per-target tables of row kernels (foreach_target.h compiles this file once per target).
#include "simd/row_kernels.h"

#include <stdexcept>
#include <string>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "simd/row_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "simd/antialias-inl.h"
#include "simd/classify-inl.h"
#include "simd/decode-inl.h"
#include "simd/fill-inl.h"
#include "simd/interpolate-inl.h"
#include "simd/reachability-inl.h"

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {

const RowKernels* KernelTable() {
  static const RowKernels table{hwy::TargetName(HWY_TARGET), HWY_TARGET, &InterpolateRowKernel, &ReachRowKernel, &RelationRowKernel, &ClassifyRowKernel,
                                &AntialiasRowKernel, &DecodeRowKernel, &FillRowKernel, &RenderCacheRowKernel,
                                &WindowMeanRowKernel, &Reach7RowKernel};
  return &table;
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace epi::simd {

HWY_EXPORT(KernelTable);

std::vector<int64_t> compiled_targets() { return hwy::SupportedAndGeneratedTargets(); }

const RowKernels& row_kernels(int64_t target) {
  const std::vector<int64_t> targets = compiled_targets();
  if (target == 0) target = targets.front();
  bool found = false;
  for (int64_t t : targets) found = found || t == target;
  if (!found || (target & (target - 1)) != 0)
    throw std::invalid_argument(std::string("Highway target not compiled or not supported here: ") +
                                hwy::TargetName(target));
  // The dispatch table's index of a single target, as hwy::ChosenTarget computes it.
  const int64_t chosen = HWY_CHOSEN_TARGET_SHIFT(target) | HWY_CHOSEN_TARGET_MASK_SCALAR;
  const size_t index = hwy::Num0BitsBelowLS1Bit_Nonzero64(uint64_t(chosen));
  return *HWY_DISPATCH_TABLE(KernelTable)[index]();
}

}  // namespace epi::simd
#endif  // HWY_ONCE

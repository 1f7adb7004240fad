// hole_mask (hole_fill.h) for every Highway target (foreach_target.h compiles this file once per target).
#include <cstring>

#include "render/hole_fill.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/hole_mask.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace epi::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

uint64_t HoleMask(const float* HWY_RESTRICT top, const float* HWY_RESTRICT rgb, size_t count) {
  const hn::ScalableTag<float> d;
  const size_t n = hn::Lanes(d);
  const auto zero = hn::Zero(d), at_top = hn::Set(d, kMaxPriority);
  uint64_t mask = 0;
  size_t i = 0;
  for (; i + n <= count; i += n) {
    hn::Vec<decltype(d)> r, g, b;
    hn::LoadInterleaved3(d, rgb + 3 * i, r, g, b);
    const auto hole = hn::And(hn::Ge(hn::LoadU(d, top + i), at_top),
                              hn::And(hn::Eq(r, zero), hn::And(hn::Eq(g, zero), hn::Eq(b, zero))));
    uint8_t bytes[8] = {};
    hn::StoreMaskBits(d, hole, bytes);
    uint64_t bits;
    std::memcpy(&bits, bytes, sizeof(bits));
    mask |= bits << i;
  }
  for (; i < count; ++i) mask |= uint64_t(is_hole(top[i], rgb + 3 * i)) << i;
  return mask;
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace epi::render {

HWY_EXPORT(HoleMask);

uint64_t hole_mask(const float* top, const float* rgb, size_t count) {
  return HWY_DYNAMIC_DISPATCH(HoleMask)(top, rgb, count);
}

}  // namespace epi::render
#endif  // HWY_ONCE

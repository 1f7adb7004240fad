// depth_windows.h for every Highway target (foreach_target.h compiles this file once per target).
#include "render/depth_windows.h"

#include <algorithm>
#include <cstring>
#include <limits>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/depth_windows.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace epi::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

constexpr float kInf = std::numeric_limits<float>::infinity();

// The least of in[x - r .. x + r] clipped to the row, one pixel.
HWY_INLINE float ClippedMin(const float* in, int w, int radius, int x) {
  float m = in[x];
  for (int q = std::max(0, x - radius); q <= std::min(w - 1, x + radius); ++q) m = std::min(m, in[q]);
  return m;
}

void RowWindowMin(const float* in, float* out, int w, int radius) {
  const hn::ScalableTag<float> d;
  const int lanes = int(hn::Lanes(d));
  int x = 0;
  for (; x < std::min(w, radius); ++x) out[x] = ClippedMin(in, w, radius, x);
  // Whole windows: 2r + 1 unaligned loads a vector.
  for (; x + lanes + radius <= w; x += lanes) {
    auto m = hn::LoadU(d, in + x - radius);
    for (int k = -radius + 1; k <= radius; ++k) m = hn::Min(m, hn::LoadU(d, in + x + k));
    hn::StoreU(m, d, out + x);
  }
  for (; x < w; ++x) out[x] = ClippedMin(in, w, radius, x);
}

void RowsMin(const float* const* rows, int count, float* out, int w) {
  const hn::ScalableTag<float> d;
  const int lanes = int(hn::Lanes(d));
  int x = 0;
  for (; x + lanes <= w; x += lanes) {
    auto m = hn::LoadU(d, rows[0] + x);
    for (int k = 1; k < count; ++k) m = hn::Min(m, hn::LoadU(d, rows[k] + x));
    hn::StoreU(m, d, out + x);
  }
  for (; x < w; ++x) {
    float m = rows[0][x];
    for (int k = 1; k < count; ++k) m = std::min(m, rows[k][x]);
    out[x] = m;
  }
}

void LoneDepths(const float* above, const float* row, const float* below, float* least, float* alone, int w) {
  // One pixel: its 3x3's other depths, clipped to the image.
  auto one = [&](int x) {
    float m = kInf;
    if (x > 0) m = std::min(m, row[x - 1]);
    if (x + 1 < w) m = std::min(m, row[x + 1]);
    for (const float* r : {above, below}) {
      if (!r) continue;
      m = std::min(m, r[x]);
      if (x > 0) m = std::min(m, r[x - 1]);
      if (x + 1 < w) m = std::min(m, r[x + 1]);
    }
    least[x] = m;
    alone[x] = m > row[x] ? row[x] : kInf;
  };
  const hn::ScalableTag<float> d;
  const int lanes = int(hn::Lanes(d));
  const auto inf = hn::Set(d, kInf);
  int x = 0;
  for (; x < std::min(w, 1); ++x) one(x);
  for (; x + lanes + 1 <= w; x += lanes) {
    auto m = hn::Min(hn::LoadU(d, row + x - 1), hn::LoadU(d, row + x + 1));
    for (const float* r : {above, below}) {
      if (!r) continue;
      m = hn::Min(m, hn::Min(hn::LoadU(d, r + x - 1), hn::Min(hn::LoadU(d, r + x), hn::LoadU(d, r + x + 1))));
    }
    const auto centre = hn::LoadU(d, row + x);
    hn::StoreU(m, d, least + x);
    hn::StoreU(hn::IfThenElse(hn::Gt(m, centre), centre, inf), d, alone + x);
  }
  for (; x < w; ++x) one(x);
}

void LoneWindowMasks(const float* alone, const float* neighbour_min, size_t stride, int rows, int n, float scale,
                     float depth, uint32_t* masks) {
  const hn::ScalableTag<float> d;
  const int lanes = int(hn::Lanes(d));
  const auto s = hn::Set(d, scale), limit = hn::Set(d, depth);
  for (int r = 0; r < rows; ++r) {
    const float* a = alone + size_t(r) * stride;
    const float* b = neighbour_min + size_t(r) * stride;
    uint32_t bits = 0;
    for (int k = 0; k < n; k += lanes) {
      // The scalar test's operations: a product rounded to float, then compared.
      const auto lone = hn::And(hn::Lt(hn::Mul(hn::LoadU(d, a + k), s), limit),
                                hn::Not(hn::Lt(hn::Mul(hn::LoadU(d, b + k), s), limit)));
      uint8_t packed[8] = {};
      hn::StoreMaskBits(d, hn::And(lone, hn::FirstN(d, size_t(n - k))), packed);
      uint64_t lane_bits = 0;
      std::memcpy(&lane_bits, packed, sizeof(lane_bits));
      bits |= uint32_t(lane_bits << k);
    }
    masks[r] = bits;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace epi::render {

HWY_EXPORT(RowWindowMin);
HWY_EXPORT(RowsMin);
HWY_EXPORT(LoneDepths);
HWY_EXPORT(LoneWindowMasks);

void row_window_min(const float* in, float* out, int w, int radius) { HWY_DYNAMIC_DISPATCH(RowWindowMin)(in, out, w, radius); }
void rows_min(const float* const* rows, int count, float* out, int w) { HWY_DYNAMIC_DISPATCH(RowsMin)(rows, count, out, w); }
void lone_depths(const float* above, const float* row, const float* below, float* least, float* alone, int w) {
  HWY_DYNAMIC_DISPATCH(LoneDepths)(above, row, below, least, alone, w);
}
void lone_window_masks(const float* alone, const float* neighbour_min, size_t stride, int rows, int n, float scale,
                       float depth, uint32_t* masks) {
  HWY_DYNAMIC_DISPATCH(LoneWindowMasks)(alone, neighbour_min, stride, rows, n, scale, depth, masks);
}

}  // namespace epi::render
#endif  // HWY_ONCE

// sparse_blend_kernels.h for every Highway target (foreach_target.h compiles this file once per target).
#include "render/sparse_blend_kernels.h"

#include <algorithm>

#include "render/sparse_blend.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/sparse_blend_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace epi::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

constexpr size_t C = kSparseBlendChannels;

// The recursion of sparse_blend.cpp's filter, one step: acc = k (x + a acc).
template <class V>
HWY_INLINE V Step(V k, V x, V a, V acc) {
  return hn::Mul(k, hn::Add(x, hn::Mul(a, acc)));
}

// The two directions added less the centre where the pixel is kept; a barrier keeps its value.
template <class V, class M>
HWY_INLINE V Combine(M kept, V forward, V backward, V x) {
  return hn::IfThenElse(kept, hn::Sub(hn::Add(forward, backward), x), x);
}

void FilterRowLanes(float* HWY_RESTRICT lanes, const float* HWY_RESTRICT keep, float* HWY_RESTRICT forward, int width,
                    float a) {
  const hn::CappedTag<float, kSparseRowLanes> d;
  using V = hn::Vec<decltype(d)>;
  constexpr size_t N = hn::MaxLanes(d), L = kSparseRowLanes, P = L / N;  // P vectors per channel
  const V va = hn::Set(d, a), zero = hn::Zero(d);
  // Every channel's chains at once: their latencies overlap.
  V acc[C * P];
  for (V& v : acc) v = zero;
  for (int x = 0; x < width; ++x) {
    const size_t at = size_t(x) * C * L;
    for (size_t p = 0; p < P; ++p) {
      const V k = hn::LoadU(d, keep + size_t(x) * L + p * N);
      for (size_t c = 0; c < C; ++c) {
        V& s = acc[c * P + p];
        s = Step(k, hn::LoadU(d, lanes + at + c * L + p * N), va, s);
        hn::StoreU(s, d, forward + at + c * L + p * N);
      }
    }
  }
  for (V& v : acc) v = zero;
  for (int x = width; x-- > 0;) {
    const size_t at = size_t(x) * C * L;
    for (size_t p = 0; p < P; ++p) {
      const V k = hn::LoadU(d, keep + size_t(x) * L + p * N);
      const auto kept = hn::Ne(k, zero);
      for (size_t c = 0; c < C; ++c) {
        V& s = acc[c * P + p];
        float* v = lanes + at + c * L + p * N;
        const V x0 = hn::LoadU(d, v);
        s = Step(k, x0, va, s);
        hn::StoreU(Combine(kept, hn::LoadU(d, forward + at + c * L + p * N), s, x0), d, v);
      }
    }
  }
}

// Lanes where barrier[] is 0.
template <class D>
HWY_INLINE auto Kept(D d, const uint8_t* barrier) {
  const hn::Rebind<uint8_t, D> d8;
  const hn::Rebind<int32_t, D> di;
  return hn::RebindMask(d, hn::Eq(hn::PromoteTo(di, hn::LoadU(d8, barrier)), hn::Zero(di)));
}

// The columns [x0, x0 + kSpan), kSpan a multiple of d's lanes; forward[(y C + c) kSpan + j].
template <class D, size_t kSpan>
size_t Strip(D d, const SparseColumnStrip& s, int x0, float* HWY_RESTRICT forward) {
  using V = hn::Vec<D>;
  constexpr size_t N = hn::MaxLanes(D()), P = kSpan / N;
  const size_t w = size_t(s.width);
  const V va = hn::Set(d, s.a), zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  auto plane = [&](size_t c, size_t i) { return s.planes + c * s.plane + i; };
  auto fwd = [&](int y, size_t c, size_t p) { return forward + (size_t(y) * C + c) * kSpan + p * N; };
  V acc[C * P];
  for (V& v : acc) v = zero;
  for (int y = 0; y < s.height; ++y) {
    const size_t row = size_t(y) * w + size_t(x0);
    for (size_t p = 0; p < P; ++p) {
      const V k = hn::IfThenElseZero(Kept(d, s.barrier + row + p * N), one);
      for (size_t c = 0; c < C; ++c) {
        V& a = acc[c * P + p];
        a = Step(k, hn::LoadU(d, plane(c, row + p * N)), va, a);
        hn::StoreU(a, d, fwd(y, c, p));
      }
    }
  }
  for (V& v : acc) v = zero;
  for (int y = s.height; y-- > 0;) {
    const size_t row = size_t(y) * w + size_t(x0);
    for (size_t p = 0; p < P; ++p) {
      const auto kept = Kept(d, s.barrier + row + p * N);
      const V k = hn::IfThenElseZero(kept, one);
      for (size_t c = 0; c < C; ++c) {
        V& a = acc[c * P + p];
        float* in = plane(c, row + p * N);
        const V x = hn::LoadU(d, in);
        a = Step(k, x, va, a);
        hn::StoreU(Combine(kept, hn::LoadU(d, fwd(y, c, p)), a, x), d, s.image ? fwd(y, c, p) : in);
      }
    }
  }
  if (!s.image) return 0;
  // The blend (sparse_blend.cpp, blend_pixel): t = clamp((dense - weight / mass) / span, 0, 1),
  // colour += t (sum / weight - colour) where the pixel is kept, reached a sample and t > 0.
  const V dense = hn::Set(d, s.dense), span = hn::Set(d, s.span);
  size_t changed = 0;
  for (int y = 0; y < s.height; ++y) {
    const size_t row = size_t(y) * w + size_t(x0);
    for (size_t p = 0; p < P; ++p) {
      const V weight = hn::LoadU(d, fwd(y, 3, p)), mass = hn::LoadU(d, fwd(y, 4, p));
      const V t = hn::Min(hn::Max(hn::Div(hn::Sub(dense, hn::Div(weight, mass)), span), zero), one);
      const auto blend = hn::And(Kept(d, s.barrier + row + p * N), hn::And(hn::Gt(weight, zero), hn::Gt(t, zero)));
      float* rgb = s.image + 3 * (row + p * N);
      V r, g, b;
      hn::LoadInterleaved3(d, rgb, r, g, b);
      auto towards = [&](V colour, size_t c) {
        return hn::IfThenElse(blend, hn::Add(colour, hn::Mul(t, hn::Sub(hn::Div(hn::LoadU(d, fwd(y, c, p)), weight), colour))), colour);
      };
      hn::StoreInterleaved3(towards(r, 0), towards(g, 1), towards(b, 2), d, rgb);
      changed += hn::CountTrue(d, blend);
    }
  }
  return changed;
}

size_t FilterColumnStrip(const SparseColumnStrip& s) {
  // Two vectors of columns at a time: ten chains of the recursion to overlap, two cache lines of
  // each row (three measured slower on AVX3: docs/render.md, "Sparse regions"); the image's last
  // columns a vector, then a column, at a time.
  const hn::CappedTag<float, kSparseStrip / 2> d;
  constexpr size_t N = hn::MaxLanes(d);
  const int end = std::min(s.width, s.x0 + kSparseStrip);
  size_t changed = 0;
  int x = s.x0;
  for (; x + int(2 * N) <= end; x += int(2 * N)) changed += Strip<decltype(d), 2 * N>(d, s, x, s.forward);
  for (; x + int(N) <= end; x += int(N)) changed += Strip<decltype(d), N>(d, s, x, s.forward);
  const hn::CappedTag<float, 1> d1;
  for (; x < end; ++x) changed += Strip<decltype(d1), 1>(d1, s, x, s.forward);
  return changed;
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace epi::render {

HWY_EXPORT(FilterRowLanes);
HWY_EXPORT(FilterColumnStrip);

void filter_row_lanes(float* lanes, const float* keep, float* forward, int width, float a) {
  HWY_DYNAMIC_DISPATCH(FilterRowLanes)(lanes, keep, forward, width, a);
}
size_t filter_column_strip(const SparseColumnStrip& strip) { return HWY_DYNAMIC_DISPATCH(FilterColumnStrip)(strip); }

}  // namespace epi::render
#endif  // HWY_ONCE

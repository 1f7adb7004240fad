// sparse_blend_kernels.h for every Highway target (foreach_target.h compiles this file once per target).
#include "render/sparse_blend_kernels.h"

#include <algorithm>

#include "render/sparse_blend.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/sparse_blend_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/cache_control.h>
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

// The planes' and barriers' row of the strip `kAhead` rows ahead of the sweep, in images whose rows
// lie a page or more apart: there the hardware prefetcher does not follow the sweep (1080p
// 1.16x); in narrower ones it does, and the prefetches only cost (512 wide: 0.92-0.96x).
constexpr int kAhead = 8;
inline bool PrefetchRows(int width) { return size_t(width) * sizeof(float) >= 4096; }
HWY_INLINE void PrefetchRow(const SparseColumnStrip& s, size_t at, size_t span) {
  for (size_t c = 0; c < C; ++c)
    for (size_t b = 0; b < sizeof(float) * span; b += 64) hwy::Prefetch(reinterpret_cast<const char*>(s.planes + c * s.plane + at) + b);
  hwy::Prefetch(s.barrier + at);
}

// The columns [x0, x0 + kSpan), kSpan a multiple of d's lanes; forward[(y C + c) kSpan + j].
template <class D, size_t kSpan>
size_t Strip(D d, const SparseColumnStrip& s, int x0, float* HWY_RESTRICT forward) {
  using V = hn::Vec<D>;
  constexpr size_t N = hn::MaxLanes(D()), P = kSpan / N;
  const size_t w = size_t(s.width);
  const V va = hn::Set(d, s.a), zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const bool ahead = PrefetchRows(s.width);
  auto plane = [&](size_t c, size_t i) { return s.planes + c * s.plane + i; };
  auto fwd = [&](int y, size_t c, size_t p) { return forward + (size_t(y) * C + c) * kSpan + p * N; };
  V acc[C * P];
  for (V& v : acc) v = zero;
  for (int y = 0; y < s.height; ++y) {
    const size_t row = size_t(y) * w + size_t(x0);
    if (ahead && y + kAhead < s.height) PrefetchRow(s, row + kAhead * w, kSpan);
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
    if (ahead && y >= kAhead) PrefetchRow(s, row - kAhead * w, kSpan);
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
    if (ahead && y + kAhead < s.height) {
      const char* rgb = reinterpret_cast<const char*>(s.image + 3 * (row + kAhead * w));
      for (size_t b = 0; b < 3 * sizeof(float) * kSpan; b += 64) hwy::Prefetch(rgb + b);
      hwy::Prefetch(s.barrier + row + kAhead * w);
    }
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

constexpr size_t L = kSparseRowLanes;

// Row r of the group at pixels [x, x + N): its C values (zeros below the group's rows) and its
// keep flag. From the EPI as sparse_blend.cpp's pixel_values: linear r, g, b and a weight of 1
// where it holds a sample and no barrier, a mass of 1 where no barrier; or from the planes.
template <class D>
HWY_INLINE void RowValues(D d, const SparseRowGroup& g, size_t r, size_t x, hn::Vec<D> v[C], hn::Vec<D>& keep) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const hn::Rebind<uint16_t, D> d16;
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  if (r >= size_t(g.rows)) {
    for (size_t c = 0; c < C; ++c) v[c] = zero;
    keep = zero;
    return;
  }
  const size_t i = g.first + r * size_t(g.width) + x;
  const auto open = Kept(d, g.barrier + i);
  keep = hn::IfThenElseZero(open, one);
  if (!g.color) {
    for (size_t c = 0; c < C; ++c) v[c] = hn::LoadU(d, g.planes + c * g.plane + i);
    return;
  }
  const auto flagged = hn::And(hn::PromoteTo(di, hn::LoadU(d16, g.edge + i)), hn::Set(di, int32_t(bits::kHasSample)));
  const auto sample = hn::And(hn::RebindMask(di, open), hn::Ne(flagged, hn::Zero(di)));
  const auto colour = hn::IfThenElseZero(hn::RebindMask(du, sample), hn::LoadU(du, g.color + i));
  const auto byte = hn::Set(du, 255u);
  v[0] = hn::GatherIndex(d, g.lut, hn::BitCast(di, hn::And(colour, byte)));
  v[1] = hn::GatherIndex(d, g.lut, hn::BitCast(di, hn::And(hn::ShiftRight<8>(colour), byte)));
  v[2] = hn::GatherIndex(d, g.lut, hn::BitCast(di, hn::And(hn::ShiftRight<16>(colour), byte)));
  v[3] = hn::IfThenElseZero(hn::RebindMask(d, sample), one);
  v[4] = keep;
}

#if HWY_TARGET != HWY_SCALAR  // (one lane: never called)
// v[0..7], eight rows of eight floats, become its eight columns (column j in v[j]).
template <class D>
HWY_INLINE void Transpose8(D d, hn::Vec<D> v[8]) {
  using V = hn::Vec<D>;
  const hn::Repartition<double, D> dd;
  V t[8];
  for (size_t k = 0; k < 8; k += 2) {
    t[k] = hn::InterleaveLower(d, v[k], v[k + 1]);      // a0 b0 a1 b1 | a4 b4 a5 b5
    t[k + 1] = hn::InterleaveUpper(d, v[k], v[k + 1]);  // a2 b2 a3 b3 | a6 b6 a7 b7
  }
  auto pairs_lower = [&](V a, V b) { return hn::BitCast(d, hn::InterleaveLower(dd, hn::BitCast(dd, a), hn::BitCast(dd, b))); };
  auto pairs_upper = [&](V a, V b) { return hn::BitCast(d, hn::InterleaveUpper(dd, hn::BitCast(dd, a), hn::BitCast(dd, b))); };
  // Rows 0-3 (u[0..3]) and 4-7 (u[4..7]) at columns j | j + 4.
  const V u[8] = {pairs_lower(t[0], t[2]), pairs_upper(t[0], t[2]), pairs_lower(t[1], t[3]), pairs_upper(t[1], t[3]),
                  pairs_lower(t[4], t[6]), pairs_upper(t[4], t[6]), pairs_lower(t[5], t[7]), pairs_upper(t[5], t[7])};
  for (size_t j = 0; j < 4; ++j) {
    v[j] = hn::ConcatLowerLower(d, u[4 + j], u[j]);
    v[j + 4] = hn::ConcatUpperUpper(d, u[4 + j], u[j]);
  }
}
#endif

// The group's pixels [x, x + N) into the lanes: N = 8 in transposes, or N = 1.
template <class D>
HWY_INLINE void GatherSpan(D d, const SparseRowGroup& g, size_t x, float* HWY_RESTRICT lanes, float* HWY_RESTRICT keep) {
  constexpr size_t N = hn::MaxLanes(D());
  static_assert(N == L || N == 1);
  hn::Vec<D> v[C][L], kept[L], row[C];
  for (size_t r = 0; r < L; ++r) {
    RowValues(d, g, r, x, row, kept[r]);
    for (size_t c = 0; c < C; ++c) v[c][r] = row[c];
  }
  if constexpr (N == L) {
    for (size_t c = 0; c < C; ++c) {
      Transpose8(d, v[c]);
      for (size_t j = 0; j < N; ++j) hn::StoreU(v[c][j], d, lanes + ((x + j) * C + c) * L);
    }
    Transpose8(d, kept);
    for (size_t j = 0; j < N; ++j) hn::StoreU(kept[j], d, keep + (x + j) * L);
  } else {
    for (size_t r = 0; r < L; ++r) {
      for (size_t c = 0; c < C; ++c) lanes[(x * C + c) * L + r] = hn::GetLane(v[c][r]);
      keep[x * L + r] = hn::GetLane(kept[r]);
    }
  }
}

// The lanes of pixels [x, x + N) back into the group's rows of the planes.
template <class D>
HWY_INLINE void ScatterSpan(D d, const SparseRowGroup& g, size_t x, const float* HWY_RESTRICT lanes) {
  constexpr size_t N = hn::MaxLanes(D());
  static_assert(N == L || N == 1);
  const size_t rows = size_t(g.rows);
  for (size_t c = 0; c < C; ++c) {
    float* plane = g.planes + c * g.plane + g.first + x;
    if constexpr (N == L) {
      hn::Vec<D> v[L];
      for (size_t j = 0; j < N; ++j) v[j] = hn::LoadU(d, lanes + ((x + j) * C + c) * L);
      Transpose8(d, v);
      for (size_t r = 0; r < rows; ++r) hn::StoreU(v[r], d, plane + r * size_t(g.width));
    } else {
      for (size_t r = 0; r < rows; ++r) plane[r * size_t(g.width)] = lanes[(x * C + c) * L + r];
    }
  }
}

// span(d, x) over the row's pixels: eight at a time where d has eight lanes, then one at a time.
template <class D, class Span>
void ForEachSpan(D d, int width, const Span& span) {
  size_t x = 0;
  if constexpr (hn::MaxLanes(D()) == L)
    for (; x + L <= size_t(width); x += L) span(d, x);
  for (const hn::CappedTag<float, 1> d1; x < size_t(width); ++x) span(d1, x);
}

void GatherRowLanes(const SparseRowGroup& g, float* HWY_RESTRICT lanes, float* HWY_RESTRICT keep) {
  ForEachSpan(hn::CappedTag<float, L>(), g.width, [&](auto d, size_t x) { GatherSpan(d, g, x, lanes, keep); });
}
void ScatterRowLanes(const SparseRowGroup& g, const float* HWY_RESTRICT lanes) {
  ForEachSpan(hn::CappedTag<float, L>(), g.width, [&](auto d, size_t x) { ScatterSpan(d, g, x, lanes); });
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace epi::render {

HWY_EXPORT(FilterRowLanes);
HWY_EXPORT(FilterColumnStrip);
HWY_EXPORT(GatherRowLanes);
HWY_EXPORT(ScatterRowLanes);

void filter_row_lanes(float* lanes, const float* keep, float* forward, int width, float a) {
  HWY_DYNAMIC_DISPATCH(FilterRowLanes)(lanes, keep, forward, width, a);
}
size_t filter_column_strip(const SparseColumnStrip& strip) { return HWY_DYNAMIC_DISPATCH(FilterColumnStrip)(strip); }
void gather_row_lanes(const SparseRowGroup& group, float* lanes, float* keep) {
  HWY_DYNAMIC_DISPATCH(GatherRowLanes)(group, lanes, keep);
}
void scatter_row_lanes(const SparseRowGroup& group, const float* lanes) { HWY_DYNAMIC_DISPATCH(ScatterRowLanes)(group, lanes); }

}  // namespace epi::render
#endif  // HWY_ONCE

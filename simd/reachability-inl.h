// The reachability row kernel (per target; included by row_kernels.cpp through
// foreach_target.h). The oracle's propagation (reachability.cpp: monotone staircase paths
// from the centre, offsets by Manhattan distance, each step a neighbour relation chained onto
// the path so far, the paths OR-ed), lane by lane: one pixel per 32-bit lane. The relations
// are 2x2 boolean matrices in 4 bits (bit 2a + b: region a of one pixel reaches region b of
// the other; region 0 primary, 1 secondary). A neighbour relation depends only on what each
// pixel shows on the shared side (ReachTables: 4 descriptors, looked up by type in a 16-byte
// table, and a 16-byte relation table); chaining is bit arithmetic. Integer logic only: equal
// to the oracle on every lane.
#if defined(EPI_SIMD_REACHABILITY_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_REACHABILITY_INL_H_
#undef EPI_SIMD_REACHABILITY_INL_H_
#else
#define EPI_SIMD_REACHABILITY_INL_H_
#endif

#include <array>
#include <cstring>

#include <hwy/highway.h>

#include "simd/row_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The oracle's step order (reachability.cpp, make_steps<2>): window index (dy+2)*5 + dx+2,
// predecessors one step closer to the centre, the side of the predecessor the step crosses
// (0 top, 1 right, 2 bottom, 3 left).
struct ReachStep {
  int index, bit;
  bool forward;  // a later row, the rest of the own row to the right, or (-1, 0), (-2, 0)
  int pred[2], side[2];
  int preds;
};
constexpr std::array<ReachStep, 24> MakeReachSteps() {
  std::array<ReachStep, 24> steps{};
  int n = 0;
  for (int dist = 1; dist <= 4; ++dist)
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        if ((dx < 0 ? -dx : dx) + (dy < 0 ? -dy : dy) != dist) continue;
        ReachStep s{};
        s.index = (dy + 2) * 5 + dx + 2;
        s.bit = s.index < 12 ? s.index : s.index - 1;
        s.forward = dy >= 0;
        if (dx != 0) {
          const int sx = dx > 0 ? 1 : -1;
          s.pred[s.preds] = (dy + 2) * 5 + (dx - sx + 2);
          s.side[s.preds++] = sx > 0 ? 1 : 3;
        }
        if (dy != 0) {
          const int sy = dy > 0 ? 1 : -1;
          s.pred[s.preds] = (dy - sy + 2) * 5 + dx + 2;
          s.side[s.preds++] = sy > 0 ? 2 : 0;
        }
        steps[size_t(n++)] = s;
      }
  return steps;
}

// Relation a->d from a->b (m) and b->d (s): row a of the result is the OR of the rows b of s
// that m(a, b) selects.
template <class V>
HWY_INLINE V Chain(V m, V s) {
  const hn::DFromV<V> d;
  const V one = hn::Set(d, 1u), three = hn::Set(d, 3u);
  const V s0 = hn::And(s, three), s1 = hn::And(hn::ShiftRight<2>(s), three);
  auto pick = [&](int shift) { return hn::Sub(hn::Zero(d), hn::And(hn::ShiftRightSame(m, shift), one)); };
  const V row0 = hn::Or(hn::And(pick(0), s0), hn::And(pick(1), s1));
  const V row1 = hn::Or(hn::And(pick(2), s0), hn::And(pick(3), s1));
  return hn::Or(row0, hn::ShiftLeft<2>(row1));
}

// Lanes x .. x + N - 1; out has N entries. kForward: only the forward steps, the offsets
// towards the two rows above from those rows' masks by symmetry (bit (dx, dy) of pixel p is
// bit (-dx, -dy) of pixel p + (dx, dy)).
template <bool kForward, class DU>
HWY_INLINE void ReachLanes(DU du, const ReachRow& row, int x, uint32_t* out) {
  using V = hn::Vec<DU>;
  static constexpr std::array<ReachStep, 24> kSteps = MakeReachSteps();
  V words[25];
  V any = hn::Zero(du);
  for (int dy = 0; dy < 5; ++dy)
    for (int dx = 0; dx < 5; ++dx) {
      words[dy * 5 + dx] = hn::LoadU(du, row.sides[dy] + kPad + x + dx - 2);
      any = hn::Or(any, words[dy * 5 + dx]);
    }
  if (hn::AllTrue(du, hn::Eq(hn::And(any, hn::Set(du, kSideNonEmpty)), hn::Zero(du)))) {
    hn::StoreU(hn::Set(du, 0xffffffu), du, out);  // only empty pixels: everything reachable
    return;
  }
  const V three = hn::Set(du, 3u), fifteen = hn::Set(du, 15u), seven = hn::Set(du, 7u);
  const V rel_lo = hn::Set(du, row.relation_lo), rel_hi = hn::Set(du, row.relation_hi);
  // The neighbour relation for descriptors (from, to): entry 4 from + to of the 16 4-bit entries.
  auto relation = [&](V from, V to) {
    const V index = hn::Or(hn::ShiftLeft<2>(from), to);
    const V table = hn::IfThenElse(hn::Eq(hn::And(index, hn::Set(du, 8u)), hn::Zero(du)), rel_lo, rel_hi);
    return hn::And(hn::Shr(table, hn::ShiftLeft<2>(hn::And(index, seven))), fifteen);
  };
  V masks[25];
  V result = hn::Zero(du);
  if (kForward)
    for (int dy = -2; dy <= -1; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const V above = hn::LoadU(du, row.above[-dy - 1] + x + dx);
        const int from = (2 - dy) * 5 + 2 - dx, to = (dy + 2) * 5 + dx + 2;  // bits of (-dx, -dy), (dx, dy)
        result = hn::Or(result, hn::ShiftLeftSame(hn::And(hn::ShiftRightSame(above, from - 1), hn::Set(du, 1u)), to));
      }
  for (const ReachStep& s : kSteps) {
    if (kForward && !s.forward) continue;
    V m = hn::Zero(du);
    for (int i = 0; i < s.preds; ++i) {
      const int p = s.pred[i], side = s.side[i];
      const V from = hn::And(hn::ShiftRightSame(words[p], 2 * side), three);
      const V to = hn::And(hn::ShiftRightSame(words[s.index], 2 * ((side + 2) & 3)), three);
      const V blocked = hn::And(hn::Or(words[p], words[s.index]), hn::Set(du, kSideBlocked));
      const V rel = hn::IfThenZeroElse(hn::Ne(blocked, hn::Zero(du)), relation(from, to));
      m = hn::Or(m, p == 12 ? rel : Chain(masks[p], rel));
    }
    masks[s.index] = m;
    result = hn::Or(result, hn::ShiftLeftSame(hn::And(m, hn::Set(du, 1u)), s.bit));
  }
  hn::StoreU(result, du, out);
}

template <bool kForward>
void ReachRowLanes(const ReachRow& row) {
  const hn::ScalableTag<uint32_t> du;
  const int n = int(hn::Lanes(du));
  int x = 0;
  for (; x + n <= row.width; x += n) ReachLanes<kForward>(du, row, x, row.reach + x);
  if (x == row.width) return;
  HWY_ALIGN uint32_t last[HWY_LANES(uint32_t)];
  ReachLanes<kForward>(du, row, x, last);  // the padded rows hold "outside" beyond the row
  std::memcpy(row.reach + x, last, size_t(row.width - x) * sizeof(uint32_t));
}

inline void ReachRowKernel(const ReachRow& row) {
  if (row.above[0]) ReachRowLanes<true>(row);
  else ReachRowLanes<false>(row);
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_REACHABILITY_INL_H_

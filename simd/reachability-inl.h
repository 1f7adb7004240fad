// The reachability row kernels (per target; included by row_kernels.cpp through
// foreach_target.h). The oracle's propagation (reachability.cpp: monotone staircase paths
// from the centre, offsets by Manhattan distance, each step a neighbour relation chained onto
// the path so far, the paths OR-ed), one pixel per byte lane (64 pixels a vector on AVX3).
//
// Two facts make it cheap. (1) The neighbour relation of two adjacent pixels depends only on
// the pair, not on the window: RelationRowKernel computes it once per row and direction
// (RelationRow: three 16-byte table lookups per lane), and the windows that cross a pair read it (each row's relations serve five
// rows of reachability). (2) Only the primary region of the centre matters (the mask is
// primary-to-primary): a path's state is the set of regions of the current pixel it reaches
// (2 bits), not a 2x2 relation. A step ANDs the pixel pair's 4-bit relation with the state
// spread as X = P * 0b0011 | S * 0b1100 (bit 2a + b survives when region a is reached and
// reaches b), ORs over the one or two predecessors, and one 16-byte table lookup turns the 4
// bits into the next state; a second lookup gives the result bit. Integer logic only: equal
// to the oracle on every lane.
#if defined(EPI_SIMD_REACHABILITY_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_REACHABILITY_INL_H_
#undef EPI_SIMD_REACHABILITY_INL_H_
#else
#define EPI_SIMD_REACHABILITY_INL_H_
#endif

#include <algorithm>
#include <array>
#include <cstring>

#include <hwy/highway.h>

#include "simd/row_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// A 16-byte table looked up per byte lane: indices 0-15, or 0x80 and above for 0.
template <class D>
struct Table16 {
#if HWY_TARGET == HWY_SCALAR
  const uint8_t* bytes;
  Table16(D, const uint8_t* table) : bytes(table) {}
  hn::Vec<D> operator()(D d, hn::Vec<D> index) const {
    const uint8_t i = hn::GetLane(index);
    return hn::Set(d, i & 0x80 ? uint8_t(0) : bytes[i & 15]);
  }
#else
  hn::Vec<D> bytes;
  Table16(D d, const uint8_t* table) : bytes(hn::LoadDup128(d, table)) {}
  hn::Vec<D> operator()(D, hn::Vec<D> index) const { return hn::TableLookupBytesOr0(bytes, index); }
#endif
};

// The relations of one row (RelationRow): per byte lane, the two pixels' side codes by type
// (one table lookup each), OR-ed into the index of the relation table.
template <class D8>
HWY_INLINE void RelationLanes(D8 d8, const RelationRow& row, int x) {
  using V = hn::Vec<D8>;
  const RelationTables& t = *row.tables;
  const Table16<D8> relation(d8, t.relation);
  const uint8_t* types = row.types + kPad + x;
  const V own = hn::LoadU(d8, types), left = hn::LoadU(d8, types - 1), right = hn::LoadU(d8, types + 1);
  const V above = hn::LoadU(d8, row.above + kPad + x);
  // from's side `side` faces to's side `side` + 2.
  auto between = [&](V from, V to, int side) {
    return relation(d8, hn::Or(Table16<D8>(d8, t.from[side])(d8, from), Table16<D8>(d8, t.to[(side + 2) & 3])(d8, to)));
  };
  uint8_t* out = row.out + x;
  hn::StoreU(between(own, right, 1), d8, out);
  hn::StoreU(between(own, left, 3), d8, out + row.plane);
  hn::StoreU(between(above, own, 2), d8, out + 2 * row.plane);
  hn::StoreU(between(own, above, 0), d8, out + 3 * row.plane);
}

// Whole vectors up to the end of the row: beyond it the types are blocked (padding), so the
// relations written there are the zeros the planes hold.
inline void RelationRowKernel(const RelationRow& row) {
  const hn::ScalableTag<uint8_t> d8;
  const int n = int(hn::Lanes(d8));
  for (int x = 0; x < row.width; x += n) RelationLanes(d8, row, x);
}

// The oracle's step order over the (2R + 1)^2 window (reachability.cpp, make_steps<R>): window
// index (dy + R)(2R + 1) + dx + R, the predecessors one step closer to the centre, and the
// relation row (row k: image row y - R + k), plane and column offset of the step from each. R = 2
// is the reachability's 5x5, R = 3 the fallback's 7x7.
struct WindowStep {
  int index, dy;
  int pred[2], row[2], plane[2], dx[2];
  int preds;
};
template <int R>
constexpr std::array<WindowStep, (2 * R + 1) * (2 * R + 1) - 1> MakeWindowSteps() {
  constexpr int side = 2 * R + 1;
  std::array<WindowStep, side * side - 1> steps{};
  int n = 0;
  for (int dist = 1; dist <= 2 * R; ++dist)
    for (int dy = -R; dy <= R; ++dy)
      for (int dx = -R; dx <= R; ++dx) {
        if ((dx < 0 ? -dx : dx) + (dy < 0 ? -dy : dy) != dist) continue;
        WindowStep s{};
        s.index = (dy + R) * side + dx + R, s.dy = dy;
        if (dx != 0) {  // from (dx - sx, dy): its right relation (sx = 1) or left (sx = -1)
          const int sx = dx > 0 ? 1 : -1;
          s.pred[s.preds] = (dy + R) * side + (dx - sx + R);
          s.row[s.preds] = dy + R, s.plane[s.preds] = sx > 0 ? 0 : 1, s.dx[s.preds] = dx - sx;
          ++s.preds;
        }
        if (dy != 0) {  // from (dx, dy - sy): row dy's down relation (sy = 1), row dy + 1's up
          const int sy = dy > 0 ? 1 : -1;
          s.pred[s.preds] = (dy - sy + R) * side + dx + R;
          s.row[s.preds] = sy > 0 ? dy + R : dy + R + 1, s.plane[s.preds] = sy > 0 ? 2 : 3, s.dx[s.preds] = dx;
          ++s.preds;
        }
        steps[size_t(n++)] = s;
      }
  return steps;
}
// The 5x5's bit of a step (reach_bit: the centre has none); the forward steps: a later row, the
// rest of the own row to the right, or (-1, 0), (-2, 0).
constexpr int ReachBit(const WindowStep& s) { return s.index < 12 ? s.index : s.index - 1; }
constexpr bool Forward(const WindowStep& s) { return s.dy >= 0; }

// t: the relation bits that survive the state (bit 2a + b: region a reached, reaches b).
// The next state X (0b0011 the primary reached, 0b1100 the secondary), and the result bit
// j of a mask byte (the primary reached).
struct StepTables {
  alignas(16) uint8_t next[16];
  alignas(16) uint8_t bit[8][16];
};
constexpr StepTables MakeStepTables() {
  StepTables t{};
  for (int i = 0; i < 16; ++i) {
    const bool primary = (i & 1) || (i & 4), secondary = (i & 2) || (i & 8);
    t.next[i] = uint8_t((primary ? 3 : 0) | (secondary ? 12 : 0));
    for (int j = 0; j < 8; ++j) t.bit[j][i] = primary ? uint8_t(1 << j) : 0;
  }
  return t;
}

// Step s's relation bits that survive its predecessors' states (OR over the one or two).
template <class D8>
HWY_INLINE hn::Vec<D8> Surviving(D8 d8, const uint8_t* const* relations, size_t plane, int x, const WindowStep& s,
                                 const hn::Vec<D8>* state) {
  hn::Vec<D8> t = hn::Zero(d8);
  for (int i = 0; i < s.preds; ++i) {
    const uint8_t* rel = relations[s.row[i]] + size_t(s.plane[i]) * plane + x + s.dx[i];
    t = hn::Or(t, hn::And(hn::LoadU(d8, rel), state[s.pred[i]]));
  }
  return t;
}

// Pixels x .. x + N - 1 (N byte lanes); out (and cache, unless null) has N entries, types
// too. kForward: only the forward steps,
// the offsets towards the two rows above from those rows' masks by symmetry (bit (dx, dy) of
// pixel p is bit (-dx, -dy) of pixel p + (dx, dy)).
template <bool kForward, class D8>
HWY_INLINE void ReachLanes(D8 d8, const ReachRow& row, int x, const uint8_t* types, uint32_t* out, uint32_t* cache) {
  using V = hn::Vec<D8>;
  static constexpr std::array<WindowStep, 24> kSteps = MakeWindowSteps<2>();
  static constexpr StepTables kTables = MakeStepTables();
  const Table16<D8> next(d8, kTables.next);
  V state[25];
  state[12] = hn::Set(d8, 3);  // the centre's primary
  V bytes[3] = {hn::Zero(d8), hn::Zero(d8), hn::Zero(d8)};
  for (const WindowStep& s : kSteps) {
    if (kForward && !Forward(s)) continue;
    const V t = Surviving(d8, row.relations, row.plane, x, s, state);
    state[s.index] = next(d8, t);
    const int bit = ReachBit(s);
    bytes[bit >> 3] = hn::Or(bytes[bit >> 3], Table16<D8>(d8, kTables.bit[bit & 7])(d8, t));
  }
  // Bytes to 32-bit masks, a quarter vector at a time.
  const size_t n = hn::Lanes(d8);
  HWY_ALIGN uint8_t b[3][HWY_LANES(uint8_t)];
  for (int k = 0; k < 3; ++k) hn::Store(bytes[k], d8, b[k]);
  const hn::Repartition<uint32_t, D8> du;
  const hn::Rebind<uint8_t, decltype(du)> dq;
  const size_t nu = hn::Lanes(du);
  for (size_t i = 0; i < n; i += nu) {
    auto result = hn::Or(hn::PromoteTo(du, hn::LoadU(dq, b[0] + i)),
                         hn::Or(hn::ShiftLeft<8>(hn::PromoteTo(du, hn::LoadU(dq, b[1] + i))),
                                hn::ShiftLeft<16>(hn::PromoteTo(du, hn::LoadU(dq, b[2] + i)))));
    if (kForward)
      for (int dy = -2; dy <= -1; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const auto above = hn::LoadU(du, row.above[-dy - 1] + x + int(i) + dx);
          const int from = (2 - dy) * 5 + 2 - dx, to = (dy + 2) * 5 + dx + 2;  // bits of (-dx, -dy), (dx, dy)
          result = hn::Or(result, hn::ShiftLeftSame(hn::And(hn::ShiftRightSame(above, from - 1), hn::Set(du, 1u)), to));
        }
    hn::StoreU(result, du, out + i);
    if (cache) {
      const auto type = hn::PromoteTo(du, hn::LoadU(dq, types + i));
      hn::StoreU(hn::Or(result, hn::ShiftLeft<24>(type)), du, cache + i);
    }
  }
}

template <bool kForward>
void ReachRowLanes(const ReachRow& row) {
  const hn::ScalableTag<uint8_t> d8;
  const int n = int(hn::Lanes(d8));
  int x = 0;
  for (; x + n <= row.width; x += n)
    ReachLanes<kForward>(d8, row, x, row.types + x, row.reach + x, row.cache ? row.cache + x : nullptr);
  if (x == row.width) return;
  constexpr int kMax = HWY_LANES(uint8_t);
  HWY_ALIGN uint32_t reach[kMax], cache[kMax];
  HWY_ALIGN uint8_t types[kMax] = {};
  const size_t rest = size_t(row.width - x);
  std::memcpy(types, row.types + x, rest);
  ReachLanes<kForward>(d8, row, x, types, reach, cache);  // the relation rows hold zeros beyond the row
  std::memcpy(row.reach + x, reach, rest * sizeof(uint32_t));
  if (row.cache) std::memcpy(row.cache + x, cache, rest * sizeof(uint32_t));
}

// The fallback's 7x7 (Reach7Row), the same propagation one ring further. Pixels x .. x + N - 1:
// the masks' seven bytes (bit j of byte b: window index 8 b + j), byte plane b at bytes + b N.
template <class D8>
HWY_INLINE void Reach7Lanes(D8 d8, const Reach7Row& row, int x, uint8_t* bytes) {
  using V = hn::Vec<D8>;
  static constexpr std::array<WindowStep, 48> kSteps = MakeWindowSteps<3>();
  static constexpr StepTables kTables = MakeStepTables();
  const Table16<D8> next(d8, kTables.next);
  V state[49];
  state[24] = hn::Set(d8, 3);  // the centre's primary
  V out[7];
  for (V& o : out) o = hn::Zero(d8);
  out[3] = hn::Set(d8, 1);  // the centre's own bit (24)
  for (const WindowStep& s : kSteps) {
    const V t = Surviving(d8, row.relations, row.plane, x, s, state);
    state[s.index] = next(d8, t);
    out[s.index >> 3] = hn::Or(out[s.index >> 3], Table16<D8>(d8, kTables.bit[s.index & 7])(d8, t));
  }
  const size_t n = hn::Lanes(d8);
  for (size_t b = 0; b < 7; ++b) hn::Store(out[b], d8, bytes + b * n);
}

// Whole vectors over [first, end), those holding a taken pixel; the taken lanes' bytes to masks.
inline void Reach7RowKernel(const Reach7Row& row) {
  const hn::ScalableTag<uint8_t> d8;
  const int n = int(hn::Lanes(d8));
  HWY_ALIGN uint8_t bytes[7 * HWY_LANES(uint8_t)];
  for (int x = row.first; x < row.end; x += n) {
    const int count = std::min(n, row.end - x);
    if (!std::memchr(row.take + x, 1, size_t(count))) continue;
    Reach7Lanes(d8, row, x, bytes);
    for (int k = 0; k < count; ++k) {
      if (!row.take[x + k]) continue;
      uint64_t mask = 0;
      for (int b = 0; b < 7; ++b) mask |= uint64_t(bytes[b * n + k]) << (8 * b);
      row.masks[x + k] = mask;
    }
  }
}

inline void ReachRowKernel(const ReachRow& row) {
  if (row.above[0]) ReachRowLanes<true>(row);
  else ReachRowLanes<false>(row);
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_REACHABILITY_INL_H_

// The classification row kernel (per target; included by row_kernels.cpp through
// foreach_target.h): classify_pixel (core/epi/classify.cpp) lane by lane, one pixel per 32-bit
// lane. Crossings counted per side, the two positions of a simple pixel from one-hot side
// masks, the area and sidedness tables gathered by edge code. Integer logic only: equal to the
// oracle on every lane.
#if defined(EPI_SIMD_CLASSIFY_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EPI_SIMD_CLASSIFY_INL_H_
#undef EPI_SIMD_CLASSIFY_INL_H_
#else
#define EPI_SIMD_CLASSIFY_INL_H_
#endif

#include <cstring>

#include <hwy/highway.h>

#include "simd/row_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace epi::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The packed table entries (ClassifyRow::code_tables) of each lane's code: bits 0-31 in `low`,
// 32-63 in `high`. Two gathers of 64-bit entries (one on the scalar target: two of 32 bits).
template <class DU>
HWY_INLINE void GatherCodeTables(DU du, const uint64_t* table, hn::Vec<DU> code, hn::Vec<DU>& low, hn::Vec<DU>& high) {
  const hn::RebindToSigned<DU> di;
#if HWY_TARGET == HWY_SCALAR
  const uint32_t* words = reinterpret_cast<const uint32_t*>(table);  // little-endian: low word first
  const auto twice = hn::BitCast(di, hn::ShiftLeft<1>(code));
  low = hn::GatherIndex(du, words, twice);
  high = hn::GatherIndex(du, words + 1, twice);
#else
  const hn::Half<decltype(di)> dh;
  const hn::Repartition<int64_t, DU> di64;
  const hn::Repartition<uint64_t, DU> du64;
  const auto index = hn::BitCast(di, code);
  const auto first = hn::GatherIndex(du64, table, hn::PromoteTo(di64, hn::LowerHalf(dh, index)));
  const auto second = hn::GatherIndex(du64, table, hn::PromoteTo(di64, hn::UpperHalf(dh, index)));
  low = hn::ConcatEven(du, hn::BitCast(du, second), hn::BitCast(du, first));
  high = hn::ConcatOdd(du, hn::BitCast(du, second), hn::BitCast(du, first));
#endif
}

// Lanes x .. x + N - 1 from pointers already offset to x; `valid` lanes are counted.
template <class DU>
HWY_INLINE void ClassifyLanes(DU du, const ClassifyRow& row, const uint8_t* top, const uint8_t* bottom,
                              const uint8_t* left, const uint8_t* right, const uint8_t* centre_h,
                              const uint8_t* centre_v, const uint16_t* in, uint16_t* edge_out, uint8_t* types_out,
                              size_t valid, int64_t counts[5]) {
  using V = hn::Vec<DU>;
  const hn::Rebind<uint8_t, DU> d8;
  const hn::Rebind<uint16_t, DU> d16;
  const hn::RebindToSigned<DU> di;
  const V zero = hn::Zero(du), one = hn::Set(du, 1u);
  const V sides[4] = {hn::PromoteTo(du, hn::LoadU(d8, top)), hn::PromoteTo(du, hn::LoadU(d8, right)),
                      hn::PromoteTo(du, hn::LoadU(d8, bottom)), hn::PromoteTo(du, hn::LoadU(d8, left))};
  const V in_edge = hn::PromoteTo(du, hn::LoadU(d16, in));
  const auto sample = hn::Ne(hn::And(in_edge, hn::Set(du, 1u << 14)), zero);
  const auto counted = hn::FirstN(du, valid);
  if (hn::AllTrue(du, hn::Eq(hn::Or(hn::Or(sides[0], sides[1]), hn::Or(sides[2], sides[3])), zero))) {
    // No crossing on any side (most vectors): empty pixels, every sample usable.
    const V edge = hn::Or(hn::And(in_edge, hn::Set(du, ~uint32_t(0x83ffu))), hn::IfThenElseZero(sample, hn::Set(du, 0x8000u)));
    hn::StoreU(hn::DemoteTo(d16, hn::BitCast(di, edge)), d16, edge_out);
    hn::StoreU(hn::Zero(d8), d8, types_out);
    counts[0] += int64_t(valid);
    counts[3] += int64_t(hn::CountTrue(du, hn::And(sample, counted)));
    return;
  }
  V count = zero, lo = hn::Set(du, 255u), hi = zero, one_per_side = hn::Set(du, ~0u);
  for (int s = 0; s < 4; ++s) {
    const V bits = hn::PopulationCount(sides[s]);
    count = hn::Add(count, bits);
    one_per_side = hn::And(one_per_side, hn::VecFromMask(du, hn::Eq(hn::And(bits, hn::Set(du, ~1u)), zero)));  // <= 1
    // The bit of a one-hot mask, then its clockwise boundary position (geometry.h).
    const V b = sides[s];
    const V m = hn::Or(hn::Or(hn::IfThenElseZero(hn::Ne(hn::And(b, hn::Set(du, 0xf0u)), zero), hn::Set(du, 4u)),
                              hn::IfThenElseZero(hn::Ne(hn::And(b, hn::Set(du, 0xccu)), zero), hn::Set(du, 2u))),
                       hn::IfThenElseZero(hn::Ne(hn::And(b, hn::Set(du, 0xaau)), zero), one));
    const V position = s < 2 ? hn::Add(m, hn::Set(du, uint32_t(8 * s))) : hn::Sub(hn::Set(du, uint32_t(8 * s + 7)), m);
    const auto present = hn::Ne(b, zero);
    lo = hn::IfThenElse(present, hn::Min(lo, position), lo);
    hi = hn::IfThenElse(present, hn::Max(hi, position), hi);
  }
  const auto empty = hn::Eq(hn::And(count, hn::Set(du, ~1u)), zero);  // count <= 1
  auto simple = hn::And(hn::Eq(count, hn::Set(du, 2u)), hn::Ne(one_per_side, zero));
  const V pair_code = hn::Or(hn::ShiftLeft<5>(lo), hi);  // the code where simple
  // The tables at the code where simple (before the centre lines' test, which only turns simple
  // lanes complex: the entries of the lanes still simple after it are the same).
  V sidedness, high;
  GatherCodeTables(du, row.code_tables, hn::IfThenElseZero(simple, pair_code), sidedness, high);
  if (centre_h) {
    // A centre-line crossing off the chord: a corner inside the pixel, complex.
    const V on_chord = hn::And(high, hn::Set(du, 0xffffu));
    const V off_chord = hn::Or(hn::AndNot(on_chord, hn::PromoteTo(du, hn::LoadU(d8, centre_h))),
                               hn::AndNot(hn::ShiftRight<8>(on_chord), hn::PromoteTo(du, hn::LoadU(d8, centre_v))));
    simple = hn::And(simple, hn::Eq(off_chord, zero));
  }
  const auto complex = hn::AndNot(simple, hn::Not(empty));  // neither empty nor simple
  const V code = hn::IfThenElseZero(simple, pair_code);
  const V region = hn::And(hn::ShiftRight<10>(in_edge), hn::Set(du, 15u));
  const V side = hn::And(hn::Shr(sidedness, hn::ShiftLeft<1>(region)), hn::Set(du, 3u));
  // A simple pixel with a sample: its side decides usability and the primary region.
  const auto decided = hn::And(simple, sample);
  const auto ambiguous = hn::And(decided, hn::Eq(side, hn::Set(du, 2u)));
  const auto usable = hn::AndNot(ambiguous, sample);
  const auto by_side = hn::AndNot(ambiguous, decided);
  const auto larger_b = hn::Ne(hn::And(high, hn::Set(du, 1u << 16)), zero);
  const auto primary_is_b = hn::Or(hn::And(by_side, hn::Eq(side, one)), hn::AndNot(by_side, larger_b));
  // Type: 2 + 2 * side pair + (primary is B) for simple pixels (geometry.h), 1 complex, 0 empty.
  const V l = hn::ShiftRight<3>(lo), h = hn::ShiftRight<3>(hi);
  const V pair = hn::IfThenElse(hn::Eq(l, zero), hn::Sub(h, one),
                                hn::IfThenElse(hn::Eq(l, one), hn::Add(h, one), hn::Set(du, 5u)));
  const V simple_type = hn::Add(hn::Add(hn::Set(du, 2u), hn::ShiftLeft<1>(pair)), hn::IfThenElseZero(primary_is_b, one));
  const V type = hn::IfThenElse(simple, simple_type, hn::IfThenElseZero(complex, one));
  const V edge = hn::Or(hn::Or(hn::And(in_edge, hn::Set(du, ~uint32_t(0x83ffu))), hn::Or(code, hn::IfThenElseZero(complex, one))),
                        hn::IfThenElseZero(usable, hn::Set(du, 0x8000u)));
  hn::StoreU(hn::DemoteTo(d16, hn::BitCast(di, edge)), d16, edge_out);
  hn::StoreU(hn::U8FromU32(type), d8, types_out);
  counts[0] += int64_t(hn::CountTrue(du, hn::And(empty, counted)));
  counts[1] += int64_t(hn::CountTrue(du, hn::And(simple, counted)));
  counts[2] += int64_t(hn::CountTrue(du, hn::And(complex, counted)));
  counts[3] += int64_t(hn::CountTrue(du, hn::And(sample, counted)));
  counts[4] += int64_t(hn::CountTrue(du, hn::And(hn::AndNot(usable, sample), counted)));
}

inline void ClassifyRowKernel(ClassifyRow& row) {
  const hn::ScalableTag<uint32_t> du;
  const int n = int(hn::Lanes(du));
  int x = 0;
  const bool centre = row.centre_h != nullptr;
  for (; x + n <= row.width; x += n)
    ClassifyLanes(du, row, row.top + x, row.bottom + x, row.left + x, row.left + x + 1,
                  centre ? row.centre_h + x : nullptr, centre ? row.centre_v + x : nullptr, row.in + x, row.edge + x,
                  row.types + x, size_t(n), row.counts);
  if (x == row.width) return;
  // The last, partial vector through zero-padded buffers.
  constexpr int kMax = HWY_LANES(uint32_t);
  const int rest = row.width - x;
  uint8_t top[kMax] = {}, bottom[kMax] = {}, left[kMax + 1] = {}, centre_h[kMax] = {}, centre_v[kMax] = {}, types[kMax];
  uint16_t in[kMax] = {}, edge[kMax];
  std::memcpy(top, row.top + x, size_t(rest));
  std::memcpy(bottom, row.bottom + x, size_t(rest));
  std::memcpy(left, row.left + x, size_t(rest) + 1);
  if (centre) {
    std::memcpy(centre_h, row.centre_h + x, size_t(rest));
    std::memcpy(centre_v, row.centre_v + x, size_t(rest));
  }
  std::memcpy(in, row.in + x, size_t(rest) * sizeof(uint16_t));
  ClassifyLanes(du, row, top, bottom, left, left + 1, centre ? centre_h : nullptr, centre ? centre_v : nullptr, in,
                edge, types, size_t(rest), row.counts);
  std::memcpy(row.edge + x, edge, size_t(rest) * sizeof(uint16_t));
  std::memcpy(row.types + x, types, size_t(rest));
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::simd
HWY_AFTER_NAMESPACE();

#endif  // EPI_SIMD_CLASSIFY_INL_H_

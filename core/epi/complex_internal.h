// Internals of the complex-pixel filter shared by the oracle (complex_filter.cpp) and the row
// kernel (complex_row.cpp, compiled once per Highway target): the sub-pixel tables, the board
// layout, the row cache's records. Not part of the library's interface.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "epi/complex_filter.h"
#include "epi/geometry.h"

namespace epi {
namespace complex_detail {

constexpr int kGrid = 6;

// Per simple sub-pixel edge (n = 4: code 16 p_low + p_high), the geometry the filter asks for,
// computed once with the same double arithmetic (so results are as if computed each time):
// the region at the eight probe points of the shared sides, the side of each quarter square,
// the area of region A.
constexpr double kProbe[2] = {1.0 / 16.0, 15.0 / 16.0};
struct SubPixelGeometry {
  uint8_t probe[4][2];  // [side: right (1,t), bottom (t,1), left (0,t), top (t,0)][t index]
  uint8_t quarter[4];   // square_side of the quarter (qx, qy) at index qx + 2 qy
  uint8_t probe_bits;   // probe[side][k] at bit 2 side + k
  float area;
};
const std::array<SubPixelGeometry, 256>& sub_pixel_geometry();

inline uint32_t half(uint32_t mask, int h) { return (mask >> (4 * h)) & 15; }

// A connected set of regions as two bitboards: regions 0 (A, or the whole of an empty
// sub-pixel) and 1 (B) of each sub-pixel.
struct Regions {
  uint64_t board[2];
  bool has(int cell, int region) const { return (board[region] >> cell) & 1; }
  // The smallest node index (2 cell + region) in the set: an id of the connected region.
  int id() const {
    const int a = board[0] ? 2 * __builtin_ctzll(board[0]) : 1000, b = board[1] ? 2 * __builtin_ctzll(board[1]) + 1 : 1000;
    return a < b ? a : b;
  }
};

// Where regions of neighbouring sub-pixels touch: bit i of joins[dir][2 ra + rb] joins region
// ra of cell i with region rb of cell i + 1 (dir 0, its right neighbour) or i + stride (dir 1, below).
using Joins = std::array<std::array<uint64_t, 4>, 2>;

// ---- The row kernel (complex_row): the same filter, restructured (docs/epi.md, "Complex pixels").
// Boards there are 6 rows of 8 bits (bit v * 8 + u, columns 6 and 7 empty), so a window's board
// is three 2-column strips side by side, each strip that of one pixel column.
constexpr int kStride = 8;

// A colour in the first three lanes of a 4-float vector (GCC/Clang vector extension): lane-wise
// products, sums and quotients round exactly as the oracle's scalar ones.
using Rgb4 = float __attribute__((vector_size(16)));
// Eight lanes (a window's eight region sets), the same extension.
using F8 = float __attribute__((vector_size(32)));
using I4 = int32_t __attribute__((vector_size(16)));
using U32x8 = uint32_t __attribute__((vector_size(32)));

// The weight 1 / (1 + d^2)^2 by d^2 (offsets up to 5 sub-pixels each way): the oracle's expression.
const std::array<float, 51>& sample_weights();
// By a window sub-pixel (v * 6 + u), its sample's weight for each lane of a window's region
// sets: lanes r and 4 + r, centre sub-pixel (2 + (r & 1), 2 + (r >> 1)); sample_weights' values.
const std::array<F8, 36>& window_weights();
// Spreads bit k of a byte to bit 8k (probe bits into a strip column; a 6-bit column into a board).
const std::array<uint64_t, 256>& spread_bits_to_bytes();

// A sub-pixel by its crossings: geom::classify_cell(sides, 4) (no 64 Ki-entry table: its
// scattered reads missed the caches), and for the row kernel the edge's probe bits spread one per
// byte.
struct SubCell {
  uint64_t probes;  // SubPixelGeometry::probe_bits, bit k at bit 8k (0 unless simple)
  uint16_t cls;     // kind | p_low << 2 | p_high << 6
  uint8_t kind, code;  // code: 16 p_low + p_high where simple, else 0
  // The region of a sample in quarter q (SubPixelGeometry::quarter) at bits 2q, 2q + 1: 3 where
  // complex (the sample is dropped), 0 where empty.
  uint8_t quarters;
};
// Entry 16 a + b: two crossings a < b (their bit indices), from classify_cell itself; at most
// one crossing (a >= b: sub_cell_entry gives b = 0) empty; entries 256-511: more than two
// crossings, complex (classify_cell's own rules).
const std::array<SubCell, 512>& sub_cells();
// The entry of a sub-pixel by its side masks (index top | right << 4 | bottom << 8 | left << 12):
// arithmetic only (as selects, GCC compiled it to branches on the crossing count, which
// mispredicted).
inline size_t sub_cell_entry(uint32_t index) {
  const uint32_t rest = index & (index - 1);  // without the lowest crossing
  const uint32_t more = uint32_t((rest & (rest - 1)) != 0);  // a third crossing
  return size_t((__builtin_ctz(index | 0x10000) & 15) * 16 + (__builtin_ctz(rest | 0x10000) & 15) + (more << 8));
}


}  // namespace complex_detail

// One pixel's sub-pixels and sample as strips take them (ComplexRowCache).
struct ComplexRowCache::Pixel {
  uint64_t column[2];   // column[sx]: bit 8k + sy = probe bit k of sub-pixel (sx, sy)
  uint16_t ok;          // bit 8 sy + sx: sub-pixel (sx, sy) not complex
  uint32_t kinds;       // CellKind of sub-pixel (sx, sy) at byte 2 sy + sx
  uint32_t codes;       // its edge code (16 p_low + p_high; 0 unless simple), the same bytes
  float present;        // the sample: 1 in a region (not dropped), else 0
  uint8_t sx, sy, region;
  complex_detail::Rgb4 rgb;             // finite also when absent; lane 3 is 0
};
struct ComplexRowCache::Rows {
  std::vector<Pixel> row[4];      // image row py at row[py & 3]
  std::vector<uint64_t> done[4];  // bit px of done[py & 3]: row[py & 3][px] computed
  uint64_t slot_row[4] = {};      // generation << 32 | py: the row a slot holds (0: none)
  uint64_t generation = 1;
  int width = -1;
  std::vector<int> xs;            // scratch: the complex pixels of the row
  std::vector<uint64_t> needed;   // scratch: the columns of their windows, one bit each
};
}  // namespace epi

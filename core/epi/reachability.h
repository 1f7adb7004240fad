// Reachability over the 5x5 neighbourhood. Footprint: 5x5 of pixel types.
// Reachability moves from the centre outwards along monotone staircase paths: a pixel at
// offset (dx, dy) is reached from its one or two side neighbours one step closer to the centre,
// (dx - sign(dx), dy) and (dx, dy - sign(dy)); each step is a neighbour-table lookup chained
// onto the path so far, and the paths are OR-combined. Complex pixels (and pixels outside the
// image) are unreachable and stop propagation. The result is the 24-bit primary-to-primary mask.
#pragma once

#include <cstdint>
#include <vector>

#include "epi/epi_pixel.h"
#include "epi/rows.h"

namespace epi {

// Bit of the 24-bit mask for offset (dx, dy), dx, dy in [-2, 2], not both 0.
constexpr int reach_bit(int dx, int dy) {
  const int index = (dy + 2) * 5 + (dx + 2);
  return index < 12 ? index : index - 1;
}
// All 24 offsets, computed directly (the oracle; the vector kernel in simd/ reuses the rows
// above by symmetry, docs/epi.md). The EpiImage form reads the cache plane, the TypeRows form
// rows y-2..y+2 (y-3..y+3 for reach_window7) of a type view (rows.h).
uint32_t reach_full(const EpiImage& epi, int x, int y);
uint32_t reach_full(TypeRows types, int x, int y);
// One propagation step of reach_full, as the visualizer's trace (trace.h) records it: offset
// (dx, dy) of type `type`, reached from `preds` side neighbours at (pred_dx, pred_dy) (type
// pred_type) in direction dir; `neighbour` the neighbour-table entry pred <-> this, `path` the
// centre <-> this along that predecessor (chained; equal to `neighbour` from the centre),
// `mask` the OR of the paths. All 4-bit masks (tables.h: Pa-Pb, Pa-Sb, Sa-Pb, Sa-Sb).
struct ReachStep {
  int dx, dy, preds;
  int pred_dx[2], pred_dy[2], dir[2];
  uint8_t type, pred_type[2], neighbour[2], path[2], mask;
};
// reach_full, recording its steps in propagation order (none on the all-empty fast path).
uint32_t reach_full_traced(TypeRows types, int x, int y, std::vector<ReachStep>& steps);
// Reachability over the 7x7 window by the same monotone paths (offsets up to 3 in x and y),
// for the fallback of pixels that reach no sample in their 5x5: bit (dy + 3) * 7 + (dx + 3),
// the centre (bit 24) included. Its inner 5x5 equals reach_full.
constexpr uint64_t kWindow7All = (uint64_t(1) << 49) - 1;
constexpr int window7_bit(int dx, int dy) { return (dy + 3) * 7 + (dx + 3); }
uint64_t reach_window7(TypeRows types, int x, int y);

}  // namespace epi

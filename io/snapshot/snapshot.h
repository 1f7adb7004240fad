// The EPI snapshot: one frame's edge-and-point image as the reconstruction reads it, so that
// the visualizer can step through the stages on real data. `epi render --save-epi FILE` writes
// it. Little-endian binary, layout in docs/visualizer.md ("Snapshots"):
//   magic "EPISNAP1", width, height (uint32), flags (uint32: bit 0 centre lines, bit 1
//   anti-aliasing, bit 2 complex filter, bit 3 fill, bit 4 unreached pixels beside edges stay
//   black, i.e. ReconstructSettings::blend_unreached_near_edges off), the edge plane (uint16 per pixel), the
//   colour plane (uint32), the masks top, left ((W+1) x (H+1) bytes each) and, with centre
//   lines, centre_h, centre_v (same size), the segment count (uint64) and the segments
//   (4 float64 each: x0 y0 x1 y1, pixel units), nothing after.
// The cache plane is not stored: the reconstruction recomputes it.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "epi/epi_pixel.h"
#include "epi/rasterize.h"
#include "epi/reconstruct.h"

namespace epi {

struct Snapshot {
  EpiImage epi;                   // edge and colour planes (classified or not)
  BoundaryMasks masks;
  std::vector<Segment> segments;  // the edges that were rasterized (for drawing)
  ReconstructSettings settings;   // filter is always Filter::epi (FrameRenderer::reconstruct_settings)
};

// what(): "<file>: <problem>", one line.
struct SnapshotError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

constexpr int kMaxSnapshotSize = 16384;

// The file's bytes (std::invalid_argument when the EPI and its masks differ in size).
std::string snapshot_bytes(const Snapshot& snapshot);
// Writes to `file` (through a temporary file renamed at the end: no half-written file).
void save_snapshot(const Snapshot& snapshot, const std::string& file);
Snapshot load_snapshot(const std::string& file);
// Whether the file starts with the snapshot magic (false when it cannot be read).
bool is_snapshot_file(const std::string& file);

}  // namespace epi

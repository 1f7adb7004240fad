// Edge rasterization into boundary-intersection masks (1/8-pixel resolution).
// Footprint: each segment touches the grid lines it crosses; the result is OR-composited.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace epi {

// A 2D edge segment in pixel coordinates (pixel (i,j) covers [i,i+1)x[j,j+1), y down).
struct Segment {
  double x0, y0, x1, y1;
};

// Grid-line crossings, one byte per grid cell (width+1 by height+1): bit m set when an edge
// crosses the 1/8 piece [m/8, (m+1)/8) of the line.
//   top[x,y]      the line y = j over x in [x, x+1)       (top of pixel (x,y), bottom of (x,y-1))
//   left[x,y]     the line x = i over y in [y, y+1)       (left of (x,y), right of (x-1,y))
//   centre_h/v    the lines y = y+1/2 and x = x+1/2 inside pixel (x,y): complex filter only.
struct BoundaryMasks {
  int width = 0, height = 0;
  bool centre_lines = false;
  std::vector<uint8_t> top, left, centre_h, centre_v;

  BoundaryMasks() = default;
  BoundaryMasks(int w, int h, bool with_centre_lines);
  size_t index(int x, int y) const { return size_t(y) * size_t(width + 1) + size_t(x); }
  void clear();
  // The four side masks of pixel (x, y): top, right, bottom, left.
  void pixel_sides(int x, int y, uint8_t sides[4]) const {
    sides[0] = top[index(x, y)];
    sides[1] = left[index(x + 1, y)];
    sides[2] = top[index(x, y + 1)];
    sides[3] = left[index(x, y)];
  }
};

// OR the crossings of each segment into the masks. The rules (docs/epi.md, "Rasterization"):
// crossings are exact intersections with the grid lines of the segment shifted by an
// infinitesimal (+e, +e^2), so an edge on a grid line, through a corner or ending on a line is
// assigned to exactly one side, the same for both pixels. Segments must be finite
// (std::invalid_argument otherwise).
void rasterize_edges(BoundaryMasks& masks, std::span<const Segment> segments);

// The same result, bit for bit, from bands of rows in parallel (each band owns its rows'
// bytes and skips segments outside them); threads 0: all cores.
void rasterize_edges_parallel(BoundaryMasks& masks, std::span<const Segment> segments, int rows_per_band = 64,
                              int threads = 0);

}  // namespace epi

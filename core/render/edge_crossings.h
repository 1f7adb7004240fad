// Which straight paths between two image positions cross a geometric edge (silhouette, border,
// sharp): the exact, sub-pixel form of "is there an edge between these two points?" that the
// edge-aware occlusion test asks (PointCache::cull_behind_surfaces, docs/render.md "Hidden points").
// The edge pieces are bucketed into square cells of the image; a query tests the pieces of the
// cells its path's bounding box overlaps. Buffers are kept between frames.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "edges/scene_edges.h"
#include "epi/rasterize.h"

namespace epi::render {

class EdgeCrossings {
 public:
  // The barrier pieces of `segments` (kinds silhouette, border, sharp; one kind per piece) over
  // an image of w x h pixels. `inv_depths`, one per segment when given (project_edges'
  // piece_inv_depth): 1/depth at its start and end; without them every piece is a barrier at
  // any depth.
  void build(std::span<const Segment> segments, std::span<const edges::EdgeKind> kinds, int w, int h,
             std::span<const glm::dvec2> inv_depths = {});
  // True when the segment from a to b (pixel coordinates) touches a barrier piece nearer than
  // `nearer_than` where it touches (its depth interpolated along the piece; where the two touch
  // along a stretch or at an end, the piece's nearer end).
  bool separated(glm::dvec2 a, glm::dvec2 b, double nearer_than = std::numeric_limits<double>::infinity()) const;
  // Whether any barrier piece is bucketed in the cells that pixels x0..x1, y0..y1 overlap (a
  // superset of the pieces inside that rectangle: cheap, and exact enough to say "none near").
  bool any_piece_near(int x0, int y0, int x1, int y1) const;
  size_t pieces() const { return pieces_.size(); }

  static constexpr int kCell = 4;  // cell side in pixels

 private:
  int cells_x_ = 0, cells_y_ = 0;
  std::vector<Segment> pieces_;         // the barrier segments
  std::vector<glm::dvec2> inv_depths_;  // 1/depth at each piece's ends; empty: depths unknown
  std::vector<uint32_t> cell_start_;    // CSR: cell c lists cell_pieces_[cell_start_[c] .. cell_start_[c+1])
  std::vector<uint32_t> cell_pieces_;
  std::vector<std::pair<uint32_t, uint32_t>> pairs_;  // (cell, piece) while building
};

}  // namespace epi::render

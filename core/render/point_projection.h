// The point cache's projection kernel (issue 11): world positions to depth and pixel position,
// the view staleness of view-dependent points and whether a point's surface faces away from the
// eye, for a batch of points at once with Highway
// (dynamic dispatch, every target Highway builds). The same operations in the same order as
// ViewFrame::project, PointCache::view_staleness and detail::faces_away, without fused multiply-add
// (-ffp-contract=off): bit-identical results (tests/render/point_cache_fast_test.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "shade/view.h"

namespace epi::render {

struct ProjectionBatch {
  static constexpr size_t kSize = 256;  // a multiple of every target's lane count
  // In: world position, the packed direction to the eye the point was shaded from (octahedral,
  // point_cache_detail.h's unpack_unit) and the lobe width (at least the minimum).
  alignas(64) float x[kSize], y[kSize], z[kSize];
  alignas(64) uint32_t view[kSize];
  alignas(64) float lobe_width[kSize];
  // In: the packed normal in the point's object space (0: no back-face test) and the eye in that
  // space less the point's position there.
  alignas(64) uint32_t normal[kSize];
  alignas(64) float eye_x[kSize], eye_y[kSize], eye_z[kSize];
  // Out: ViewFrame::project's depth and pixel; the staleness in 1/16 lobe widths where the
  // kernel settles it (detail::staleness_steps' estimate), -1 where PointCache::view_staleness
  // must (near a rounding boundary, a zero distance to the eye, a NaN).
  alignas(64) float depth[kSize], pixel_x[kSize], pixel_y[kSize];
  alignas(64) int32_t staleness[kSize];
  alignas(64) int32_t back_facing[kSize];  // detail::faces_away: 1 or 0
};

// Fills the outputs of the first n entries of the batch (n <= kSize); the inputs must be set up
// to n rounded up to 16 (a vector's lanes), or kSize.
void project_batch(const ViewFrame& frame, ProjectionBatch& batch, size_t n);

}  // namespace epi::render

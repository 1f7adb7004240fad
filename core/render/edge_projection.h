// 3D edges into the EPI (docs/render.md, "Edges"): world-space segments clipped against the near
// plane and the image, projected to pixel coordinates, and culled against a conservative depth
// buffer filtered from the reprojected points (maximum over 4x4, plus an offset that grows where
// points are sparse).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "epi/rasterize.h"
#include "render/point_cache.h"
#include "shade/view.h"

namespace epi::render {

struct DepthFilterSettings {
  float base_offset = 0.02f;    // relative depth slack where the 4x4 is full of points
  float sparse_offset = 0.25f;  // extra relative slack at the sparsest (one point in the 4x4)
};

// Per pixel: the largest point depth in the 4x4 window [x-1, x+2] x [y-1, y+2] times
// (1 + base + sparse * empty fraction of the window); +inf where the window holds no point.
void filter_depth(const PointImage& points, const DepthFilterSettings& settings, std::vector<float>& out);

enum class EdgeFate { outside, culled, visible };

// Projects the world segment a-b into `frame`: clipped to depth >= max(znear, 1e-6) and to the
// image grown by a one-pixel margin, then split where it lies behind `filtered_depth` (empty:
// no culling), sampled at most a pixel apart. Appends the visible pieces.
EdgeFate project_edge(const ViewFrame& frame, const glm::dvec3& a, const glm::dvec3& b,
                      std::span<const float> filtered_depth, std::vector<Segment>& out);

}  // namespace epi::render

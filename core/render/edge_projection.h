// 3D edges into the EPI (docs/render.md, "Edges"): world-space segments clipped against the near
// plane and the image, projected to pixel coordinates, and culled against a conservative depth
// buffer filtered from the reprojected points (maximum over 4x4, plus an offset that grows where
// points are sparse).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "edges/scene_edges.h"
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
// Bands of rows in parallel, each with its own rows' maxima (no whole-image scratch).
void filter_depth(const PointImage& points, const DepthFilterSettings& settings, std::vector<float>& out);

enum class EdgeFate { outside, culled, visible };

// Projects the world segment a-b into `frame`: clipped to depth >= max(znear, 1e-6) and to the
// image grown by a one-pixel margin, then split where it lies behind `filtered_depth` (empty:
// no culling), sampled at most a pixel apart. Appends the visible pieces, and to `inv_depths`
// (when given) 1/depth at each piece's start and end (exact: 1/depth is affine along a projected
// segment).
EdgeFate project_edge(const ViewFrame& frame, const glm::dvec3& a, const glm::dvec3& b,
                      std::span<const float> filtered_depth, std::vector<Segment>& out,
                      std::vector<glm::dvec2>* inv_depths = nullptr);

// project_edge over many edges in parallel chunks of edges,
// the pieces concatenated in edge order: `out`, `piece_edge` (the edge of each piece) and
// `piece_inv_depth` (1/depth at its ends), all appended to, are bit for bit those of calling
// project_edge on each edge in turn, whatever the thread count; fates[k] is edge k's fate. The
// chunks' buffers are kept in `scratch`.
struct EdgeProjectionScratch {
  std::vector<std::vector<Segment>> pieces;
  std::vector<std::vector<uint32_t>> piece_edge;
  std::vector<std::vector<glm::dvec2>> piece_inv_depth;
};
void project_edges(const ViewFrame& frame, std::span<const edges::SceneEdge> edges, std::span<const float> filtered_depth,
                   std::vector<Segment>& out, std::vector<uint32_t>& piece_edge, std::vector<glm::dvec2>& piece_inv_depth,
                   std::vector<EdgeFate>& fates, EdgeProjectionScratch& scratch);

// Pixels crossed by the edge pieces, sampled every 1/8 pixel along each: kDepthEdge where a
// silhouette or border crosses, kSharpEdge where a sharp edge does, kShadowEdge where an umbral,
// penumbral or shadow edge does (point_cache.h). Pieces in parallel, bits ORed in atomically:
// the same mask as piece after piece (OR does not depend on the order). `mask` is resized to
// width x height and keeps its storage.
void mark_edge_pixels(std::span<const Segment> segments, std::span<const edges::EdgeKind> kinds, int width, int height,
                      std::vector<uint8_t>& mask);

}  // namespace epi::render

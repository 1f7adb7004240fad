// Mesh topology: welding vertices by position, degenerate-triangle repair, and the
// unique-edge table (adjacent faces per edge) that `epi info` counts and the edge finder uses.
#pragma once

#include <span>
#include <vector>

#include "scene/scene.h"

namespace epi {

// Vertices with bit-identical positions (after -0 -> +0) merge. Deterministic: the welded
// vertex takes the lowest original index among its copies; welded ids are dense, in order.
struct Weld {
  std::vector<uint32_t> remap;  // original vertex -> welded vertex
  std::vector<glm::vec3> positions;  // one per welded vertex
};
Weld weld_by_position(std::span<const glm::vec3> positions);

// A unique edge of the welded mesh with its adjacent faces.
struct MeshEdge {
  uint32_t v0 = 0, v1 = 0;   // welded vertex ids, v0 < v1
  uint32_t face0 = kNone;    // first adjacent triangle
  uint32_t face1 = kNone;    // second adjacent triangle, kNone on a border
  uint32_t face_count = 0;   // 1 border, 2 manifold, >2 non-manifold
};

struct EdgeTable {
  Weld weld;
  std::vector<MeshEdge> edges;  // sorted by (v0, v1)
  uint32_t border_edges = 0;
  uint32_t non_manifold_edges = 0;
  size_t memory_bytes() const;
};
EdgeTable build_edge_table(const Mesh& mesh);

// Removes triangles with repeated vertex indices or zero area (and fixes material ranges).
// Returns how many were dropped.
uint32_t drop_degenerate_triangles(Mesh& mesh);

}  // namespace epi

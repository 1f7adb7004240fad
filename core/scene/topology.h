// Mesh topology: welding vertex copies into surface points, degenerate-triangle repair, and the
// unique-edge table (adjacent faces per edge) that `epi info` counts and the edge finder uses.
#pragma once

#include <span>
#include <vector>

#include "scene/scene.h"

namespace epi {

// The weld tolerance of a mesh: max(1e-5 x the diagonal of its bounding box, 8 float epsilons x
// its largest coordinate magnitude). Exporters write the two copies of a seam vertex from different
// formulas (cos 0 and cos 2pi) or round them differently (1e-16 to 1e-7 relative); real detail is
// far above 1e-5 of a model's size. 0 for an empty mesh or one at a single point at the origin.
float weld_tolerance(std::span<const glm::vec3> positions);

// Which vertex copies are one surface point (docs/scene-format.md, "Welding"):
//  1. position classes: copies within the tolerance in every coordinate, transitively (exact
//     copies, -0 and +0 included; non-finite positions are never welded);
//  2. a triangle side joins two classes; where exactly two sides join the same two classes (an
//     exporter's seam), their copies weld: the edge becomes manifold. Where more sides do (two
//     closed surfaces touching along an edge), they pair radially: around the edge, each face pairs
//     with its neighbour on its inner side, so each surface stays closed and apart from the other;
//     when no consistent pairing exists (inconsistent winding, odd count) all copies weld, as an
//     exact weld would, and the edge is non-manifold;
//  3. copies that share a class but no stitched edge (two boxes touching at a corner, sheets that
//     merely touch) stay apart.
// A triangle with two corners in one class is degenerate at the tolerance: those corners weld,
// and it has no edges.
// Deterministic: a welded vertex takes the position of its lowest original index; welded ids are
// dense, in the order of those indices.
struct Weld {
  std::vector<uint32_t> remap;       // original vertex -> welded vertex
  std::vector<glm::vec3> positions;  // one per welded vertex
  float tolerance = 0.0f;            // weld_tolerance of the positions
  uint32_t merged = 0;               // copies welded onto another (original count - welded count)
  uint32_t merged_inexact = 0;       // of those, copies whose position differs from their welded vertex's
};
Weld weld_mesh(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles);

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

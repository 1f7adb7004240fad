// Per-mesh edge data in object space: face planes as flat arrays (for the vectorized silhouette
// test), the unique edges of the welded mesh with their adjacent faces, and the feature flags
// (sharp by dihedral angle, border, non-manifold). Built once per mesh; see docs/edges.md.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace epi::edges {

enum EdgeFlag : uint8_t { kSharp = 1, kBorder = 2, kNonManifold = 4 };

// Where a face is seen from, in the mesh's local frame (object space minus EdgeMesh::origin):
// a point (w = 1) or a direction towards a light at infinity (w = 0).
struct Viewpoint {
  float x = 0, y = 0, z = 0, w = 1;
};

struct EdgeMesh {
  glm::dvec3 origin{0.0};  // centre of the mesh bounds; planes are stored relative to it (precision)

  // Face planes: n . (p - origin) = d, n unit length (zero for degenerate faces).
  std::vector<float> nx, ny, nz, d;
  std::vector<glm::uvec3> faces;  // welded vertex ids

  std::vector<glm::vec3> positions;  // welded, object space
  // Unique edges: welded endpoints, adjacent faces (face1 == face0 on a border, so it is never a
  // view silhouette by Equation 1), feature flags.
  std::vector<uint32_t> v0, v1, face0, face1;
  std::vector<uint8_t> flags;
  std::vector<uint32_t> feature_edges;  // edges with any flag set
  std::vector<uint32_t> border_edges;   // edges with one face (shadow-event generators: see docs)
  // Non-manifold edges (sorted) and all their faces (CSR): the faces of non_manifold[i] are
  // non_manifold_faces[non_manifold_start[i], non_manifold_start[i + 1]).
  std::vector<uint32_t> non_manifold, non_manifold_start, non_manifold_faces;
  // Faces around each welded vertex (CSR): ring_faces[ring_start[v], ring_start[v + 1]).
  std::vector<uint32_t> ring_start, ring_faces;
  float max_abs_d = 0.0f;

  size_t face_count() const { return d.size(); }
  // Every face of edge e: one on a border, two on a manifold edge, all of them when non-manifold.
  std::span<const uint32_t> edge_faces(uint32_t e, uint32_t (&scratch)[2]) const;
  size_t edge_count() const { return v0.size(); }
  size_t memory_bytes() const;

  // Object-space point or direction (towards the light) into this mesh's local frame.
  Viewpoint local_point(const glm::dvec3& object_point) const;
  static Viewpoint local_direction(const glm::dvec3& object_direction);
};

EdgeMesh build_edge_mesh(const Mesh& mesh);

// Equation 1's per-face test, with the view vector from the face's plane: the one definition that
// the brute-force finder and the edge tree's leaves share, so both give the same answer.
inline bool front_facing(const EdgeMesh& m, uint32_t f, const Viewpoint& v) {
  return m.nx[f] * v.x + m.ny[f] * v.y + m.nz[f] * v.z - m.d[f] * v.w > 0.0f;
}
inline bool is_silhouette(const EdgeMesh& m, uint32_t e, const Viewpoint& v) {
  return front_facing(m, m.face0[e], v) != front_facing(m, m.face1[e], v);
}

// Brute force over every face and edge (vectorized loops); results sorted by edge id.
// `facing` is scratch, one byte per face.
void brute_force_silhouettes(const EdgeMesh& m, const Viewpoint& v, std::vector<uint8_t>& facing,
                             std::vector<uint32_t>& out);

// Sharp edges seen from the front (an adjacent face front-facing; for a non-manifold edge any of
// its faces) that are not silhouettes, and every border edge: the feature edges to draw from
// this viewpoint.
void visible_feature_edges(const EdgeMesh& m, const Viewpoint& v, std::vector<uint32_t>& sharp,
                           std::vector<uint32_t>& border);

}  // namespace epi::edges

#include "edges/edge_mesh.h"

#include <algorithm>
#include <cmath>

#include "scene/topology.h"
#include "target_clones.h"

namespace epi::edges {

size_t EdgeMesh::memory_bytes() const {
  return (nx.capacity() + ny.capacity() + nz.capacity() + d.capacity()) * sizeof(float) +
         faces.capacity() * sizeof(glm::uvec3) + positions.capacity() * sizeof(glm::vec3) +
         (v0.capacity() + v1.capacity() + face0.capacity() + face1.capacity() + feature_edges.capacity()) *
             sizeof(uint32_t) +
         flags.capacity() + (ring_start.capacity() + ring_faces.capacity()) * sizeof(uint32_t) +
         (border_edges.capacity() + non_manifold.capacity() + non_manifold_start.capacity() +
          non_manifold_faces.capacity()) * sizeof(uint32_t);
}

Viewpoint EdgeMesh::local_point(const glm::dvec3& p) const {
  const glm::dvec3 q = p - origin;
  return {float(q.x), float(q.y), float(q.z), 1.0f};
}

Viewpoint EdgeMesh::local_direction(const glm::dvec3& direction) {
  return {float(direction.x), float(direction.y), float(direction.z), 0.0f};
}

EdgeMesh build_edge_mesh(const Mesh& mesh) {
  const EdgeTable table = build_edge_table(mesh);
  EdgeMesh m;
  m.positions = table.weld.positions;
  Bounds bounds;
  for (const glm::vec3& p : m.positions) bounds.extend(p);
  if (!bounds.empty()) m.origin = (glm::dvec3(bounds.min) + glm::dvec3(bounds.max)) * 0.5;

  // Face planes in double, rounded once to float.
  const size_t face_count = mesh.triangles.size();
  m.faces.resize(face_count);
  m.nx.resize(face_count), m.ny.resize(face_count), m.nz.resize(face_count), m.d.resize(face_count);
  for (size_t f = 0; f < face_count; ++f) {
    const glm::uvec3& t = mesh.triangles[f];
    const glm::uvec3 w{table.weld.remap[t.x], table.weld.remap[t.y], table.weld.remap[t.z]};
    m.faces[f] = w;
    const glm::dvec3 p0 = glm::dvec3(m.positions[w.x]) - m.origin;
    const glm::dvec3 p1 = glm::dvec3(m.positions[w.y]) - m.origin;
    const glm::dvec3 p2 = glm::dvec3(m.positions[w.z]) - m.origin;
    glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
    const double length = glm::length(n);
    n = length > 0.0 ? n / length : glm::dvec3(0.0);
    m.nx[f] = float(n.x), m.ny[f] = float(n.y), m.nz[f] = float(n.z);
    m.d[f] = float(glm::dot(glm::dvec3(m.nx[f], m.ny[f], m.nz[f]), (p0 + p1 + p2) / 3.0));
    m.max_abs_d = std::max(m.max_abs_d, std::fabs(m.d[f]));
  }

  // Edges and their flags. A non-manifold edge keeps its first two faces for Equation 1.
  const double sharp_cos = std::cos(double(mesh.sharp_angle_degrees) * M_PI / 180.0);
  const size_t edge_count = table.edges.size();
  m.v0.resize(edge_count), m.v1.resize(edge_count), m.face0.resize(edge_count), m.face1.resize(edge_count);
  m.flags.assign(edge_count, 0);
  for (size_t e = 0; e < edge_count; ++e) {
    const MeshEdge& edge = table.edges[e];
    m.v0[e] = edge.v0, m.v1[e] = edge.v1, m.face0[e] = edge.face0;
    m.face1[e] = edge.face_count >= 2 ? edge.face1 : edge.face0;
    uint8_t flags = 0;
    if (edge.face_count == 1) flags |= kBorder;
    if (edge.face_count > 2) flags |= kNonManifold | kSharp;
    if (edge.face_count == 2) {
      const uint32_t a = edge.face0, b = edge.face1;
      const double cos_angle = double(m.nx[a]) * m.nx[b] + double(m.ny[a]) * m.ny[b] + double(m.nz[a]) * m.nz[b];
      if (cos_angle < sharp_cos) flags |= kSharp;
    }
    m.flags[e] = flags;
    if (flags) m.feature_edges.push_back(uint32_t(e));
    if (flags & kBorder) m.border_edges.push_back(uint32_t(e));
    if (flags & kNonManifold) m.non_manifold.push_back(uint32_t(e));
  }

  // Faces around each vertex, by counting sort.
  m.ring_start.assign(m.positions.size() + 1, 0);
  for (const glm::uvec3& f : m.faces)
    for (int k = 0; k < 3; ++k) ++m.ring_start[f[k] + 1];
  for (size_t v = 0; v < m.positions.size(); ++v) m.ring_start[v + 1] += m.ring_start[v];
  m.ring_faces.resize(m.ring_start.back());
  std::vector<uint32_t> fill(m.ring_start.begin(), m.ring_start.end() - 1);
  for (uint32_t f = 0; f < m.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) m.ring_faces[fill[m.faces[f][k]]++] = f;

  // All faces of each non-manifold edge: the faces around v0 that also hold v1.
  m.non_manifold_start.push_back(0);
  for (uint32_t e : m.non_manifold) {
    for (uint32_t r = m.ring_start[m.v0[e]]; r < m.ring_start[m.v0[e] + 1]; ++r) {
      const glm::uvec3& f = m.faces[m.ring_faces[r]];
      if (f.x == m.v1[e] || f.y == m.v1[e] || f.z == m.v1[e]) m.non_manifold_faces.push_back(m.ring_faces[r]);
    }
    m.non_manifold_start.push_back(uint32_t(m.non_manifold_faces.size()));
  }
  return m;
}

std::span<const uint32_t> EdgeMesh::edge_faces(uint32_t e, uint32_t (&scratch)[2]) const {
  if (flags[e] & kNonManifold) {
    const size_t i = size_t(std::lower_bound(non_manifold.begin(), non_manifold.end(), e) - non_manifold.begin());
    return {non_manifold_faces.data() + non_manifold_start[i], non_manifold_faces.data() + non_manifold_start[i + 1]};
  }
  scratch[0] = face0[e], scratch[1] = face1[e];
  return {scratch, face0[e] == face1[e] ? 1u : 2u};
}

namespace {

// The facing pass, compiled for several instruction sets; without FMA contraction every target
// computes the same bits as the scalar front_facing().
EPI_TARGET_CLONES void facing_pass(
    const float* __restrict nx, const float* __restrict ny, const float* __restrict nz, const float* __restrict d,
    size_t n, float x, float y, float z, float w, uint8_t* __restrict facing) {
  for (size_t i = 0; i < n; ++i) facing[i] = (nx[i] * x + ny[i] * y + nz[i] * z - d[i] * w) > 0.0f;
}

}  // namespace

void brute_force_silhouettes(const EdgeMesh& m, const Viewpoint& v, std::vector<uint8_t>& facing,
                             std::vector<uint32_t>& out) {
  out.clear();
  const size_t face_count = m.face_count();
  facing.resize(face_count);
  facing_pass(m.nx.data(), m.ny.data(), m.nz.data(), m.d.data(), face_count, v.x, v.y, v.z, v.w, facing.data());
  const uint32_t* f0 = m.face0.data();
  const uint32_t* f1 = m.face1.data();
  const uint8_t* facing_data = facing.data();
  const size_t edge_count = m.edge_count();
  for (size_t e = 0; e < edge_count; ++e)
    if (facing_data[f0[e]] != facing_data[f1[e]]) out.push_back(uint32_t(e));
}

void visible_feature_edges(const EdgeMesh& m, const Viewpoint& v, std::vector<uint32_t>& sharp,
                           std::vector<uint32_t>& border) {
  sharp.clear(), border.clear();
  for (uint32_t e : m.feature_edges) {
    if (m.flags[e] & kBorder) {
      border.push_back(e);
      continue;
    }
    const bool front0 = front_facing(m, m.face0[e], v), front1 = front_facing(m, m.face1[e], v);
    if (front0 != front1) continue;  // a silhouette, reported as such
    bool front = front0;
    if (!front && (m.flags[e] & kNonManifold)) {  // a third (or later) face may face the viewer
      uint32_t scratch[2];
      for (uint32_t f : m.edge_faces(e, scratch)) front |= front_facing(m, f, v);
    }
    if (front) sharp.push_back(e);
  }
}

}  // namespace epi::edges

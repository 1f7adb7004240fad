#include "edges/receiver_tree.h"

#include <algorithm>
#include <cmath>

namespace epi::edges {
namespace {

struct Build {
  const EdgeMesh& mesh;
  std::vector<uint32_t>& faces;
  std::vector<ReceiverNode>& nodes;
  std::vector<glm::vec3> centroid;
  uint32_t leaf_size;

  void node_bounds(ReceiverNode& node, uint32_t begin, uint32_t end) const {
    for (int a = 0; a < 3; ++a) node.lo[a] = node.n_lo[a] = INFINITY, node.hi[a] = node.n_hi[a] = -INFINITY;
    node.d_lo = INFINITY, node.d_hi = -INFINITY;
    for (uint32_t i = begin; i < end; ++i) {
      const uint32_t f = faces[i];
      const float n[3] = {mesh.nx[f], mesh.ny[f], mesh.nz[f]};
      for (int a = 0; a < 3; ++a) {
        node.n_lo[a] = std::min(node.n_lo[a], n[a]), node.n_hi[a] = std::max(node.n_hi[a], n[a]);
        for (int k = 0; k < 3; ++k) {
          const float p = mesh.positions[mesh.faces[f][k]][a];
          node.lo[a] = std::min(node.lo[a], p), node.hi[a] = std::max(node.hi[a], p);
        }
      }
      node.d_lo = std::min(node.d_lo, mesh.d[f]), node.d_hi = std::max(node.d_hi, mesh.d[f]);
    }
  }

  uint32_t build(uint32_t begin, uint32_t end) {
    const uint32_t self = uint32_t(nodes.size());
    nodes.emplace_back();
    node_bounds(nodes[self], begin, end);
    if (end - begin <= leaf_size) {
      nodes[self].first = begin, nodes[self].count = end - begin;
      return self;
    }
    // Median split on the longest axis of the face centroids (ties by face id: deterministic).
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (uint32_t i = begin; i < end; ++i) lo = glm::min(lo, centroid[faces[i]]), hi = glm::max(hi, centroid[faces[i]]);
    const glm::vec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(faces.begin() + begin, faces.begin() + middle, faces.begin() + end, [&](uint32_t a, uint32_t b) {
      const float ca = centroid[a][axis], cb = centroid[b][axis];
      return ca < cb || (ca == cb && a < b);
    });
    const uint32_t left = build(begin, middle);
    const uint32_t right = build(middle, end);
    nodes[self].left = left, nodes[self].right = right;
    return self;
  }
};

}  // namespace

ReceiverTree::ReceiverTree(const EdgeMesh& mesh, uint32_t leaf_size) {
  if (mesh.face_count() == 0) return;
  faces_.resize(mesh.face_count());
  for (uint32_t f = 0; f < faces_.size(); ++f) faces_[f] = f;
  Build build{mesh, faces_, nodes_, {}, std::max(1u, leaf_size)};
  build.centroid.resize(mesh.face_count());
  for (uint32_t f = 0; f < faces_.size(); ++f) {
    const glm::uvec3& t = mesh.faces[f];
    build.centroid[f] = (mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) / 3.0f;
  }
  build.build(0, uint32_t(faces_.size()));
}

bool ReceiverTree::may_face(const ReceiverNode& node, const ViewBox& light) {
  // Some face may be front-facing to some light point unless n . e - d w < 0 over the whole node.
  const Interval n[3] = {{node.n_lo[0], node.n_hi[0]}, {node.n_lo[1], node.n_hi[1]}, {node.n_lo[2], node.n_hi[2]}};
  const Interval value = n[0] * light.x + n[1] * light.y + n[2] * light.z - Interval{node.d_lo, node.d_hi} * Interval::point(light.w);
  double magnitude = std::max(std::fabs(node.d_lo), std::fabs(node.d_hi));
  for (const Interval& e : {light.x, light.y, light.z}) magnitude += std::max(std::fabs(e.lo), std::fabs(e.hi));
  return value.hi >= -1e-6 * magnitude;
}

}  // namespace epi::edges

// A bounding-volume hierarchy over one receiver's faces (object space) whose nodes also carry
// normal and plane-offset intervals, so that a shadow event skips whole subtrees that miss its
// plane or face away from the light (section 6.4, "Shadow edge computation").
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "edges/edge_mesh.h"
#include "edges/edge_tree.h"

namespace epi::edges {

struct ReceiverNode {
  float lo[3], hi[3];      // face vertices, object space
  float n_lo[3], n_hi[3];  // face normals
  float d_lo, d_hi;        // plane offsets (local frame, as EdgeMesh::d)
  uint32_t first = 0, count = 0;  // leaf faces: faces[first, first + count)
  uint32_t left = kNone, right = kNone;
};

class ReceiverTree {
 public:
  ReceiverTree() = default;
  explicit ReceiverTree(const EdgeMesh& mesh, uint32_t leaf_size = 4);

  // Calls visit(face) for faces that may cross the plane n . x = c (object space) and may face
  // some viewpoint of `light` (local frame; null: all faces) and lie on the inner side
  // (m . x >= k) of every given half-space; the caller runs the exact tests.
  struct HalfSpace {
    glm::dvec3 m;
    double k;
  };
  template <class Visit>
  void faces_near_plane(const glm::dvec3& n, double c, double tolerance, const ViewBox* light,
                        std::span<const HalfSpace> sides, Visit&& visit) const;

  size_t memory_bytes() const { return nodes_.capacity() * sizeof(ReceiverNode) + faces_.capacity() * sizeof(uint32_t); }
  const std::vector<ReceiverNode>& nodes() const { return nodes_; }

 private:
  static bool may_face(const ReceiverNode& node, const ViewBox& light);
  std::vector<ReceiverNode> nodes_;
  std::vector<uint32_t> faces_;
};

template <class Visit>
void ReceiverTree::faces_near_plane(const glm::dvec3& n, double c, double tolerance, const ViewBox* light,
                                    std::span<const HalfSpace> sides, Visit&& visit) const {
  if (nodes_.empty()) return;
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const ReceiverNode& node = nodes_[stack[--top]];
    double centre = -c, radius = 0.0;
    for (int a = 0; a < 3; ++a) {
      centre += n[a] * 0.5 * (double(node.lo[a]) + node.hi[a]);
      radius += std::abs(n[a]) * 0.5 * (double(node.hi[a]) - node.lo[a]);
    }
    if (centre - radius > tolerance || centre + radius < -tolerance) continue;
    bool outside = false;
    for (const HalfSpace& h : sides) {
      double best = -h.k;  // the box corner farthest along m
      for (int a = 0; a < 3; ++a) best += h.m[a] >= 0.0 ? h.m[a] * double(node.hi[a]) : h.m[a] * double(node.lo[a]);
      outside |= best < -tolerance;
    }
    if (outside) continue;
    if (light && !may_face(node, *light)) continue;
    if (node.left == kNone) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) visit(faces_[i]);
      continue;
    }
    stack[top++] = node.right;
    stack[top++] = node.left;
  }
}

}  // namespace epi::edges

// The interval edge tree of section 6.4: every node bounds the normals, plane offsets and vertex
// positions of the faces of all edges below it with interval vectors, so that a query prunes any
// subtree whose faces all face the viewpoint the same way. Queries run in the mesh's local frame,
// so moving an object never rebuilds its tree. See docs/edges.md.
#pragma once

#include <cstdint>
#include <vector>

#include "edges/edge_mesh.h"
#include "edges/interval.h"

namespace epi::edges {

struct EdgeTreeSettings {
  uint32_t leaf_size = 32;                 // a node with at most this many edges is a leaf
  uint32_t parallel_threshold = 16384;    // subtrees with more edges are built as parallel tasks
  float keep_high_fraction = 0.5f;        // an edge stays at a node if its normals span more than this
                                          // fraction of the node's normal range on some axis
  bool operator==(const EdgeTreeSettings&) const = default;
};

struct EdgeTreeNode {
  float n_lo[3], n_hi[3];  // face normals
  float p_lo[3], p_hi[3];  // face vertices, local frame
  float d_lo, d_hi;        // plane offsets
  float magnitude;         // max |d| + sum of max |p|: bounds the rounding of Equation 1 (see .cpp)
  uint32_t first, count;   // edges stored at this node: order[first, first + count)
  uint32_t left = kNone, right = kNone;
};

// A box of viewpoints in the local frame (a point when lo == hi), with w = 1 or 0 as in Viewpoint.
struct ViewBox {
  Interval x, y, z;
  double w = 1.0;
  static ViewBox point(const Viewpoint& v) { return {Interval::point(v.x), Interval::point(v.y), Interval::point(v.z), v.w}; }
};

class EdgeTree {
 public:
  EdgeTree() = default;
  EdgeTree(const EdgeMesh& mesh, const EdgeTreeSettings& settings = {});

  // Silhouette edges from a viewpoint; the same set as brute_force_silhouettes, sorted by edge id.
  void silhouettes(const EdgeMesh& mesh, const Viewpoint& v, std::vector<uint32_t>& out) const;

  // Calls visit(edge) for every edge that can be a silhouette from some viewpoint in the box
  // (a superset of them: the caller runs the exact test).
  template <class Visit>
  void candidates(const EdgeMesh& mesh, const ViewBox& box, Visit&& visit) const;

  const std::vector<EdgeTreeNode>& nodes() const { return nodes_; }
  const std::vector<uint32_t>& order() const { return order_; }
  size_t memory_bytes() const {
    return nodes_.capacity() * sizeof(EdgeTreeNode) + order_.capacity() * sizeof(uint32_t) + planes_.capacity() * sizeof(EdgePlanes);
  }
  // Whether a node can hold a silhouette for some viewpoint in the box (false: prune it).
  static bool may_hold_silhouette(const EdgeTreeNode& node, const ViewBox& box, double max_abs_d);
  // The same for one viewpoint, faster (exact products in double, see edge_tree.cpp).
  static bool may_hold_silhouette(const EdgeTreeNode& node, const double e[3], double w);

  // Both face planes of every edge in tree order (a copy of EdgeMesh's, for cache-friendly leaves).
  struct EdgePlanes {
    float n0[3], d0, n1[3], d1;
  };

 private:
  std::vector<EdgeTreeNode> nodes_;  // depth first, root at 0
  std::vector<uint32_t> order_;      // silhouette-capable edge ids (no borders), grouped by node
  std::vector<EdgePlanes> planes_;   // planes_[i] belongs to order_[i]
  double max_abs_d_ = 0.0;
};

template <class Visit>
void EdgeTree::candidates(const EdgeMesh& mesh, const ViewBox& box, Visit&& visit) const {
  (void)mesh;
  if (nodes_.empty()) return;
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const EdgeTreeNode& node = nodes_[stack[--top]];
    if (!may_hold_silhouette(node, box, max_abs_d_)) continue;
    for (uint32_t i = node.first; i < node.first + node.count; ++i) visit(order_[i]);
    if (node.right != kNone) stack[top++] = node.right;
    if (node.left != kNone) stack[top++] = node.left;
  }
}

}  // namespace epi::edges

#include "edges/edge_tree.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

namespace epi::edges {
namespace {

// Bounds of one edge's faces (one face on a border), computed once before the build.
struct EdgeBounds {
  float n_lo[3], n_hi[3], p_lo[3], p_hi[3], d_lo, d_hi;
};

void clear(EdgeTreeNode& node) {
  for (int a = 0; a < 3; ++a) node.n_lo[a] = node.p_lo[a] = INFINITY, node.n_hi[a] = node.p_hi[a] = -INFINITY;
  node.d_lo = INFINITY, node.d_hi = -INFINITY;
}

void extend(EdgeTreeNode& node, const EdgeBounds& b) {
  for (int a = 0; a < 3; ++a) {
    node.n_lo[a] = std::min(node.n_lo[a], b.n_lo[a]), node.n_hi[a] = std::max(node.n_hi[a], b.n_hi[a]);
    node.p_lo[a] = std::min(node.p_lo[a], b.p_lo[a]), node.p_hi[a] = std::max(node.p_hi[a], b.p_hi[a]);
  }
  node.d_lo = std::min(node.d_lo, b.d_lo), node.d_hi = std::max(node.d_hi, b.d_hi);
}

float normal_extent(const EdgeTreeNode& node) {
  return (node.n_hi[0] - node.n_lo[0]) + (node.n_hi[1] - node.n_lo[1]) + (node.n_hi[2] - node.n_lo[2]);
}

struct Builder {
  const std::vector<EdgeBounds>& bounds;
  std::vector<uint32_t>& order;
  const EdgeTreeSettings& settings;

  float centre(uint32_t e, int axis) const { return bounds[e].n_lo[axis] + bounds[e].n_hi[axis]; }

  bool spans_node(uint32_t e, const EdgeTreeNode& node) const {
    for (int a = 0; a < 3; ++a) {
      const float range = node.n_hi[a] - node.n_lo[a];
      if (range > 0.0f && bounds[e].n_hi[a] - bounds[e].n_lo[a] > settings.keep_high_fraction * range) return true;
    }
    return false;
  }

  // Splits order[begin, end) at its middle along one normal axis (ties by edge id: deterministic).
  void split(uint32_t begin, uint32_t middle, uint32_t end, int axis) {
    std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end, [&](uint32_t a, uint32_t b) {
      const float ca = centre(a, axis), cb = centre(b, axis);
      return ca < cb || (ca == cb && a < b);
    });
  }

  float children_extent(uint32_t begin, uint32_t middle, uint32_t end) const {
    EdgeTreeNode left, right;
    clear(left), clear(right);
    for (uint32_t i = begin; i < middle; ++i) extend(left, bounds[order[i]]);
    for (uint32_t i = middle; i < end; ++i) extend(right, bounds[order[i]]);
    return normal_extent(left) + normal_extent(right);
  }

  // Builds the subtree over order[begin, end) into `out` (root first, child links local to `out`).
  void build(uint32_t begin, uint32_t end, std::vector<EdgeTreeNode>& out) {
    EdgeTreeNode node;
    clear(node);
    for (uint32_t i = begin; i < end; ++i) extend(node, bounds[order[i]]);
    node.first = begin;
    const uint32_t self = uint32_t(out.size());
    if (end - begin <= settings.leaf_size) {
      node.count = end - begin;
      out.push_back(node);
      return;
    }
    // Sharp edges (normals spanning much of the node's range) stay here, at the front.
    const auto kept = std::stable_partition(order.begin() + begin, order.begin() + end,
                                            [&](uint32_t e) { return spans_node(e, node); });
    const uint32_t rest = uint32_t(kept - order.begin());
    node.count = rest - begin;
    if (end - rest <= settings.leaf_size) {
      node.count = end - begin;
      out.push_back(node);
      return;
    }
    // The normal axis whose median split gives the smallest combined child extent.
    const uint32_t middle = rest + (end - rest) / 2;
    int best_axis = 0;
    float best_extent = INFINITY;
    for (int axis = 0; axis < 3; ++axis) {
      split(rest, middle, end, axis);
      const float extent = children_extent(rest, middle, end);
      if (extent < best_extent) best_extent = extent, best_axis = axis;
    }
    if (best_axis != 2) split(rest, middle, end, best_axis);
    out.push_back(node);

    if (end - rest > settings.parallel_threshold) {
      std::vector<EdgeTreeNode> left, right;
      tbb::parallel_invoke([&] { build(rest, middle, left); }, [&] { build(middle, end, right); });
      append(out, self, left, right);
    } else {
      out[self].left = uint32_t(out.size());
      build(rest, middle, out);
      out[self].right = uint32_t(out.size());
      build(middle, end, out);
    }
  }

  static void append(std::vector<EdgeTreeNode>& out, uint32_t self, const std::vector<EdgeTreeNode>& left,
                     const std::vector<EdgeTreeNode>& right) {
    for (const auto* part : {&left, &right}) {
      const uint32_t offset = uint32_t(out.size());
      (part == &left ? out[self].left : out[self].right) = offset;
      for (EdgeTreeNode node : *part) {
        if (node.left != kNone) node.left += offset;
        if (node.right != kNone) node.right += offset;
        out.push_back(node);
      }
    }
  }
};

double max_abs(float lo, float hi) { return std::max(std::fabs(double(lo)), std::fabs(double(hi))); }
double max_abs(const Interval& i) { return std::max(std::fabs(i.lo), std::fabs(i.hi)); }

}  // namespace

EdgeTree::EdgeTree(const EdgeMesh& mesh, const EdgeTreeSettings& settings) : max_abs_d_(mesh.max_abs_d) {
  // Only edges with two faces can be silhouettes.
  for (uint32_t e = 0; e < mesh.edge_count(); ++e)
    if (mesh.face0[e] != mesh.face1[e]) order_.push_back(e);
  if (order_.empty()) return;

  std::vector<EdgeBounds> bounds(mesh.edge_count());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.edge_count(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t e = r.begin(); e != r.end(); ++e) {
      EdgeBounds& b = bounds[e];
      const uint32_t faces[2] = {mesh.face0[e], mesh.face1[e]};
      for (int a = 0; a < 3; ++a) b.n_lo[a] = b.p_lo[a] = INFINITY, b.n_hi[a] = b.p_hi[a] = -INFINITY;
      b.d_lo = INFINITY, b.d_hi = -INFINITY;
      for (uint32_t f : faces) {
        const float n[3] = {mesh.nx[f], mesh.ny[f], mesh.nz[f]};
        for (int a = 0; a < 3; ++a) b.n_lo[a] = std::min(b.n_lo[a], n[a]), b.n_hi[a] = std::max(b.n_hi[a], n[a]);
        b.d_lo = std::min(b.d_lo, mesh.d[f]), b.d_hi = std::max(b.d_hi, mesh.d[f]);
        for (int k = 0; k < 3; ++k) {
          // Local-frame vertex, rounded outward so the float box holds the exact double value.
          const glm::dvec3 p = glm::dvec3(mesh.positions[mesh.faces[f][k]]) - mesh.origin;
          for (int a = 0; a < 3; ++a) {
            b.p_lo[a] = std::min(b.p_lo[a], std::nextafter(float(p[a]), -INFINITY));
            b.p_hi[a] = std::max(b.p_hi[a], std::nextafter(float(p[a]), INFINITY));
          }
        }
      }
    }
  });
  Builder builder{bounds, order_, settings};
  builder.build(0, uint32_t(order_.size()), nodes_);
  for (EdgeTreeNode& node : nodes_) {
    double magnitude = max_abs(node.d_lo, node.d_hi);
    for (int a = 0; a < 3; ++a) magnitude += max_abs(node.p_lo[a], node.p_hi[a]);
    node.magnitude = std::nextafter(float(magnitude), INFINITY);
  }
  planes_.resize(order_.size());
  for (size_t i = 0; i < order_.size(); ++i) {
    const uint32_t f0 = mesh.face0[order_[i]], f1 = mesh.face1[order_[i]];
    planes_[i] = {{mesh.nx[f0], mesh.ny[f0], mesh.nz[f0]}, mesh.d[f0], {mesh.nx[f1], mesh.ny[f1], mesh.nz[f1]}, mesh.d[f1]};
  }
}

// One viewpoint: every product of two floats is exact in double, and the sums of at most seven
// such terms err by a few double ulps of the magnitude, far below the 1e-6 margin that covers the
// float evaluation of Equation 1: the test stays conservative without explicit outward rounding.
bool EdgeTree::may_hold_silhouette(const EdgeTreeNode& node, const double e[3], double w) {
  double lo = -double(node.d_hi) * w, hi = -double(node.d_lo) * w;
  double magnitude = double(node.magnitude) * w;
  for (int a = 0; a < 3; ++a) {
    const double p0 = node.n_lo[a] * e[a], p1 = node.n_hi[a] * e[a];
    lo += std::min(p0, p1), hi += std::max(p0, p1);
    magnitude += std::fabs(e[a]);
  }
  const double margin = 1e-6 * magnitude + 1e-40;
  if (lo > margin || hi < -margin) return false;
  if (w == 0.0) return true;
  // n . (e - p) over the position box.
  lo = hi = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double q_lo = e[a] - node.p_hi[a], q_hi = e[a] - node.p_lo[a];
    const double p0 = node.n_lo[a] * q_lo, p1 = node.n_lo[a] * q_hi, p2 = node.n_hi[a] * q_lo, p3 = node.n_hi[a] * q_hi;
    lo += std::min(std::min(p0, p1), std::min(p2, p3)), hi += std::max(std::max(p0, p1), std::max(p2, p3));
  }
  return lo <= margin && hi >= -margin;
}

bool EdgeTree::may_hold_silhouette(const EdgeTreeNode& node, const ViewBox& box, double max_abs_d) {
  (void)max_abs_d;
  const Interval n[3] = {{node.n_lo[0], node.n_hi[0]}, {node.n_lo[1], node.n_hi[1]}, {node.n_lo[2], node.n_hi[2]}};
  const Interval e[3] = {box.x, box.y, box.z};
  const Interval w = Interval::point(box.w);
  // The float evaluation of front_facing() errs by less than a few ulps of the sum of its terms'
  // magnitudes (and the stored d differs from n . p by as much): prune only beyond that margin.
  double magnitude = max_abs(node.d_lo, node.d_hi) * box.w;
  for (int a = 0; a < 3; ++a)
    magnitude += max_abs(node.n_lo[a], node.n_hi[a]) * max_abs(e[a]) + max_abs(node.p_lo[a], node.p_hi[a]) * box.w;
  const double margin = 1e-6 * magnitude + 1e-40;

  // n . e - d w over the node's plane intervals.
  const Interval plane = n[0] * e[0] + n[1] * e[1] + n[2] * e[2] - Interval{node.d_lo, node.d_hi} * w;
  if (!plane.contains_zero_within(margin)) return false;
  if (box.w == 0.0) return true;
  // n . (e - p) over the node's position intervals.
  Interval sum{0.0, 0.0};
  for (int a = 0; a < 3; ++a) sum = sum + n[a] * (e[a] - Interval{node.p_lo[a], node.p_hi[a]});
  return sum.contains_zero_within(margin);
}

void EdgeTree::silhouettes(const EdgeMesh& mesh, const Viewpoint& v, std::vector<uint32_t>& out) const {
  (void)mesh;
  out.clear();
  if (nodes_.empty()) return;
  const double e[3] = {v.x, v.y, v.z};
  const double w = v.w;
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const EdgeTreeNode& node = nodes_[stack[--top]];
    if (!may_hold_silhouette(node, e, w)) continue;
    // Equation 1 on the node's edges, written exactly as front_facing() so that the bits agree.
    for (uint32_t i = node.first; i < node.first + node.count; ++i) {
      const EdgePlanes& p = planes_[i];
      const bool front0 = p.n0[0] * v.x + p.n0[1] * v.y + p.n0[2] * v.z - p.d0 * v.w > 0.0f;
      const bool front1 = p.n1[0] * v.x + p.n1[1] * v.y + p.n1[2] * v.z - p.d1 * v.w > 0.0f;
      if (front0 != front1) out.push_back(order_[i]);
    }
    if (node.right != kNone) stack[top++] = node.right;
    if (node.left != kNone) stack[top++] = node.left;
  }
  std::sort(out.begin(), out.end());
}

}  // namespace epi::edges

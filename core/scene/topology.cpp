// Welding, the unique-edge table and degenerate-triangle removal: passes over flat arrays (a
// sorted grid for the position classes, disjoint sets for the weld, a counting sort for the edges).
#include "scene/topology.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

namespace epi {
namespace {

// Disjoint sets over vertex indices (path halving; the lower index becomes the root).
class DisjointSets {
 public:
  explicit DisjointSets(size_t n) : parent_(n) {
    for (size_t i = 0; i < n; ++i) parent_[i] = uint32_t(i);
  }
  uint32_t find(uint32_t v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  void join(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<uint32_t> parent_;
};

// A triangle side from corner `corner` to corner `corner + 1`, its ends mapped to (lo, hi), lo < hi.
struct Side {
  uint32_t lo, hi, face, corner;
};

// The sides of the triangles under `map` (vertex -> class or welded id, `count` of them), sorted
// by (lo, hi) and in triangle order within a group: a counting sort by lo, then each bucket (a
// vertex's valence) stably by hi. A triangle with two corners mapped to one vertex is collapsed
// (a sliver below the tolerance, such as a pole's) and has no sides: its two remaining sides
// coincide and would make its edge look non-manifold.
std::vector<Side> grouped_sides(std::span<const glm::uvec3> triangles, const std::vector<uint32_t>& map, size_t count) {
  std::vector<uint32_t> bucket_start(count + 1, 0);
  auto for_each_side = [&](auto&& visit) {
    for (uint32_t t = 0; t < triangles.size(); ++t) {
      const uint32_t w[3] = {map[triangles[t].x], map[triangles[t].y], map[triangles[t].z]};
      if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) continue;
      for (uint32_t i = 0; i < 3; ++i) visit(Side{std::min(w[i], w[(i + 1) % 3]), std::max(w[i], w[(i + 1) % 3]), t, i});
    }
  };
  for_each_side([&](const Side& s) { ++bucket_start[s.lo + 1]; });
  for (size_t v = 0; v < count; ++v) bucket_start[v + 1] += bucket_start[v];
  std::vector<Side> sides(bucket_start[count]);
  std::vector<uint32_t> fill(bucket_start.begin(), bucket_start.end() - 1);
  for_each_side([&](const Side& s) { sides[fill[s.lo]++] = s; });
  for (size_t v = 0; v < count; ++v)
    std::stable_sort(sides.begin() + bucket_start[v], sides.begin() + bucket_start[v + 1],
                     [](const Side& a, const Side& b) { return a.hi < b.hi; });
  return sides;
}

// Calls visit(first, last) for each run of sides with the same (lo, hi).
template <class Visit>
void for_each_group(const std::vector<Side>& sides, Visit&& visit) {
  for (size_t i = 0; i < sides.size();) {
    size_t end = i + 1;
    while (end < sides.size() && sides[end].lo == sides[i].lo && sides[end].hi == sides[i].hi) ++end;
    visit(i, end);
    i = end;
  }
}

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// Bit pattern of a coordinate with -0 folded onto +0, so that the two weld together.
uint32_t coordinate_bits(float value) {
  uint32_t bits = std::bit_cast<uint32_t>(value);
  return bits == 0x80000000u ? 0u : bits;
}

uint64_t mix(uint64_t h) {  // murmur3 finaliser
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return h;
}

bool same_bits(const glm::vec3& a, const glm::vec3& b) {
  return coordinate_bits(a.x) == coordinate_bits(b.x) && coordinate_bits(a.y) == coordinate_bits(b.y) &&
         coordinate_bits(a.z) == coordinate_bits(b.z);
}

// An open-addressing table from 64-bit keys to the first of a chain of ids.
class ChainTable {
 public:
  explicit ChainTable(size_t entries) {
    size_t capacity = 16;
    while (capacity < 2 * entries) capacity *= 2;
    keys_.resize(capacity), heads_.assign(capacity, kNone), mask_ = capacity - 1;
  }
  // The chain head for `key`, created (kNone) if new.
  uint32_t& head(uint64_t key) {
    size_t slot = mix(key) & mask_;
    while (heads_[slot] != kNone && keys_[slot] != key) slot = (slot + 1) & mask_;
    keys_[slot] = key;
    return heads_[slot];
  }

 private:
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> heads_;
  size_t mask_ = 0;
};

// Position classes: vertices within `tolerance` in every coordinate, transitively. Exact copies
// first (a hash of the coordinates' bits), then the distinct finite positions on a grid of cells
// 32 tolerances wide: each is tested against those in the cells its tolerance box overlaps.
// Returns the class of each vertex (dense ids, in order of first appearance) and their count.
std::vector<uint32_t> position_classes(std::span<const glm::vec3> positions, float tolerance, size_t& class_count) {
  const size_t n = positions.size();
  // Exact copies: distinct[v] numbers the distinct bit patterns; first_of[d] is the first vertex.
  std::vector<uint32_t> distinct(n), first_of;
  {
    ChainTable table(n);
    std::vector<uint32_t> next;  // chains of distinct ids whose bits hash alike
    for (uint32_t v = 0; v < n; ++v) {
      const glm::vec3& p = positions[v];
      const uint64_t key =
          (uint64_t(coordinate_bits(p.x)) << 32 | coordinate_bits(p.y)) ^ mix(coordinate_bits(p.z) + 0x9e3779b97f4a7c15ull);
      uint32_t& head = table.head(key);
      uint32_t d = head;
      while (d != kNone && !same_bits(positions[first_of[d]], p)) d = next[d];
      if (d == kNone) {
        d = uint32_t(first_of.size());
        first_of.push_back(v), next.push_back(head), head = d;
      }
      distinct[v] = d;
    }
  }
  // Near copies: the grid over distinct finite positions.
  DisjointSets sets(first_of.size());
  Bounds bounds;
  for (uint32_t v : first_of)
    if (finite(positions[v])) bounds.extend(positions[v]);
  if (!bounds.empty() && tolerance > 0.0f) {
    const double cell = 32.0 * double(tolerance);
    auto cell_index = [&](double coordinate, int axis) {  // at most 3,126 per axis
      return uint64_t(std::max(0.0, std::floor((coordinate - double(bounds.min[axis])) / cell)));
    };
    auto key = [](uint64_t x, uint64_t y, uint64_t z) { return x << 42 | y << 21 | z; };
    // The positions sorted by cell: a cell's positions are one run. Each position is tested
    // against the rest of its run, and, where its tolerance box crosses into cells of higher key
    // (rarely: cells are 32 tolerances wide), against those found by binary search. A pair is
    // found from its lower cell only: the boxes of two positions within the tolerance overlap
    // each other's cells.
    struct Entry {
      uint64_t key;
      uint32_t distinct;
    };
    std::vector<Entry> entries;
    entries.reserve(first_of.size());
    for (uint32_t d = 0; d < first_of.size(); ++d) {
      const glm::vec3& p = positions[first_of[d]];
      if (finite(p)) entries.push_back({key(cell_index(p.x, 0), cell_index(p.y, 1), cell_index(p.z, 2)), d});
    }
    std::sort(entries.begin(), entries.end(),
              [](const Entry& x, const Entry& y) { return x.key != y.key ? x.key < y.key : x.distinct < y.distinct; });
    auto test_run = [&](const glm::vec3& p, uint32_t d, size_t from, uint64_t k) {
      for (size_t j = from; j < entries.size() && entries[j].key == k; ++j) {
        const glm::vec3 gap = glm::abs(positions[first_of[entries[j].distinct]] - p);
        if (std::max({gap.x, gap.y, gap.z}) <= tolerance) sets.join(d, entries[j].distinct);
      }
    };
    for (size_t i = 0; i < entries.size(); ++i) {
      const uint32_t d = entries[i].distinct;
      const glm::vec3& p = positions[first_of[d]];
      test_run(p, d, i + 1, entries[i].key);
      uint64_t lo[3], hi[3];
      for (int axis = 0; axis < 3; ++axis)
        lo[axis] = cell_index(double(p[axis]) - tolerance, axis), hi[axis] = cell_index(double(p[axis]) + tolerance, axis);
      if (lo[0] == hi[0] && lo[1] == hi[1] && lo[2] == hi[2]) continue;  // inside its cell
      for (uint64_t x = lo[0]; x <= hi[0]; ++x)
        for (uint64_t y = lo[1]; y <= hi[1]; ++y)
          for (uint64_t z = lo[2]; z <= hi[2]; ++z) {
            const uint64_t k = key(x, y, z);
            if (k <= entries[i].key) continue;
            const auto first = std::lower_bound(entries.begin(), entries.end(), k,
                                                [](const Entry& e, uint64_t value) { return e.key < value; });
            test_run(p, d, size_t(first - entries.begin()), k);
          }
    }
  }
  std::vector<uint32_t> class_of_root(first_of.size(), kNone);
  std::vector<uint32_t> classes(n);
  class_count = 0;
  for (uint32_t v = 0; v < n; ++v) {
    uint32_t& c = class_of_root[sets.find(distinct[v])];
    if (c == kNone) c = uint32_t(class_count++);
    classes[v] = c;
  }
  return classes;
}

// Pairs the faces of the sides in [first, last), which all join the same two position classes:
// around the edge, each face pairs with its neighbour on its inner side (opposite its normal).
// Returns false when they do not alternate so (odd count, inconsistent winding, zero-area faces).
bool pair_radially(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles,
                   const std::vector<Side>& sides, size_t first, size_t last, std::vector<std::pair<size_t, size_t>>& pairs) {
  if ((last - first) % 2 != 0) return false;
  // The edge axis from the first side's ends (class lo to class hi) and a basis across it.
  const Side& s0 = sides[first];
  glm::dvec3 a(positions[triangles[s0.face][s0.corner]]), b(positions[triangles[s0.face][(s0.corner + 1) % 3]]);
  glm::dvec3 axis = glm::normalize(b - a);
  const glm::dvec3 helper = std::fabs(axis.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 r1 = glm::normalize(glm::cross(axis, helper)), r2 = glm::cross(axis, r1);
  struct Wing {
    double angle;
    int inner;  // +1: the face's inside (opposite its normal) lies towards increasing angle
    size_t side;
  };
  std::vector<Wing> wings;
  for (size_t s = first; s < last; ++s) {
    const glm::uvec3& tri = triangles[sides[s].face];
    const glm::dvec3 p0(positions[tri.x]), p1(positions[tri.y]), p2(positions[tri.z]);
    glm::dvec3 w = glm::dvec3(positions[tri[(sides[s].corner + 2) % 3]]) - a;
    w -= axis * glm::dot(w, axis);
    const double inner = -glm::dot(glm::cross(p1 - p0, p2 - p0), glm::cross(axis, w));
    if (!(inner != 0.0) || !std::isfinite(inner)) return false;
    wings.push_back({std::atan2(glm::dot(w, r2), glm::dot(w, r1)), inner > 0.0 ? 1 : -1, s});
  }
  // Measure angles from the middle of the widest gap, so that no tie straddles the wrap-around;
  // angles within 1e-6 rad are ties (coincident faces), ordered with inner-towards-lower first.
  std::sort(wings.begin(), wings.end(), [](const Wing& x, const Wing& y) { return x.angle < y.angle; });
  double widest = wings.front().angle + 2.0 * M_PI - wings.back().angle, start = wings.back().angle;
  for (size_t i = 1; i < wings.size(); ++i)
    if (wings[i].angle - wings[i - 1].angle > widest) widest = wings[i].angle - wings[i - 1].angle, start = wings[i - 1].angle;
  for (Wing& w : wings) w.angle = std::fmod(w.angle - start - 0.5 * widest + 4.0 * M_PI, 2.0 * M_PI);
  std::sort(wings.begin(), wings.end(), [](const Wing& x, const Wing& y) { return x.angle < y.angle; });
  for (size_t i = 1; i < wings.size(); ++i)
    if (wings[i].angle - wings[i - 1].angle < 1e-6) wings[i].angle = wings[i - 1].angle;
  std::stable_sort(wings.begin(), wings.end(), [](const Wing& x, const Wing& y) {
    return x.angle != y.angle ? x.angle < y.angle : x.inner < y.inner;
  });
  // Inner sides must alternate +, - going around (starting anywhere on a +).
  size_t offset = wings[0].inner > 0 ? 0 : 1;
  for (size_t i = 0; i < wings.size(); i += 2) {
    const Wing& x = wings[(i + offset) % wings.size()];
    const Wing& y = wings[(i + offset + 1) % wings.size()];
    if (x.inner < 0 || y.inner > 0) return false;
    pairs.emplace_back(x.side, y.side);
  }
  return true;
}

}  // namespace

float weld_tolerance(std::span<const glm::vec3> positions) {
  Bounds bounds;
  float largest = 0.0f;
  for (const glm::vec3& p : positions)
    if (finite(p)) bounds.extend(p), largest = std::max({largest, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  if (bounds.empty()) return 0.0f;
  const double diagonal = glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min));
  return float(std::max(1e-5 * diagonal, 8.0 * double(std::numeric_limits<float>::epsilon()) * largest));
}

namespace {

// weld_mesh, and the sides grouped by welded vertex when they come for free: when every position
// class welded whole, class ids are welded ids and the stitching's grouping is the edge table's.
Weld weld_with_sides(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles,
                     std::vector<Side>* welded_sides) {
  Weld weld;
  weld.tolerance = weld_tolerance(positions);
  size_t class_count = 0;
  const std::vector<uint32_t> classes = position_classes(positions, weld.tolerance, class_count);

  // Stitch: the copies at the ends of sides that pair up join.
  DisjointSets copies(positions.size());
  std::vector<Side> sides = grouped_sides(triangles, classes, class_count);
  auto end_vertex = [&](const Side& s, uint32_t cls) {
    const glm::uvec3& tri = triangles[s.face];
    const uint32_t v = tri[s.corner];
    return classes[v] == cls ? v : tri[(s.corner + 1) % 3];
  };
  auto stitch = [&](const Side& x, const Side& y) {
    copies.join(end_vertex(x, x.lo), end_vertex(y, x.lo));
    copies.join(end_vertex(x, x.hi), end_vertex(y, x.hi));
  };
  // A triangle collapsed at the tolerance joins its corners that share a class (a pole copy used
  // only by its sliver would stay apart and bring the sliver's edges back).
  for (const glm::uvec3& t : triangles)
    for (int i = 0; i < 3; ++i)
      if (classes[t[i]] == classes[t[(i + 1) % 3]]) copies.join(t[i], t[(i + 1) % 3]);
  std::vector<std::pair<size_t, size_t>> pairs;
  for_each_group(sides, [&](size_t first, size_t last) {
    if (last - first == 2) return stitch(sides[first], sides[first + 1]);
    if (last - first < 2) return;
    pairs.clear();
    if (pair_radially(positions, triangles, sides, first, last, pairs)) {
      for (const auto& [x, y] : pairs) stitch(sides[x], sides[y]);
    } else {
      for (size_t s = first + 1; s < last; ++s) stitch(sides[first], sides[s]);
    }
  });

  // Welded ids in the order of each set's lowest index.
  weld.remap.assign(positions.size(), kNone);
  for (uint32_t v = 0; v < positions.size(); ++v) {
    const uint32_t root = copies.find(v);
    if (root == v) {
      weld.remap[v] = uint32_t(weld.positions.size());
      weld.positions.push_back(positions[v]);
    } else {
      weld.remap[v] = weld.remap[root];
      ++weld.merged;
      const glm::vec3 &p = positions[v], &q = positions[root];
      if (p.x != q.x || p.y != q.y || p.z != q.z) ++weld.merged_inexact;  // -0 == +0
    }
  }
  weld.positions.shrink_to_fit();
  if (welded_sides)
    *welded_sides = weld.positions.size() == class_count ? std::move(sides)
                                                         : grouped_sides(triangles, weld.remap, weld.positions.size());
  return weld;
}

}  // namespace

Weld weld_mesh(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles) {
  return weld_with_sides(positions, triangles, nullptr);
}

size_t EdgeTable::memory_bytes() const {
  return weld.remap.capacity() * sizeof(uint32_t) + weld.positions.capacity() * sizeof(glm::vec3) +
         edges.capacity() * sizeof(MeshEdge);
}

EdgeTable build_edge_table(const Mesh& mesh) {
  EdgeTable table;
  std::vector<Side> sides;
  table.weld = weld_with_sides(mesh.positions, mesh.triangles, &sides);
  table.edges.reserve(sides.size() / 2 + 1);
  for_each_group(sides, [&](size_t first, size_t last) {
    MeshEdge edge;
    edge.v0 = sides[first].lo;
    edge.v1 = sides[first].hi;
    edge.face0 = sides[first].face;
    edge.face1 = last - first > 1 ? sides[first + 1].face : kNone;
    edge.face_count = uint32_t(last - first);
    if (edge.face_count == 1) ++table.border_edges;
    if (edge.face_count > 2) ++table.non_manifold_edges;
    table.edges.push_back(edge);
  });
  table.edges.shrink_to_fit();
  return table;
}

uint32_t drop_degenerate_triangles(Mesh& mesh) {
  auto degenerate = [&](const glm::uvec3& t) {
    if (t.x == t.y || t.y == t.z || t.x == t.z) return true;
    assert(t.x < mesh.positions.size() && t.y < mesh.positions.size() && t.z < mesh.positions.size());
    // Zero area, decided in double so that float round-off does not hide or invent it.
    const glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
  };

  // Compact the triangles in place, counting survivors as we go: kept_before[t] is the new index
  // of old triangle t, so each material range maps to [kept_before[first], kept_before[end]).
  std::vector<uint32_t> kept_before(mesh.triangles.size() + 1);
  uint32_t kept = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    kept_before[t] = kept;
    if (!degenerate(mesh.triangles[t])) mesh.triangles[kept++] = mesh.triangles[t];
  }
  kept_before[mesh.triangles.size()] = kept;
  std::vector<MaterialRange> ranges;
  for (const MaterialRange& r : mesh.materials) {
    const size_t first = std::min<size_t>(r.first_triangle, mesh.triangles.size());
    const size_t end = std::min<size_t>(size_t(r.first_triangle) + r.triangle_count, mesh.triangles.size());
    const uint32_t count = kept_before[end] - kept_before[first];
    if (count > 0) ranges.push_back({kept_before[first], count, r.material});  // ranges left empty go
  }
  const uint32_t dropped = static_cast<uint32_t>(mesh.triangles.size() - kept);
  mesh.triangles.resize(kept);
  mesh.materials = std::move(ranges);
  return dropped;
}

}  // namespace epi

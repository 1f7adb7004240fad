// Welding, the unique-edge table and degenerate-triangle removal: linear-time passes over flat
// arrays (an open-addressing hash table for the weld, a counting sort for the edges).
#include "scene/topology.h"

#include <algorithm>
#include <bit>
#include <cassert>

namespace epi {
namespace {

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

uint64_t position_hash(const glm::vec3& p) {
  const uint64_t x = coordinate_bits(p.x), y = coordinate_bits(p.y), z = coordinate_bits(p.z);
  return mix((x << 32 | y) ^ mix(z + 0x9e3779b97f4a7c15ull));
}

bool same_position(const glm::vec3& a, const glm::vec3& b) {
  return coordinate_bits(a.x) == coordinate_bits(b.x) && coordinate_bits(a.y) == coordinate_bits(b.y) &&
         coordinate_bits(a.z) == coordinate_bits(b.z);
}

}  // namespace

Weld weld_by_position(std::span<const glm::vec3> positions) {
  // Open addressing over welded ids; vertices are visited in order, so the first copy of a position
  // (its lowest index) creates the welded vertex and welded ids come out dense and in order.
  Weld weld;
  weld.remap.resize(positions.size());
  size_t capacity = 16;
  while (capacity < 2 * positions.size()) capacity *= 2;
  const size_t mask = capacity - 1;
  std::vector<uint32_t> table(capacity, kNone);
  for (size_t v = 0; v < positions.size(); ++v) {
    size_t slot = position_hash(positions[v]) & mask;
    while (table[slot] != kNone && !same_position(weld.positions[table[slot]], positions[v])) slot = (slot + 1) & mask;
    if (table[slot] == kNone) {
      table[slot] = static_cast<uint32_t>(weld.positions.size());
      weld.positions.push_back(positions[v]);
    }
    weld.remap[v] = table[slot];
  }
  weld.positions.shrink_to_fit();
  return weld;
}

size_t EdgeTable::memory_bytes() const {
  return weld.remap.capacity() * sizeof(uint32_t) + weld.positions.capacity() * sizeof(glm::vec3) +
         edges.capacity() * sizeof(MeshEdge);
}

EdgeTable build_edge_table(const Mesh& mesh) {
  EdgeTable table;
  table.weld = weld_by_position(mesh.positions);
  const std::vector<uint32_t>& remap = table.weld.remap;
  const size_t vertex_count = table.weld.positions.size();

  // Counting sort of the triangle sides by their lower welded vertex. Sides whose two ends weld
  // together (degenerate) have no edge. Within a bucket, sides keep triangle order.
  std::vector<uint32_t> bucket_start(vertex_count + 1, 0);
  auto for_each_side = [&](auto&& visit) {
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      const glm::uvec3& tri = mesh.triangles[t];
      const uint32_t w[3] = {remap[tri.x], remap[tri.y], remap[tri.z]};
      for (int i = 0; i < 3; ++i) {
        const uint32_t a = w[i], b = w[(i + 1) % 3];
        if (a != b) visit(std::min(a, b), std::max(a, b), t);
      }
    }
  };
  for_each_side([&](uint32_t lo, uint32_t, uint32_t) { ++bucket_start[lo + 1]; });
  for (size_t v = 0; v < vertex_count; ++v) bucket_start[v + 1] += bucket_start[v];

  struct Side {
    uint32_t other, face;
  };
  std::vector<Side> sides(bucket_start[vertex_count]);
  {
    std::vector<uint32_t> fill(bucket_start.begin(), bucket_start.end() - 1);
    for_each_side([&](uint32_t lo, uint32_t hi, uint32_t t) { sides[fill[lo]++] = {hi, t}; });
  }

  // Each bucket is small (the vertex valence): sort it by the other end, stably, and group.
  table.edges.reserve(sides.size() / 2 + 1);
  for (size_t v = 0; v < vertex_count; ++v) {
    auto begin = sides.begin() + bucket_start[v], end = sides.begin() + bucket_start[v + 1];
    std::stable_sort(begin, end, [](const Side& a, const Side& b) { return a.other < b.other; });
    for (auto it = begin; it != end;) {
      auto group_end = it;
      while (group_end != end && group_end->other == it->other) ++group_end;
      MeshEdge edge;
      edge.v0 = static_cast<uint32_t>(v);
      edge.v1 = it->other;
      edge.face0 = it->face;
      edge.face1 = group_end - it > 1 ? (it + 1)->face : kNone;
      edge.face_count = static_cast<uint32_t>(group_end - it);
      if (edge.face_count == 1) ++table.border_edges;
      if (edge.face_count > 2) ++table.non_manifold_edges;
      table.edges.push_back(edge);
      it = group_end;
    }
  }
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

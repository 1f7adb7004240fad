// Topology: weld and edge table against brute-force references, counts on hand-built meshes,
// degenerate-triangle removal.
#include <algorithm>
#include <bit>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "scene/topology.h"

namespace epi {
namespace {

bool same_bits(const glm::vec3& a, const glm::vec3& b) {
  auto bits = [](float f) { return f == 0.0f ? 0u : std::bit_cast<uint32_t>(f); };
  return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z);
}

// O(n^2) reference: each vertex maps to its lowest-index copy; welded ids number those in order.
Weld brute_force_weld(const std::vector<glm::vec3>& positions) {
  Weld weld;
  std::vector<uint32_t> id_of_first(positions.size(), kNone);
  for (size_t v = 0; v < positions.size(); ++v) {
    size_t first = 0;
    while (!same_bits(positions[first], positions[v])) ++first;
    if (first == v) {
      id_of_first[v] = uint32_t(weld.positions.size());
      weld.positions.push_back(positions[v]);
    }
    weld.remap.push_back(id_of_first[first]);
  }
  return weld;
}

// Reference edge table from a std::map over welded sides, in triangle order.
std::vector<MeshEdge> brute_force_edges(const Mesh& mesh, const Weld& weld) {
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> faces_of_edge;
  for (uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = weld.remap[mesh.triangles[t][i]], b = weld.remap[mesh.triangles[t][(i + 1) % 3]];
      if (a != b) faces_of_edge[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  std::vector<MeshEdge> edges;
  for (const auto& [key, faces] : faces_of_edge)
    edges.push_back({key.first, key.second, faces[0], faces.size() > 1 ? faces[1] : kNone, uint32_t(faces.size())});
  return edges;
}

// Random mesh whose positions come from a small pool (so many coincide, including -0 and +0).
Mesh random_mesh(std::mt19937& rng, size_t vertex_count, size_t triangle_count, int pool) {
  std::uniform_int_distribution<int> coordinate(-pool, pool);
  Mesh mesh;
  for (size_t v = 0; v < vertex_count; ++v) {
    glm::vec3 p;
    for (int axis = 0; axis < 3; ++axis) {
      p[axis] = coordinate(rng) * 0.5f;
      if (p[axis] == 0.0f && rng() % 2) p[axis] = -0.0f;
    }
    mesh.positions.push_back(p);
  }
  std::uniform_int_distribution<uint32_t> index(0, uint32_t(vertex_count - 1));
  for (size_t t = 0; t < triangle_count; ++t) mesh.triangles.emplace_back(index(rng), index(rng), index(rng));
  return mesh;
}

TEST(Weld, MatchesBruteForceOnRandomMeshes) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 60; ++trial) {
    const size_t n = 1 + rng() % 400;
    const Mesh mesh = random_mesh(rng, n, 1, 1 + trial % 6);
    const Weld expected = brute_force_weld(mesh.positions);
    const Weld weld = weld_by_position(mesh.positions);
    ASSERT_EQ(weld.remap, expected.remap) << "trial " << trial;
    ASSERT_EQ(weld.positions.size(), expected.positions.size());
    for (size_t i = 0; i < weld.positions.size(); ++i) ASSERT_TRUE(same_bits(weld.positions[i], expected.positions[i]));
  }
}

TEST(Weld, SignedZerosMergeAndOtherBitsDoNot) {
  const std::vector<glm::vec3> p = {{0.0f, 1.0f, 2.0f}, {-0.0f, 1.0f, 2.0f}, {0.0f, 1.0f, std::nextafter(2.0f, 3.0f)},
                                    {0.0f, -0.0f, 0.0f}, {-0.0f, 0.0f, -0.0f}};
  const Weld weld = weld_by_position(p);
  EXPECT_EQ(weld.remap, (std::vector<uint32_t>{0, 0, 1, 2, 2}));
  EXPECT_EQ(weld.positions.size(), 3u);
  EXPECT_TRUE(weld_by_position({}).positions.empty());
}

TEST(Weld, AllDistinctIsIdentity) {
  std::vector<glm::vec3> p;
  for (int i = 0; i < 10000; ++i) p.emplace_back(float(i), float(i % 7), -float(i % 13));
  const Weld weld = weld_by_position(p);
  for (uint32_t i = 0; i < p.size(); ++i) ASSERT_EQ(weld.remap[i], i);
}

void expect_same_edges(const EdgeTable& table, const std::vector<MeshEdge>& expected) {
  ASSERT_EQ(table.edges.size(), expected.size());
  uint32_t border = 0, non_manifold = 0;
  for (size_t e = 0; e < expected.size(); ++e) {
    const MeshEdge& a = table.edges[e];
    const MeshEdge& b = expected[e];
    ASSERT_EQ(a.v0, b.v0) << e;
    ASSERT_EQ(a.v1, b.v1) << e;
    ASSERT_EQ(a.face0, b.face0) << e;
    ASSERT_EQ(a.face1, b.face1) << e;
    ASSERT_EQ(a.face_count, b.face_count) << e;
    border += b.face_count == 1;
    non_manifold += b.face_count > 2;
  }
  EXPECT_EQ(table.border_edges, border);
  EXPECT_EQ(table.non_manifold_edges, non_manifold);
}

TEST(EdgeTable, MatchesBruteForceOnRandomMeshes) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    const Mesh mesh = random_mesh(rng, 3 + rng() % 300, 1 + rng() % 500, 1 + trial % 5);
    const EdgeTable table = build_edge_table(mesh);
    const Weld weld = brute_force_weld(mesh.positions);
    ASSERT_EQ(table.weld.remap, weld.remap);
    expect_same_edges(table, brute_force_edges(mesh, weld));
  }
}

TEST(EdgeTable, MatchesReferenceOnALargeGrid) {
  // A triangle soup (3 vertices per triangle) of a 300x300 grid: welding must rebuild the grid.
  const int n = 300;
  Mesh mesh;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const glm::vec3 a(x, y, 0), b(x + 1, y, 0), c(x + 1, y + 1, 0), d(x, y + 1, 0);
      for (const glm::vec3& p : {a, b, c, a, c, d}) mesh.positions.push_back(p * 0.1f);
      const uint32_t base = uint32_t(mesh.positions.size() - 6);
      mesh.triangles.emplace_back(base, base + 1, base + 2);
      mesh.triangles.emplace_back(base + 3, base + 4, base + 5);
    }
  const EdgeTable table = build_edge_table(mesh);
  EXPECT_EQ(table.weld.positions.size(), size_t(n + 1) * (n + 1));
  EXPECT_EQ(table.edges.size(), size_t(2 * n * (n + 1) + n * n));
  EXPECT_EQ(table.border_edges, uint32_t(4 * n));
  EXPECT_EQ(table.non_manifold_edges, 0u);
  Weld weld = weld_by_position(mesh.positions);
  expect_same_edges(table, brute_force_edges(mesh, weld));
  EXPECT_GT(table.memory_bytes(), table.edges.size() * sizeof(MeshEdge));
}

TEST(EdgeTable, HandBuiltCounts) {
  Mesh single;
  single.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  single.triangles = {{0, 1, 2}};
  EdgeTable t = build_edge_table(single);
  EXPECT_EQ(t.edges.size(), 3u);
  EXPECT_EQ(t.border_edges, 3u);
  EXPECT_EQ(t.non_manifold_edges, 0u);

  Mesh pair = single;  // two triangles on edge (1,2)
  pair.positions.push_back({1, 1, 0});
  pair.triangles.push_back({1, 3, 2});
  t = build_edge_table(pair);
  EXPECT_EQ(t.edges.size(), 5u);
  EXPECT_EQ(t.border_edges, 4u);
  // Sorted by (v0, v1): (0,1) (0,2) (1,2) (1,3) (2,3).
  EXPECT_EQ(t.edges[2].v0, 1u);
  EXPECT_EQ(t.edges[2].v1, 2u);
  EXPECT_EQ(t.edges[2].face0, 0u);
  EXPECT_EQ(t.edges[2].face1, 1u);
  EXPECT_EQ(t.edges[2].face_count, 2u);

  Mesh fin = pair;  // a third triangle on (1,2): non-manifold
  fin.positions.push_back({0.5f, 0.5f, 1.0f});
  fin.triangles.push_back({2, 1, 4});
  t = build_edge_table(fin);
  EXPECT_EQ(t.non_manifold_edges, 1u);
  EXPECT_EQ(t.border_edges, 6u);

  // A closed tetrahedron given as a soup of 12 vertices: no borders once welded.
  const glm::vec3 v[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  const int faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  Mesh soup;
  for (const auto& f : faces) {
    for (int i : f) soup.positions.push_back(v[i]);
    const uint32_t base = uint32_t(soup.positions.size() - 3);
    soup.triangles.emplace_back(base, base + 1, base + 2);
  }
  t = build_edge_table(soup);
  EXPECT_EQ(t.weld.positions.size(), 4u);
  EXPECT_EQ(t.edges.size(), 6u);
  EXPECT_EQ(t.border_edges, 0u);
  for (const MeshEdge& e : t.edges) EXPECT_EQ(e.face_count, 2u);

  // Bowtie: two triangles sharing only a vertex.
  Mesh bowtie;
  bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  bowtie.triangles = {{0, 1, 2}, {0, 3, 4}};
  t = build_edge_table(bowtie);
  EXPECT_EQ(t.edges.size(), 6u);
  EXPECT_EQ(t.border_edges, 6u);
  EXPECT_EQ(t.non_manifold_edges, 0u);

  EXPECT_TRUE(build_edge_table(Mesh{}).edges.empty());
}

TEST(DropDegenerate, RepeatedIndicesAndZeroArea) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {0, 0, 0}, {1e-20f, 0, 0}};
  mesh.triangles = {
      {0, 1, 2},  // keep
      {0, 0, 2},  // repeated index
      {0, 1, 3},  // collinear
      {0, 4, 2},  // two indices, same point: zero area
      {1, 2, 5},  // tiny but non-zero area: keep
      {2, 1, 1},  // repeated
  };
  mesh.materials = {{0, 2, 7}, {2, 2, 8}, {4, 2, 9}};
  EXPECT_EQ(drop_degenerate_triangles(mesh), 4u);
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(mesh.triangles[1], glm::uvec3(1, 2, 5));
  // The middle range lost all its triangles and disappears; the others are renumbered.
  ASSERT_EQ(mesh.materials.size(), 2u);
  EXPECT_EQ(mesh.materials[0].first_triangle, 0u);
  EXPECT_EQ(mesh.materials[0].triangle_count, 1u);
  EXPECT_EQ(mesh.materials[0].material, 7u);
  EXPECT_EQ(mesh.materials[1].first_triangle, 1u);
  EXPECT_EQ(mesh.materials[1].triangle_count, 1u);
  EXPECT_EQ(mesh.materials[1].material, 9u);
  EXPECT_EQ(mesh.material_of(1), 9u);
}

TEST(DropDegenerate, MatchesAFilterOnRandomMeshes) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 40; ++trial) {
    Mesh mesh = random_mesh(rng, 4 + rng() % 30, 1 + rng() % 200, 1);
    // Random material ranges covering all triangles.
    for (uint32_t first = 0; first < mesh.triangles.size();) {
      const uint32_t count = std::min<uint32_t>(1 + rng() % 20, uint32_t(mesh.triangles.size()) - first);
      mesh.materials.push_back({first, count, uint32_t(mesh.materials.size())});
      first += count;
    }
    std::vector<std::pair<glm::uvec3, uint32_t>> expected;  // triangle, material
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      const glm::uvec3 tri = mesh.triangles[t];
      const glm::dvec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
      const bool repeated = tri.x == tri.y || tri.y == tri.z || tri.x == tri.z;
      if (!repeated && glm::length(glm::cross(b - a, c - a)) > 0.0) expected.push_back({tri, mesh.material_of(t)});
    }
    const uint32_t before = uint32_t(mesh.triangles.size());
    EXPECT_EQ(drop_degenerate_triangles(mesh), before - expected.size());
    ASSERT_EQ(mesh.triangles.size(), expected.size());
    uint32_t covered = 0;
    for (const MaterialRange& r : mesh.materials) {
      EXPECT_EQ(r.first_triangle, covered);
      EXPECT_GT(r.triangle_count, 0u);
      covered += r.triangle_count;
    }
    EXPECT_EQ(covered, expected.size());
    for (uint32_t t = 0; t < expected.size(); ++t) {
      EXPECT_EQ(mesh.triangles[t], expected[t].first);
      EXPECT_EQ(mesh.material_of(t), expected[t].second);
    }
  }
}

TEST(DropDegenerate, TrianglesOutsideRangesAreKept) {
  // Ranges should cover every triangle; if they do not, no good triangle may be lost anyway.
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 0, 1}, {0, 1, 2}, {1, 2, 0}};
  mesh.materials = {{0, 2, 4}};  // the last two triangles are in no range
  EXPECT_EQ(drop_degenerate_triangles(mesh), 1u);
  EXPECT_EQ(mesh.triangles.size(), 3u);
  ASSERT_EQ(mesh.materials.size(), 1u);
  EXPECT_EQ(mesh.materials[0].first_triangle, 0u);
  EXPECT_EQ(mesh.materials[0].triangle_count, 1u);
}

TEST(DropDegenerate, MeshWithoutMaterials) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 1}, {0, 1, 2}};
  EXPECT_EQ(drop_degenerate_triangles(mesh), 1u);
  EXPECT_EQ(mesh.triangles.size(), 1u);
  EXPECT_TRUE(mesh.materials.empty());
}

}  // namespace
}  // namespace epi

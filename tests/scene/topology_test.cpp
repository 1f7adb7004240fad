// Topology: the weld (tolerance, seams of exporters, surfaces that only touch), the edge table
// against a brute-force reference, counts on hand-built meshes, degenerate-triangle removal.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "scene/topology.h"
#include "test_meshes.h"

namespace epi {
namespace {

// Reference edge table from a std::map over welded sides, in triangle order; triangles with two
// corners welded together have none.
std::vector<MeshEdge> brute_force_edges(const Mesh& mesh, const Weld& weld) {
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> faces_of_edge;
  for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3 w(weld.remap[mesh.triangles[t].x], weld.remap[mesh.triangles[t].y], weld.remap[mesh.triangles[t].z]);
    if (w.x == w.y || w.y == w.z || w.x == w.z) continue;  // collapsed by the weld: no edges
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = w[i], b = w[(i + 1) % 3];
      faces_of_edge[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
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

Weld weld_of(const Mesh& mesh) { return weld_mesh(mesh.positions, mesh.triangles); }

// Ids dense, in order of each welded vertex's lowest copy, whose position it takes; the counts add up.
void expect_well_formed(const Mesh& mesh, const Weld& weld) {
  ASSERT_EQ(weld.remap.size(), mesh.positions.size());
  uint32_t next = 0, inexact = 0;
  std::vector<uint32_t> first_copy;
  for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
    if (weld.remap[v] == next) first_copy.push_back(v), ++next;
    ASSERT_LT(weld.remap[v], next) << v;
    const glm::vec3 p = mesh.positions[v], q = mesh.positions[first_copy[weld.remap[v]]];
    inexact += p != q;
    const glm::vec3 d = glm::abs(p - q);
    EXPECT_LE(std::max({d.x, d.y, d.z}), 4.0f * weld.tolerance) << v;  // a class is a few tolerances wide at most
  }
  EXPECT_EQ(weld.positions.size(), next);
  for (uint32_t w = 0; w < next; ++w) EXPECT_EQ(weld.positions[w], mesh.positions[first_copy[w]]);
  EXPECT_EQ(weld.merged, mesh.positions.size() - next);
  EXPECT_EQ(weld.merged_inexact, inexact);
}

// Random meshes over a small pool of positions (exact copies, -0 and +0 among them): where exactly
// two triangle sides join the same two positions, their copies weld; copies weld only at one position.
TEST(Weld, StitchesSidesThatPairUpOnRandomMeshes) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 60; ++trial) {
    const Mesh mesh = random_mesh(rng, 3 + rng() % 300, 1 + rng() % 200, 1 + trial % 6);
    const Weld weld = weld_of(mesh);
    expect_well_formed(mesh, weld);
    std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, std::vector<std::pair<uint32_t, uint32_t>>> sides;
    auto key = [](const glm::vec3& p) { return std::array<float, 3>{p.x + 0.0f, p.y + 0.0f, p.z + 0.0f}; };  // -0 -> +0
    for (const glm::uvec3& t : mesh.triangles) {
      const auto p0 = key(mesh.positions[t.x]), p1 = key(mesh.positions[t.y]), p2 = key(mesh.positions[t.z]);
      if (p0 == p1 || p1 == p2 || p0 == p2) continue;  // collapsed: no sides
      for (int i = 0; i < 3; ++i) {
        uint32_t a = t[i], b = t[(i + 1) % 3];
        if (key(mesh.positions[b]) < key(mesh.positions[a])) std::swap(a, b);
        sides[{key(mesh.positions[a]), key(mesh.positions[b])}].emplace_back(a, b);
      }
    }
    for (const auto& [ends, list] : sides)
      if (list.size() == 2) {
        ASSERT_EQ(weld.remap[list[0].first], weld.remap[list[1].first]) << "trial " << trial;
        ASSERT_EQ(weld.remap[list[0].second], weld.remap[list[1].second]) << "trial " << trial;
      }
    for (uint32_t v = 0; v < mesh.positions.size(); ++v)
      ASSERT_EQ(key(mesh.positions[v]), key(weld.positions[weld.remap[v]])) << "trial " << trial;
  }
}

TEST(Weld, ToleranceIsRelativeToTheExtent) {
  const std::vector<glm::vec3> unit = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_FLOAT_EQ(weld_tolerance(unit), 1e-5f * std::sqrt(3.0f));
  const std::vector<glm::vec3> far = {{1000, 0, 0}, {1000.001f, 0, 0}};  // float spacing at 1000 is 6e-5
  EXPECT_FLOAT_EQ(weld_tolerance(far), 8.0f * std::numeric_limits<float>::epsilon() * 1000.001f);
  EXPECT_EQ(weld_tolerance({}), 0.0f);
  // Copies within the tolerance weld; twice as far apart, they do not.
  for (const float scale : {1e-3f, 1.0f, 1e4f}) {
    Mesh pair;  // two triangles on the edge (1,2), its copies (3,4) moved by `offset`
    const float tolerance = scale * 1e-5f * std::sqrt(2.0f);
    for (const float offset : {0.9f * tolerance, 2.0f * tolerance}) {
      pair.positions = {{0, 0, 0}, {scale, 0, 0}, {0, scale, 0}, {scale + offset, -offset, 0}, {-offset, scale, 0},
                        {scale, scale, 0}};
      pair.triangles = {{0, 1, 2}, {3, 5, 4}};
      const Weld weld = weld_of(pair);
      ASSERT_NEAR(weld.tolerance, tolerance, 1e-3f * tolerance);
      const bool welded = offset < tolerance;
      EXPECT_EQ(weld.remap[3] == weld.remap[1] && weld.remap[4] == weld.remap[2], welded) << scale << " " << offset;
      EXPECT_EQ(weld.merged_inexact, welded ? 2u : 0u);
      EXPECT_EQ(build_edge_table(pair).border_edges, welded ? 4u : 6u);
    }
  }
}

TEST(Weld, SignedZerosWeld) {
  Mesh pair;
  pair.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, -0.0f, -0.0f}, {-0.0f, 1, 0}, {1, 1, 0}};
  pair.triangles = {{0, 1, 2}, {3, 5, 4}};
  const Weld weld = weld_of(pair);
  EXPECT_EQ(weld.remap, (std::vector<uint32_t>{0, 1, 2, 1, 2, 3}));
  EXPECT_EQ(weld.merged_inexact, 0u);
}

TEST(Weld, AllDistinctIsIdentity) {
  Mesh mesh;
  for (int i = 0; i < 10000; ++i) mesh.positions.emplace_back(float(i), float(i % 7), -float(i % 13));
  for (uint32_t i = 0; i + 2 < 10000; i += 3) mesh.triangles.emplace_back(i, i + 1, i + 2);
  const Weld weld = weld_of(mesh);
  for (uint32_t i = 0; i < mesh.positions.size(); ++i) ASSERT_EQ(weld.remap[i], i);
  EXPECT_EQ(weld.merged, 0u);
  EXPECT_TRUE(weld_mesh({}, {}).positions.empty());
}

// The torus of issue 9: seam copies from cos/sin of 0 and 2 pi, not bit-identical. An exact weld
// left 2 (48 + 24) = 144 border edges; with the tolerance, none. Also far from the origin, tiny and huge.
TEST(Weld, ExporterTorusIsClosed) {
  const int rings = 48, segments = 24;
  struct Case {
    float scale;
    glm::vec3 centre;
  };
  for (const Case& c : {Case{1.0f, {0, 0, 0}}, Case{1e-3f, {0, 0, 0}}, Case{1e3f, {0, 0, 0}}, Case{1.0f, {300, -200, 50}}}) {
    Mesh mesh = edges::test::exporter_torus(rings, segments, c.scale, 0.35f * c.scale, c.centre);
    // Far from the origin the 1e-16 differences round away: there the last row is 2 ulps off, as
    // an exporter's float arithmetic leaves it.
    if (c.centre != glm::vec3(0.0f))
      for (int s = 0; s <= segments; ++s)
        for (int step = 0; step < 2; ++step) {
          glm::vec3& p = mesh.positions[rings * (segments + 1) + s];
          p = {std::nextafter(p.x, 1e9f), std::nextafter(p.y, 1e9f), std::nextafter(p.z, -1e9f)};
        }
    // The copies really differ (else this tests nothing): the first and last rows are not bit-identical.
    int differing = 0;
    for (int s = 0; s <= segments; ++s) differing += mesh.positions[s] != mesh.positions[rings * (segments + 1) + s];
    ASSERT_GT(differing, 0);
    const EdgeTable table = build_edge_table(mesh);
    expect_well_formed(mesh, table.weld);
    EXPECT_EQ(table.border_edges, 0u) << c.scale;
    EXPECT_EQ(table.non_manifold_edges, 0u);
    EXPECT_EQ(table.weld.positions.size(), size_t(rings * segments));
    EXPECT_EQ(table.weld.merged, uint32_t(rings + segments + 1));
    EXPECT_GT(table.weld.merged_inexact, 0u);
    EXPECT_EQ(table.edges.size(), size_t(3 * rings * segments));
  }
}

// A closed mesh exploded into a triangle soup, each copy moved on its own: by a few float ulps
// (an exporter writing each face's corners separately), or by up to 0.45 tolerances per
// coordinate (so some copies of a vertex fall into different grid cells of the weld's search).
// The weld rebuilds the original indexing exactly.
TEST(Weld, SoupWithRoundingRebuildsTheMesh) {
  std::mt19937 rng(3);
  const Mesh indexed = edges::test::torus(40, 20);
  const float tolerance = weld_tolerance(indexed.positions);
  for (const bool by_tolerance : {false, true}) {
    std::uniform_real_distribution<float> offset(-0.45f * tolerance, 0.45f * tolerance);
    Mesh soup;
    std::vector<uint32_t> original;
    for (const glm::uvec3& t : indexed.triangles) {
      for (int k = 0; k < 3; ++k) {
        glm::vec3 p = indexed.positions[t[k]];
        for (int axis = 0; axis < 3; ++axis) {
          if (by_tolerance) {
            p[axis] += offset(rng);
            continue;
          }
          for (int step = int(rng() % 7) - 3; step != 0; step += step > 0 ? -1 : 1)
            p[axis] = std::nextafter(p[axis], step > 0 ? 10.0f : -10.0f);
        }
        soup.positions.push_back(p);
        original.push_back(t[k]);
      }
      const uint32_t base = uint32_t(soup.positions.size() - 3);
      soup.triangles.emplace_back(base, base + 1, base + 2);
    }
    const EdgeTable table = build_edge_table(soup);
    ASSERT_NEAR(table.weld.tolerance, tolerance, 1e-3f * tolerance);
    expect_well_formed(soup, table.weld);
    // A bijection between original and welded vertices.
    EXPECT_EQ(table.weld.positions.size(), indexed.positions.size()) << by_tolerance;
    std::vector<uint32_t> welded_of(indexed.positions.size(), kNone);
    for (size_t a = 0; a < soup.positions.size(); ++a) {
      if (welded_of[original[a]] == kNone) welded_of[original[a]] = table.weld.remap[a];
      ASSERT_EQ(table.weld.remap[a], welded_of[original[a]]) << a << " " << by_tolerance;
    }
    std::sort(welded_of.begin(), welded_of.end());
    EXPECT_EQ(std::unique(welded_of.begin(), welded_of.end()), welded_of.end());
    EXPECT_EQ(table.border_edges, 0u);
    EXPECT_EQ(table.non_manifold_edges, 0u);
  }
}

// A UV sphere whose south pole copies come from sin(pi) != 0: they weld, the pole's sliver
// triangles collapse, and the sphere is closed.
TEST(Weld, SpherePoleCopiesWeld) {
  const int rings = 16, segments = 32;
  Mesh sphere;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
      sphere.positions.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    }
  auto id = [&](int r, int s) { return uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      sphere.triangles.emplace_back(id(r, s), id(r, s + 1), id(r + 1, s));
      sphere.triangles.emplace_back(id(r, s + 1), id(r + 1, s + 1), id(r + 1, s));
    }
  const EdgeTable table = build_edge_table(sphere);
  EXPECT_EQ(table.border_edges, 0u);
  EXPECT_EQ(table.non_manifold_edges, 0u);
  EXPECT_EQ(table.weld.positions.size(), size_t((rings - 1) * segments + 2));
}

// Surfaces that are close but apart keep apart: two parallel sheets 7 and 70 tolerances apart.
TEST(Weld, SheetsASmallDistanceApartStayApart) {
  for (const float gap : {1e-4f, 1e-3f}) {
    Mesh sheets;
    for (const float y : {0.0f, gap}) {
      const uint32_t base = uint32_t(sheets.positions.size());
      sheets.positions.insert(sheets.positions.end(), {{0, y, 0}, {1, y, 0}, {1, y, 1}, {0, y, 1}});
      sheets.triangles.emplace_back(base, base + 2, base + 1);
      sheets.triangles.emplace_back(base, base + 3, base + 2);
    }
    const EdgeTable table = build_edge_table(sheets);
    EXPECT_EQ(table.weld.positions.size(), 8u) << gap;
    EXPECT_EQ(table.border_edges, 8u);
  }
}

// Closed boxes (each written with 4 vertices per face) touching along a face, an edge or a corner:
// the coincident copies sit on different surfaces. Each box stays closed and apart from the other;
// an exact weld made their shared edges non-manifold.
TEST(Weld, TouchingBoxesStayClosedAndApart) {
  struct Case {
    const char* name;
    glm::vec3 offset;  // of the second unit box
  };
  for (const Case& c : {Case{"face +y", {0, 1, 0}}, Case{"face -y", {0, -1, 0}}, Case{"face +x", {1, 0, 0}},
                        Case{"face -z", {0, 0, -1}}, Case{"edge", {1, 1, 0}}, Case{"edge -x +z", {-1, 0, 1}},
                        Case{"corner", {1, 1, 1}}}) {
    Mesh boxes = edges::test::box({0, 0, 0}, {1, 1, 1});
    const Mesh second = edges::test::box(c.offset, c.offset + glm::vec3(1));
    const uint32_t base = uint32_t(boxes.positions.size());
    boxes.positions.insert(boxes.positions.end(), second.positions.begin(), second.positions.end());
    for (const glm::uvec3& t : second.triangles) boxes.triangles.push_back(t + base);
    const EdgeTable table = build_edge_table(boxes);
    EXPECT_EQ(table.weld.positions.size(), 16u) << c.name;
    EXPECT_EQ(table.border_edges, 0u) << c.name;
    EXPECT_EQ(table.non_manifold_edges, 0u) << c.name;
    for (uint32_t v = 0; v < base; ++v)
      for (uint32_t u = base; u < boxes.positions.size(); ++u) ASSERT_NE(table.weld.remap[v], table.weld.remap[u]) << c.name;
    // The same with each box written with 8 shared corners.
    Mesh indexed;
    for (const glm::vec3& lo : {glm::vec3(0.0f), c.offset}) {
      const uint32_t first = uint32_t(indexed.positions.size());
      for (int k = 0; k < 8; ++k) indexed.positions.push_back(lo + glm::vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
      const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {1, 3, 7, 5}, {0, 4, 6, 2}};
      for (const auto& q : quads) {
        indexed.triangles.emplace_back(first + q[0], first + q[1], first + q[2]);
        indexed.triangles.emplace_back(first + q[0], first + q[2], first + q[3]);
      }
    }
    const EdgeTable indexed_table = build_edge_table(indexed);
    EXPECT_EQ(indexed_table.weld.merged, 0u) << c.name;
    EXPECT_EQ(indexed_table.border_edges, 0u) << c.name;
    EXPECT_EQ(indexed_table.non_manifold_edges, 0u) << c.name;
  }
}

// Three faces on one edge, each with its own copies (a fin): no manifold pairing exists, so all
// copies weld as an exact weld would and the edge is non-manifold.
TEST(Weld, UnpairableEdgeWeldsAllCopies) {
  Mesh fin;
  const glm::vec3 a(0, 0, 0), b(0, 0, 1);
  for (const glm::vec3& wing : {glm::vec3(1, 0, 0), glm::vec3(-1, 0.2f, 0), glm::vec3(0, -1, 0.5f)}) {
    const uint32_t base = uint32_t(fin.positions.size());
    fin.positions.insert(fin.positions.end(), {a, b, wing});
    fin.triangles.emplace_back(base, base + 1, base + 2);
  }
  const EdgeTable table = build_edge_table(fin);
  EXPECT_EQ(table.weld.positions.size(), 5u);
  EXPECT_EQ(table.non_manifold_edges, 1u);
  EXPECT_EQ(table.border_edges, 6u);
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
    const Weld weld = weld_of(mesh);
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
  expect_same_edges(table, brute_force_edges(mesh, weld_of(mesh)));
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

// Edge data, the brute-force finder and the interval edge tree: the tree must return exactly the
// brute-force set for every viewpoint, on smooth, sharp and deliberately hard meshes.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <set>

#include <tbb/global_control.h>

#include "edges/edge_tree.h"
#include "test_meshes.h"

namespace epi::edges {
namespace {

using namespace test;

std::vector<uint32_t> scalar_silhouettes(const EdgeMesh& m, const Viewpoint& v) {
  std::vector<uint32_t> out;
  for (uint32_t e = 0; e < m.edge_count(); ++e)
    if (is_silhouette(m, e, v)) out.push_back(e);
  return out;
}

TEST(EdgeMesh, BoxWeldsSeamsAndFlagsSharpEdges) {
  const EdgeMesh m = build_edge_mesh(box({-1, -1, -1}, {1, 1, 1}));
  EXPECT_EQ(m.positions.size(), 8u);
  EXPECT_EQ(m.edge_count(), 18u);  // 12 box edges + 6 diagonals
  int sharp = 0;
  for (uint8_t f : m.flags) {
    sharp += (f & kSharp) != 0;
    EXPECT_FALSE(f & kBorder);
  }
  EXPECT_EQ(sharp, 12);
}

// The torus of issue 9, written as exporters write it (seam copies from cos/sin of 0 and 2 pi):
// the edge finder sees one closed smooth surface, so the seam is no border and no feature edge;
// seen from outside, its silhouettes are the only edges.
TEST(EdgeMesh, ExporterTorusSeamIsNoEdge) {
  const EdgeMesh m = build_edge_mesh(exporter_torus(48, 24));
  EXPECT_EQ(m.positions.size(), size_t(48 * 24));
  EXPECT_TRUE(m.border_edges.empty());
  EXPECT_TRUE(m.non_manifold.empty());
  EXPECT_TRUE(m.feature_edges.empty());
  EXPECT_EQ(m.edge_count(), size_t(3 * 48 * 24));
  for (uint8_t f : m.flags) EXPECT_EQ(f, 0);
}

TEST(EdgeMesh, SharpCutoffIsPerMesh) {
  Mesh mesh = box({-1, -1, -1}, {1, 1, 1});
  mesh.sharp_angle_degrees = 95.0f;  // the box's 90 degree edges are now smooth
  EXPECT_TRUE(build_edge_mesh(mesh).feature_edges.empty());
  mesh.sharp_angle_degrees = 89.0f;
  EXPECT_EQ(build_edge_mesh(mesh).feature_edges.size(), 12u);
}

TEST(EdgeMesh, BordersAndNonManifold) {
  const EdgeMesh grid_mesh = build_edge_mesh(grid(3));
  int border = 0;
  for (uint8_t f : grid_mesh.flags) border += (f & kBorder) != 0;
  EXPECT_EQ(border, 12);
  const EdgeMesh hard = build_edge_mesh(hard_mesh());
  int non_manifold = 0;
  for (uint32_t e = 0; e < hard.edge_count(); ++e)
    if (hard.flags[e] & kNonManifold) {
      ++non_manifold;
      EXPECT_TRUE(hard.flags[e] & kSharp);
      EXPECT_EQ(std::min(hard.v0[e], hard.v1[e]), 0u);
    }
  EXPECT_EQ(non_manifold, 1);
}

TEST(BruteForce, MatchesScalarReference) {
  const EdgeMesh m = build_edge_mesh(bumpy_sphere(40, 80, 0.1f, 3));
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-3, 3);
  std::vector<uint8_t> facing;
  std::vector<uint32_t> fast;
  for (int i = 0; i < 200; ++i) {
    const Viewpoint v{u(rng), u(rng), u(rng), i % 10 == 0 ? 0.0f : 1.0f};
    brute_force_silhouettes(m, v, facing, fast);
    ASSERT_EQ(fast, scalar_silhouettes(m, v));
  }
}

// On a closed mesh the silhouette is a set of closed loops: every vertex touches an even number
// of silhouette edges.
TEST(BruteForce, SilhouettesOfClosedMeshesFormLoops) {
  for (const Mesh& mesh : {uv_sphere(30, 60), torus(48, 24), bumpy_sphere(30, 60, 0.2f, 9)}) {
    const EdgeMesh m = build_edge_mesh(mesh);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-4, 4);
    std::vector<uint8_t> facing;
    std::vector<uint32_t> sil;
    for (int i = 0; i < 50; ++i) {
      brute_force_silhouettes(m, {u(rng), u(rng), u(rng), 1.0f}, facing, sil);
      std::vector<int> degree(m.positions.size(), 0);
      for (uint32_t e : sil) ++degree[m.v0[e]], ++degree[m.v1[e]];
      for (int d : degree) ASSERT_EQ(d % 2, 0) << mesh.name;
    }
  }
}

TEST(BruteForce, SphereSilhouetteFromFarAwayIsTheEquator) {
  const Mesh mesh = uv_sphere(64, 128);
  const EdgeMesh m = build_edge_mesh(mesh);
  std::vector<uint8_t> facing;
  std::vector<uint32_t> sil;
  brute_force_silhouettes(m, m.local_direction({0, 1, 0}), facing, sil);
  ASSERT_FALSE(sil.empty());
  for (uint32_t e : sil) EXPECT_LT(std::fabs(m.positions[m.v0[e]].y) + std::fabs(m.positions[m.v1[e]].y), 0.06f);
}

// Viewpoints that stress the test: random, far away, at infinity, inside, at a vertex, in a
// face's plane, on an edge.
std::vector<Viewpoint> hard_viewpoints(const EdgeMesh& m, uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<uint32_t> face(0, uint32_t(m.face_count() - 1));
  double scale = 0;
  for (const glm::vec3& p : m.positions) scale = std::max(scale, glm::length(glm::dvec3(p) - m.origin));
  std::vector<Viewpoint> out;
  for (int i = 0; i < count; ++i) {
    const glm::uvec3 f = m.faces[face(rng)];
    const glm::dvec3 a = m.positions[f.x], b = m.positions[f.y], c = m.positions[f.z];
    const glm::dvec3 random_dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + 1e-9);
    switch (i % 8) {
      case 0: out.push_back(m.local_point(m.origin + random_dir * scale * (1.5 + 3 * std::fabs(u(rng))))); break;
      case 1: out.push_back(m.local_point(m.origin + random_dir * scale * 1e6)); break;
      case 2: out.push_back(EdgeMesh::local_direction(random_dir)); break;
      case 3: out.push_back(m.local_point(m.origin + random_dir * scale * 0.3 * std::fabs(u(rng)))); break;
      case 4: out.push_back(m.local_point(a)); break;
      case 5: out.push_back(m.local_point(a + (b - a) * (1 + 4 * u(rng)) + (c - a) * (3 * u(rng)))); break;  // face plane
      case 6: out.push_back(m.local_point(a + (b - a) * (0.5 + 0.5 * u(rng)))); break;  // on an edge
      default: out.push_back(m.local_point(a + (b - a) * 1e-3 * u(rng) + (c - a) * 1e-3 * u(rng))); break;
    }
  }
  return out;
}

std::vector<Mesh> hard_meshes() {
  std::vector<Mesh> meshes = {uv_sphere(40, 80), torus(60, 30), box({-1, -2, -3}, {1, 2, 3}), grid(20),
                              bumpy_sphere(50, 100, 0.15f, 7), hard_mesh(), random_soup(300, 1500, 5)};
  meshes.push_back(transformed(uv_sphere(40, 80), 1e-4f, {1e-4f, 0, 0}, " tiny"));
  meshes.push_back(transformed(torus(60, 30), 1e5f, {3e5f, -1e5f, 2e5f}, " huge"));
  meshes.push_back(transformed(bumpy_sphere(30, 60, 0.3f, 11), 1.0f, {1e5f, 1e5f, 0}, " far from origin"));
  Mesh slivers = uv_sphere(400, 8);  // long thin triangles
  slivers.name = "slivers";
  meshes.push_back(slivers);
  return meshes;
}

TEST(EdgeTree, EqualsBruteForceOnHardMeshesAndViewpoints) {
  for (const Mesh& mesh : hard_meshes()) {
    const EdgeMesh m = build_edge_mesh(mesh);
    for (uint32_t leaf_size : {1u, 8u}) {
      EdgeTreeSettings settings;
      settings.leaf_size = leaf_size;
      settings.parallel_threshold = 512;
      const EdgeTree tree(m, settings);
      std::vector<uint8_t> facing;
      std::vector<uint32_t> expected, got;
      for (const Viewpoint& v : hard_viewpoints(m, 17 + leaf_size, 400)) {
        brute_force_silhouettes(m, v, facing, expected);
        tree.silhouettes(m, v, got);
        ASSERT_EQ(got, expected) << mesh.name << " viewpoint " << v.x << "," << v.y << "," << v.z << "," << v.w;
      }
    }
  }
}

TEST(EdgeTree, EveryEdgeStoredOnce) {
  const EdgeMesh m = build_edge_mesh(bumpy_sphere(50, 100, 0.2f, 4));
  const EdgeTree tree(m);
  std::vector<uint32_t> stored;
  for (const EdgeTreeNode& node : tree.nodes())
    for (uint32_t i = node.first; i < node.first + node.count; ++i) stored.push_back(tree.order()[i]);
  std::sort(stored.begin(), stored.end());
  EXPECT_EQ(std::adjacent_find(stored.begin(), stored.end()), stored.end());
  EXPECT_EQ(stored.size(), m.edge_count());  // closed mesh: every edge has two faces
}

TEST(EdgeTree, SameTreeWhateverTheThreadCount) {
  const EdgeMesh m = build_edge_mesh(bumpy_sphere(120, 240, 0.05f, 8));
  EdgeTreeSettings settings;
  settings.parallel_threshold = 1000;
  auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return EdgeTree(m, settings);
  };
  const EdgeTree one = build(1), two = build(2);
  ASSERT_EQ(one.order(), two.order());
  ASSERT_EQ(one.nodes().size(), two.nodes().size());
  for (size_t i = 0; i < one.nodes().size(); ++i)
    ASSERT_EQ(std::memcmp(&one.nodes()[i], &two.nodes()[i], sizeof(EdgeTreeNode)), 0) << i;
}

TEST(EdgeTree, PrunesMostOfASmoothMesh) {
  const EdgeMesh m = build_edge_mesh(uv_sphere(200, 400));
  const EdgeTree tree(m);
  size_t visited = 0;
  tree.candidates(m, ViewBox::point(m.local_point({0.3, 4, 2})), [&](uint32_t) { ++visited; });
  EXPECT_LT(visited, m.edge_count() / 20) << visited << " of " << m.edge_count();
}

TEST(EdgeTree, BoxQueryKeepsEverySilhouetteFromInsideTheBox) {
  // The interval query with a box of viewpoints (area lights) must keep every edge that is a
  // silhouette from any point of the box: sample points, corners included.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  for (const Mesh& mesh : {torus(60, 30), bumpy_sphere(40, 80, 0.1f, 5), hard_mesh()}) {
    const EdgeMesh m = build_edge_mesh(mesh);
    const EdgeTree tree(m);
    for (int trial = 0; trial < 20; ++trial) {
      const glm::dvec3 lo(4 * u(rng) - 2, 2 + 2 * u(rng), 4 * u(rng) - 2);
      const glm::dvec3 hi = lo + glm::dvec3(u(rng), 0.5 * u(rng), u(rng)) * (trial % 2 ? 0.1 : 1.5);
      const Viewpoint a = m.local_point(lo), b = m.local_point(hi);
      const ViewBox box{{a.x, b.x}, {a.y, b.y}, {a.z, b.z}, 1.0};
      std::vector<uint8_t> kept(m.edge_count(), 0);
      tree.candidates(m, box, [&](uint32_t e) { kept[e] = 1; });
      std::vector<uint8_t> facing;
      std::vector<uint32_t> sil;
      for (int k = 0; k < 40; ++k) {
        glm::dvec3 p;
        for (int c = 0; c < 3; ++c) p[c] = k < 8 ? ((k >> c) & 1 ? hi[c] : lo[c]) : lo[c] + (hi[c] - lo[c]) * u(rng);
        brute_force_silhouettes(m, m.local_point(p), facing, sil);
        for (uint32_t e : sil) ASSERT_TRUE(kept[e]) << mesh.name << " edge " << e;
      }
    }
  }
}

TEST(EdgeTree, SharpEdgesAreKeptHigh) {
  // Edges stored at an inner node are those whose normals span more than half of its range: on a
  // box with single-edge leaves, the sharp edges stop above the leaves.
  const EdgeMesh m = build_edge_mesh(box({-1, -1, -1}, {1, 1, 1}));
  EdgeTreeSettings settings;
  settings.leaf_size = 1;
  const EdgeTree tree(m, settings);
  int kept_inner = 0;
  for (const EdgeTreeNode& node : tree.nodes()) {
    if (node.left == kNone) continue;
    for (uint32_t i = node.first; i < node.first + node.count; ++i) {
      const uint32_t e = tree.order()[i];
      EXPECT_TRUE(m.flags[e] & kSharp);
      bool spans = false;
      const float n0[3] = {m.nx[m.face0[e]], m.ny[m.face0[e]], m.nz[m.face0[e]]};
      const float n1[3] = {m.nx[m.face1[e]], m.ny[m.face1[e]], m.nz[m.face1[e]]};
      for (int a = 0; a < 3; ++a) spans |= std::fabs(n0[a] - n1[a]) > 0.5f * (node.n_hi[a] - node.n_lo[a]);
      EXPECT_TRUE(spans);
      ++kept_inner;
    }
  }
  EXPECT_GE(kept_inner, 6);
}

}  // namespace
}  // namespace epi::edges

// The edge finder on the bundled scenes: tree and brute force agree for every mesh from many
// viewpoints, the scene-level edges are what their kinds say, and the per-object choice rule.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "edges/scene_edges.h"
#include "load_scene.h"
#include "test_meshes.h"

namespace epi::edges {
namespace {

const char* kScenes[] = {"cornell_box", "torus_capsule", "chains", "rooms", "grid_dragon"};

class BundledScene : public ::testing::TestWithParam<const char*> {};

TEST_P(BundledScene, TreeEqualsBruteForceAndEdgesAreWhatTheySay) {
  const std::filesystem::path file = std::filesystem::path(EPI_SOURCE_DIR) / "scenes" / (std::string(GetParam()) + ".gltf");
  ASSERT_TRUE(std::filesystem::exists(file)) << file;
  const Scene scene = load_scene(file);
  const SceneEdgeFinder finder(scene);
  const Bounds world = scene.world_bounds();
  const glm::dvec3 centre = (glm::dvec3(world.min) + glm::dvec3(world.max)) * 0.5;
  const double size = glm::length(glm::dvec3(world.max) - glm::dvec3(world.min));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);

  // Viewpoints inside and around the scene, at infinity, and at mesh vertices.
  for (uint32_t i = 0; i < scene.meshes.size(); ++i) {
    const EdgeMesh& m = finder.edge_mesh(i);
    const EdgeTree& tree = finder.edge_tree(i);
    const int count = m.face_count() > 100000 ? 40 : 150;
    std::vector<uint8_t> facing;
    std::vector<uint32_t> expected, got;
    for (int k = 0; k < count; ++k) {
      Viewpoint v;
      if (k % 5 == 3) v = EdgeMesh::local_direction({u(rng), u(rng), u(rng)});
      else if (k % 5 == 4) v = m.local_point(m.positions[std::uniform_int_distribution<size_t>(0, m.positions.size() - 1)(rng)]);
      else v = m.local_point(centre + glm::dvec3(u(rng), u(rng), u(rng)) * size * (k % 5 == 0 ? 0.5 : 2.0));
      brute_force_silhouettes(m, v, facing, expected);
      tree.silhouettes(m, v, got);
      ASSERT_EQ(got, expected) << GetParam() << " mesh " << scene.meshes[i].name << " view " << k;
    }
  }

  // Scene edges from the default camera: kinds hold in each object's frame.
  const glm::dvec3 eye(scene.cameras.empty() ? glm::vec3(0, 0, 5) : scene.cameras[0].eye);
  std::vector<SceneEdge> edges;
  finder.view_edges(scene, eye, edges);
  EXPECT_FALSE(edges.empty());
  for (const SceneEdge& e : edges) {
    ASSERT_LT(e.object, scene.objects.size());
    EXPECT_TRUE(e.kind == EdgeKind::silhouette || e.kind == EdgeKind::sharp || e.kind == EdgeKind::border);
    EXPECT_GT(glm::length(e.b - e.a), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, BundledScene, ::testing::ValuesIn(kScenes));

TEST(ChoiceRule, LargeSmoothMeshesUseTheTreeSmallOnesBruteForce) {
  Scene scene;
  scene.meshes = {test::uv_sphere(8, 16), test::uv_sphere(220, 440), test::bumpy_sphere(220, 440, 0.05f, 2)};
  for (uint32_t i = 0; i < 3; ++i) scene.objects.push_back({"o" + std::to_string(i), i, glm::mat4(1.0f)});
  const SceneEdgeFinder finder(scene);
  EXPECT_FALSE(finder.choice(0).tree);
  EXPECT_TRUE(finder.choice(1).tree);
  EXPECT_FALSE(finder.choice(2).tree);  // a noisy mesh: silhouettes everywhere, the tree only adds work
  SceneEdgeSettings forced;
  forced.force = 1;
  EXPECT_TRUE(SceneEdgeFinder(scene, forced).choice(0).tree);
}

TEST(Triples, BlockerIsItsOwnReceiverAndFarObjectsAreLeftOut) {
  Scene scene;
  scene.meshes = {test::uv_sphere(8, 16, 0.5f)};
  auto at = [](glm::vec3 p) {
    glm::mat4 m(1.0f);
    m[3] = glm::vec4(p, 1.0f);
    return m;
  };
  scene.objects = {{"blocker", 0, at({0, 2, 0})}, {"below", 0, at({0, 0, 0})}, {"aside", 0, at({5, 0, 0})}};
  PunctualLight light;
  light.position = {0, 5, 0};
  scene.punctual_lights.push_back(light);
  const SceneEdgeFinder finder(scene);
  const auto triples = finder.find_triples(scene);
  auto has = [&](uint32_t b, uint32_t r) {
    return std::find(triples.begin(), triples.end(), LightBlockerReceiver{0, b, r}) != triples.end();
  };
  EXPECT_TRUE(has(0, 0));
  EXPECT_TRUE(has(0, 1));
  EXPECT_FALSE(has(0, 2));
  EXPECT_FALSE(has(1, 2));
}

}  // namespace
}  // namespace epi::edges

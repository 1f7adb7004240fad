// Model only what a scene requires (issue 15; docs/reliability.md, "Model only what a scene
// requires"): each structure that `epi info` reports memory for, or that the frame loop builds, is
// absent when the scene or the settings do not need it, and present when they do (the positive
// control, so that a test cannot pass by never building anything).
#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "edges/scene_edges.h"
#include "area_lights.h"
#include "gltf_builder.h"
#include "load_scene.h"
#include "render/renderer.h"
#include "test_scenes.h"

namespace epi {
namespace {

using test::GltfBuilder;
using test::json;
using test::TempDir;

size_t item_bytes(const std::vector<MemoryItem>& items, const std::string& name, bool* present = nullptr) {
  for (const MemoryItem& item : items)
    if (item.name == name) {
      if (present) *present = true;
      return item.bytes;
    }
  if (present) *present = false;
  return 0;
}

// A cube and a ground quad as glTF; the cube emissive or not, with or without a subdivision request.
Scene load_cube_scene(const TempDir& dir, bool emissive, const json& subdivision = nullptr, int level_override = -1) {
  GltfBuilder b;
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  test::unit_cube(positions, indices);
  json material = {{"name", "cube"}};
  if (emissive) material["emissiveFactor"] = {1.0, 1.0, 1.0};
  json mesh = {{"name", "cube"}, {"primitives", json::array({b.make_primitive(positions, indices, b.add_material(material))})}};
  if (!subdivision.is_null()) mesh["extras"]["epi"]["subdivision"] = subdivision;
  b.doc["meshes"].push_back(mesh);
  b.add_mesh("ground", test::unit_quad_positions(), test::unit_quad_indices(), b.add_material({{"name", "ground"}}));
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 10.0}}};
  b.set_scene({b.add_node({{"mesh", 0}, {"translation", {0.0, 0.0, 1.0}}}),
               b.add_node({{"mesh", 1}, {"scale", {10.0, 10.0, 1.0}}}),
               b.add_node({{"translation", {2.0, 2.0, 4.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}})});
  LoadOptions options;
  options.subdiv_level_override = level_override;
  return load_scene(b.write_gltf(dir / "cube.gltf"), options);
}

TEST(ModelOnly, NoAreaLightsWithoutEmissiveMeshes) {
  TempDir dir;
  const Scene plain = load_cube_scene(dir, false);
  EXPECT_TRUE(plain.area_lights.empty());
  bool present = true;
  item_bytes(plain.memory(), "area lights", &present);
  EXPECT_FALSE(present) << "epi info would list area lights";
  {
    const RayScene rs(plain);
    EXPECT_TRUE(rs.area_lights().empty());
    EXPECT_TRUE(rs.area_light_cdf().empty());
    EXPECT_EQ(item_bytes(rs.memory(), "area lights (placed copy)"), 0u);
    const edges::SceneEdgeFinder finder(plain);
    EXPECT_EQ(finder.lights().size(), 1u);  // the point light only
  }
  // The positive control: an emissive cube is an area light, with its triangles and CDF.
  const Scene lit = load_cube_scene(dir, true);
  ASSERT_EQ(lit.area_lights.size(), 1u);
  EXPECT_GT(item_bytes(lit.memory(), "area lights", &present), 0u);
  EXPECT_TRUE(present);
  const RayScene rs(lit);
  EXPECT_GT(item_bytes(rs.memory(), "area lights (placed copy)"), 0u);
  EXPECT_EQ(edges::SceneEdgeFinder(lit).lights().size(), 2u);
}

// The frame loop computes area-light events (the umbral and penumbral edges' shadow events) only
// when soft-shadow edges are asked for; with them off (the default) an area-lit scene computes no
// (light, blocker) pair at all, and with no emissive mesh there is nothing to compute either way.
TEST(ModelOnly, NoAreaLightEventsUnlessSoftShadowEdgesAreOn) {
  auto pairs = [](bool soft, bool emissive) {
    Scene scene = test::plane_and_box();
    scene.punctual_lights.clear();
    if (emissive) {
      const uint32_t m = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(8.0f));
      test::add_object(scene, test::quad_mesh({-1, -1, 4}, {0, 2, 0}, {2, 0, 0}, m), "lamp");
      scene.area_lights = build_area_lights(scene);  // with outlines, as the loader builds them
    } else {
      scene.punctual_lights.push_back(test::point_light({2.0f, -3.0f, 6.0f}, glm::vec3(40.0f)));
    }
    RayScene rs(scene);
    ShaderSettings shading;
    shading.area_light_samples = 2;
    Shader shader(rs, shading);
    render::FrameSettings s;
    s.width = 48, s.height = 32, s.sample_budget = 0.2, s.sync = true, s.soft_shadow_edges = soft;
    render::FrameRenderer renderer(scene, rs, shader, s);
    for (int k = 0; k < 4; ++k) renderer.render(scene.cameras[0]);
    size_t soft_edges = 0;
    for (const edges::SceneEdge& e : renderer.scene_edges())
      soft_edges += e.kind == edges::EdgeKind::umbral || e.kind == edges::EdgeKind::penumbral;
    return std::pair(renderer.edge_finder()->pairs_recomputed(), soft_edges);
  };
  EXPECT_EQ(pairs(false, true), std::pair(size_t(0), size_t(0)));  // area light, soft edges off
  const auto on = pairs(true, true);                                // the positive control
  EXPECT_GT(on.first, 0u);
  EXPECT_GT(on.second, 0u);
  EXPECT_EQ(pairs(true, false).second, 0u);  // soft edges on, but no area light: no soft edge
}

// The edge finder keeps a tree only for meshes the cost model gives to the tree. With the default
// model every mesh here goes to brute force (as nearly every bundled mesh does: docs/edges.md) and
// keeps no tree; with brute force made expensive (the positive control) the sphere keeps its tree.
TEST(ModelOnly, NoEdgeTreeForMeshesSentToBruteForce) {
  Scene scene = test::plane_and_box();
  test::add_object(scene, test::sphere_mesh({3, 3, 1}, 1.0f, 32, 64, test::add_material(scene, glm::vec3(0.5f))), "sphere");
  edges::SceneEdgeSettings costly_brute_force;
  costly_brute_force.cost.ns_per_face = 1e3;
  for (const bool sphere_tree : {false, true}) {
    SCOPED_TRACE(sphere_tree);
    const edges::SceneEdgeFinder finder(scene, sphere_tree ? costly_brute_force : edges::SceneEdgeSettings{});
    for (uint32_t mesh = 0; mesh < scene.meshes.size(); ++mesh) {
      SCOPED_TRACE(scene.meshes[mesh].name);
      const bool tree = finder.choice(mesh).tree;
      EXPECT_EQ(tree, sphere_tree);  // costly brute force: every mesh takes the tree
      EXPECT_EQ(finder.edge_tree(mesh).nodes().empty(), !tree);
      EXPECT_EQ(finder.edge_tree(mesh).memory_bytes() == 0, !tree);
    }
  }
  // Keeping every tree (as `epi edges` does, to time both finders) costs more memory.
  const edges::SceneEdgeFinder finder(scene);
  edges::SceneEdgeSettings keep;
  keep.keep_unchosen_trees = true;
  const edges::SceneEdgeFinder all(scene, keep);
  EXPECT_FALSE(all.edge_tree(2).nodes().empty());  // the sphere
  EXPECT_GT(all.memory_bytes(), finder.memory_bytes() + scene.meshes[2].triangles.size());
  // The edges found are the same either way (brute force is exact).
  std::vector<edges::SceneEdge> a, b;
  finder.view_edges(scene, {3.0, -6.0, 4.0}, a);
  all.view_edges(scene, {3.0, -6.0, 4.0}, b);
  EXPECT_EQ(a.size(), b.size());
}

// No subdivision without a request in the mesh's extras, even with a level override on the command
// line (`--subdiv-level`): the cube keeps its 12 triangles and flat shading (no normals).
TEST(ModelOnly, NoSubdivisionWithoutExtras) {
  TempDir dir;
  for (const int level_override : {-1, 3}) {
    SCOPED_TRACE(level_override);
    const Scene scene = load_cube_scene(dir, false, nullptr, level_override);
    const Mesh& cube = scene.meshes[0];
    EXPECT_FALSE(cube.subdivided);
    EXPECT_EQ(cube.triangles.size(), 12u);
    EXPECT_TRUE(cube.normals.empty());
  }
  // The positive control: the same cube with a request, and the override applied to it.
  const Scene scene = load_cube_scene(dir, false, {{"scheme", "catmull-clark"}, {"level", 1}}, 2);
  EXPECT_TRUE(scene.meshes[0].subdivided);
  EXPECT_EQ(scene.meshes[0].subdivision.level, 2);
  EXPECT_GT(scene.meshes[0].triangles.size(), 12u * 15u);
  EXPECT_FALSE(scene.meshes[0].normals.empty());
  EXPECT_FALSE(scene.meshes[1].subdivided);  // the ground, without a request, untouched
  EXPECT_EQ(scene.meshes[1].triangles.size(), 2u);
}

// The frame loop builds the edge finder only in epi mode with edges on, its receiver trees only with
// shadow edges on, and the complex filter's centre-line masks only when that filter is on.
TEST(ModelOnly, TheFrameLoopBuildsOnlyWhatItsSettingsUse) {
  const Scene scene = test::plane_and_box();
  RayScene rs(scene);
  Shader shader(rs, ShaderSettings{});
  auto make = [&](render::RenderMode mode, bool edges, bool complex) {
    render::FrameSettings s;
    s.width = 32, s.height = 32, s.sync = true, s.mode = mode;
    s.view_edges = s.shadow_edges = edges, s.complex_filter = complex;
    return std::make_unique<render::FrameRenderer>(scene, rs, shader, s);
  };
  // Receiver trees only with shadow edges on (view edges alone need none).
  auto make_edges = [&](bool shadow_edges) {
    render::FrameSettings s;
    s.width = 32, s.height = 32, s.sync = true, s.shadow_edges = shadow_edges;
    return std::make_unique<render::FrameRenderer>(scene, rs, shader, s);
  };
  const auto view_only = make_edges(false), with_shadows = make_edges(true);
  for (uint32_t mesh = 0; mesh < scene.meshes.size(); ++mesh) {
    EXPECT_EQ(view_only->edge_finder()->receiver_tree(mesh).memory_bytes(), 0u);
    EXPECT_GT(with_shadows->edge_finder()->receiver_tree(mesh).memory_bytes(), 0u);
  }
  EXPECT_LT(view_only->edge_finder()->memory_bytes(), with_shadows->edge_finder()->memory_bytes());
  view_only->render(scene.cameras[0]);  // and it renders, with its view edges
  EXPECT_GT(view_only->stats().edges.silhouette, 0);
  EXPECT_EQ(view_only->stats().edges.shadow, 0);

  const auto epi = make(render::RenderMode::epi, true, true);
  EXPECT_NE(epi->edge_finder(), nullptr);  // the positive control
  EXPECT_TRUE(epi->masks().centre_lines);
  EXPECT_FALSE(epi->masks().centre_h.empty());
  EXPECT_EQ(make(render::RenderMode::rendercache, true, true)->edge_finder(), nullptr);
  EXPECT_EQ(make(render::RenderMode::epi, false, true)->edge_finder(), nullptr);
  const auto plain = make(render::RenderMode::epi, true, false);
  EXPECT_FALSE(plain->masks().centre_lines);
  EXPECT_TRUE(plain->masks().centre_h.empty());
  EXPECT_TRUE(plain->masks().centre_v.empty());
  const auto cache = make(render::RenderMode::rendercache, true, true);
  EXPECT_TRUE(cache->masks().centre_h.empty());  // no edges at all in render cache mode
}

}  // namespace
}  // namespace epi

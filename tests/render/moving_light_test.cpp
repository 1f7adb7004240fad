// Punctual lights moved by the frame loop (camera path `light` keys): the shader traces with the
// moved light (sync directly, async between batches), the shot records the light placement it was
// traced with, and the edge finder recomputes exactly the moved light's shadow edges.
#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "edges/scene_edges.h"
#include "render/renderer.h"
#include "test_scenes.h"

namespace epi::render {
namespace {

using test::plane_and_box;

FrameSettings small_settings(bool sync) {
  FrameSettings s;
  s.mode = RenderMode::epi, s.width = 64, s.height = 64, s.sample_budget = 0.05, s.sync = sync, s.seed = 3;
  return s;
}

bool is_shadow(const edges::SceneEdge& e) {
  return e.kind == edges::EdgeKind::umbral || e.kind == edges::EdgeKind::penumbral || e.kind == edges::EdgeKind::shadow;
}

std::vector<edges::SceneEdge> box_shadow_edges(const std::vector<edges::SceneEdge>& all) {
  std::vector<edges::SceneEdge> out;
  for (const edges::SceneEdge& e : all)
    if (is_shadow(e) && e.blocker == 1) out.push_back(e);
  return out;
}

bool on_some_edge(const std::vector<edges::SceneEdge>& list, uint32_t object, glm::dvec3 p) {
  return std::any_of(list.begin(), list.end(), [&](const edges::SceneEdge& e) {
    if (e.object != object) return false;
    const glm::dvec3 ab = e.b - e.a;
    const double t = std::clamp(glm::dot(p - e.a, ab) / std::max(glm::dot(ab, ab), 1e-30), 0.0, 1.0);
    return glm::length(p - (e.a + t * ab)) < 1e-4;
  });
}

// Points along every edge of `a` that lie on no edge of `b`.
size_t points_off(const std::vector<edges::SceneEdge>& a, const std::vector<edges::SceneEdge>& b) {
  size_t off = 0;
  for (const edges::SceneEdge& e : a)
    for (double t : {0.0, 0.3, 0.7, 1.0}) off += !on_some_edge(b, e.object, glm::mix(e.a, e.b, t));
  return off;
}

std::vector<ShadeRequest> grid_requests() {
  std::vector<ShadeRequest> requests;
  for (int y = 0; y < 64; y += 3)
    for (int x = 0; x < 64; x += 3) requests.push_back({uint32_t(requests.size()), float(x) + 0.5f, float(y) + 0.5f});
  return requests;
}

ViewFrame view_of(const Camera& camera) {
  View view;
  view.camera = camera, view.width = 64, view.height = 64;
  return ViewFrame(view);
}

// Shades the grid with `shader` and with a fresh shader over `placed` (the light put there
// directly): how many colours differ.
size_t shading_differences(const Shader& shader, const Scene& placed, const Camera& camera) {
  RayScene ray_scene(placed);
  const Shader fresh(ray_scene, shader.settings());
  ShadeBatch a, b;
  shader.shade(view_of(camera), grid_requests(), a);
  fresh.shade(view_of(camera), grid_requests(), b);
  size_t differ = 0;
  for (size_t i = 0; i < a.results.size(); ++i) differ += a.results[i].color != b.results[i].color;
  return differ;
}

TEST(MovingLight, SyncShadowEdgesAndShadingFollowThePointLight) {
  const Scene scene = plane_and_box();
  RayScene ray_scene(scene);
  const Shader shader(ray_scene, ShaderSettings{});
  FrameRenderer renderer(scene, ray_scene, shader, small_settings(true));
  const Camera camera = scene.cameras[0];
  for (int k = 0; k < 6; ++k) renderer.render(camera);
  const std::vector<edges::SceneEdge> before = box_shadow_edges(renderer.scene_edges());
  ASSERT_GE(before.size(), 4u);
  const size_t recomputed = renderer.edge_finder()->pairs_recomputed();
  std::vector<glm::vec3> lights = {scene.punctual_lights[0].position};
  renderer.render(camera, {}, lights);  // placed where the scene places it: nothing moves
  EXPECT_EQ(renderer.edge_finder()->pairs_recomputed(), recomputed);

  const glm::vec3 moved = scene.punctual_lights[0].position + glm::vec3(1.5f, 1.0f, -0.5f);
  lights[0] = moved;
  renderer.render(camera, {}, lights);
  EXPECT_GT(renderer.edge_finder()->pairs_recomputed(), recomputed);
  EXPECT_EQ(renderer.light_positions()[0], moved);
  EXPECT_EQ(ray_scene.punctual_lights()[0].position, moved);
  const std::vector<edges::SceneEdge> after = box_shadow_edges(renderer.scene_edges());
  ASSERT_GE(after.size(), 4u);
  EXPECT_GT(points_off(after, before), after.size());  // the shadow moved

  // The oracle: the edge finder over the scene with the light placed there directly.
  Scene placed = plane_and_box();
  placed.punctual_lights[0].position = moved;
  edges::SceneEdgeFinder finder(placed);
  std::vector<edges::LightBlockerReceiver> triples = finder.find_triples(placed);
  std::erase_if(triples, [](const edges::LightBlockerReceiver& t) { return t.blocker != 1; });
  std::vector<edges::SceneEdge> expected;
  finder.shadow_edges(placed, triples, expected);
  expected = box_shadow_edges(expected);
  ASSERT_GE(expected.size(), 4u);
  EXPECT_EQ(points_off(after, expected), 0u);
  EXPECT_EQ(points_off(expected, after), 0u);

  // Shading: the renderer's shader now lights as a fresh one with the light placed there, and a
  // receiver point under the moved shadow changes.
  EXPECT_EQ(shading_differences(shader, placed, camera), 0u);
  EXPECT_GT(shading_differences(shader, scene, camera), 20u);
}

TEST(MovingLight, AMovedLightRecomputesOnlyItsOwnPairs) {
  Scene scene = plane_and_box();
  scene.punctual_lights.push_back(test::point_light({-3.0f, -2.0f, 5.0f}, glm::vec3(30.0f)));
  scene.punctual_lights.back().name = "second";
  edges::SceneEdgeFinder finder(scene);
  const std::vector<edges::LightBlockerReceiver> triples = finder.find_triples(scene);
  std::vector<edges::SceneEdge> out;
  finder.shadow_edges(scene, triples, out);
  const size_t first = finder.pairs_recomputed();
  finder.shadow_edges(scene, triples, out);
  EXPECT_EQ(finder.pairs_recomputed(), first);
  size_t pairs_of_second = 0;
  for (uint32_t b = 0; b < scene.objects.size(); ++b)
    pairs_of_second += std::any_of(triples.begin(), triples.end(), [&](const auto& t) { return t.light == 1 && t.blocker == b; });
  ASSERT_GT(pairs_of_second, 0u);
  ASSERT_LT(pairs_of_second * 2, first + pairs_of_second);  // the other light has pairs too
  scene.punctual_lights[1].position.x += 0.5f;
  finder.shadow_edges(scene, triples, out);
  EXPECT_EQ(finder.pairs_recomputed(), first + pairs_of_second);
}

void wait_for_shader(const FrameRenderer& renderer) {
  for (int k = 0; k < 20000 && renderer.pending_requests() > 0; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

// Async shading while the light moves every frame: every frame integrates samples (nothing is
// dropped because the light moved), each shot records the light position it is traced with, and
// the shader ends up lighting as a fresh one with the light placed there.
TEST(MovingLight, AsyncWithALightMovingEveryFrameIntegratesSamples) {
  const Scene scene = plane_and_box();
  RayScene ray_scene(scene);
  const Shader shader(ray_scene, ShaderSettings{});
  FrameSettings s = small_settings(false);
  s.sample_budget = 0.1;
  FrameRenderer renderer(scene, ray_scene, shader, s);
  const Camera camera = scene.cameras[0];
  std::vector<glm::vec3> lights = {scene.punctual_lights[0].position};
  size_t recomputed = 0;
  for (int k = 0; k < 24; ++k) {
    lights[0] = scene.punctual_lights[0].position + glm::vec3(-0.15f * float(k), 0.1f * float(k), 0.0f);
    renderer.render(camera, {}, lights);
    EXPECT_EQ(renderer.newest_shot_light_positions()[0], lights[0]) << "frame " << k;
    if (k > 0) {
      EXPECT_GT(renderer.stats().samples, 64u * 64u / 20) << "frame " << k;
      EXPECT_LT(renderer.stats().sparseness, 20.0);
    }
    if (k > 2) {  // the shadow edges follow the light
      EXPECT_GT(renderer.edge_finder()->pairs_recomputed(), recomputed) << "frame " << k;
      EXPECT_GT(renderer.stats().edges.shadow + renderer.stats().edges.culled, 0) << "frame " << k;
    }
    recomputed = renderer.edge_finder()->pairs_recomputed();
    wait_for_shader(renderer);
  }
  EXPECT_EQ(ray_scene.punctual_lights()[0].position, lights[0]);
  Scene placed = plane_and_box();
  placed.punctual_lights[0].position = lights[0];
  EXPECT_EQ(shading_differences(shader, placed, camera), 0u);
}

TEST(MovingLight, BadPlacementsAreRejected) {
  Scene scene = plane_and_box();
  PunctualLight sun;
  sun.name = "sun", sun.type = LightType::directional;
  scene.punctual_lights.push_back(sun);
  RayScene ray_scene(scene);
  EXPECT_THROW(ray_scene.set_punctual_light_position(1, glm::vec3(1.0f)), std::invalid_argument);
  EXPECT_THROW(ray_scene.set_punctual_light_position(2, glm::vec3(1.0f)), std::out_of_range);
  const Shader shader(ray_scene, ShaderSettings{});
  FrameRenderer renderer(scene, ray_scene, shader, small_settings(true));
  const std::vector<glm::vec3> one = {glm::vec3(0.0f)};
  EXPECT_THROW(renderer.render(scene.cameras[0], {}, one), std::invalid_argument);  // two lights
  // A directional light's entry is ignored (it has no position).
  const std::vector<glm::vec3> two = {scene.punctual_lights[0].position, glm::vec3(5.0f)};
  renderer.render(scene.cameras[0], {}, two);
  EXPECT_EQ(ray_scene.punctual_lights()[1].position, sun.position);
}

}  // namespace
}  // namespace epi::render

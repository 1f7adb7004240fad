// Punctual highlights (docs/render.md, "Punctual highlights"): the cache shows a point's punctual
// lights' specular part recomputed for the eye of each frame, so a metal shaded from one view and
// seen from another shows what the shader computes from the new view, instead of a stale highlight
// faded out and dropped.
#include <cmath>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "epi/epi_pixel.h"
#include "render/point_cache.h"
#include "shade/shader.h"
#include "test_scenes.h"

namespace epi::render {
namespace {

constexpr int kSize = 64;

// A smooth gold sphere (roughness 0.3: lobe width 0.09 rad) under a point light, on a floor.
Scene metal_scene() {
  Scene scene;
  const uint32_t gold = test::add_material(scene, glm::vec3(0.9f, 0.7f, 0.3f), 1.0f, 0.3f);
  const uint32_t grey = test::add_material(scene, glm::vec3(0.5f), 0.0f, 0.8f);
  test::add_object(scene, test::sphere_mesh({0, 0, 1}, 1.0f, 48, 96, gold), "ball");
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, grey), "floor");
  scene.punctual_lights.push_back(test::point_light({2, -2, 4}, glm::vec3(40.0f)));
  return scene;
}

// Every pixel of `frame` shaded once.
ShadeBatch shade_all(const Shader& shader, const ViewFrame& frame) {
  std::vector<ShadeRequest> requests;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) requests.push_back({uint32_t(requests.size()), float(x) + 0.5f, float(y) + 0.5f});
  ShadeBatch batch;
  shader.shade(frame, requests, batch);
  return batch;
}

struct Shown {
  int drawn = 0, sampled = 0, close = 0;  // ball pixels drawn, holding a sample, within tolerance
};

// The cache filled from `shot`, projected into `now`: the ball's drawn points against the shader's
// colour of the same points from `now`.
Shown shown_from(const Shader& shader, const ViewFrame& shot, const ViewFrame& now, float highlight_share,
                 bool reference_path = false) {
  const std::vector<glm::mat4> transforms(2, glm::mat4(1.0f));
  PointCacheSettings settings;
  settings.punctual_highlight_share = highlight_share;
  settings.reference_path = reference_path;
  PointCache cache(kSize, kSize, settings);
  cache.set_highlight_model(shader.punctual_specular_model());
  cache.insert(shot, shade_all(shader, shot), transforms);
  cache.project(now, transforms, false);
  EpiImage epi(kSize, kSize);
  cache.fill_epi(epi);
  std::vector<ShadeRequest> requests;
  std::vector<size_t> pixels;
  for (size_t i = 0; i < epi.edge.size(); ++i) {
    const int32_t slot = cache.image().point[i];
    if (slot < 0 || cache.points()[size_t(slot)].object != 0) continue;
    const Projection p = now.project(cache.world_position(cache.points()[size_t(slot)], now, transforms));
    requests.push_back({uint32_t(requests.size()), p.pixel.x, p.pixel.y});
    pixels.push_back(i);
  }
  ShadeBatch fresh;
  shader.shade(now, requests, fresh);
  Shown shown;
  for (const ShadeResult& r : fresh.results) {
    if (!r.hit || r.object != 0) continue;
    const size_t i = pixels[r.id];
    ++shown.drawn;
    if (!has_sample(epi.edge[i])) continue;
    ++shown.sampled;
    float rgb[3];
    decode_color(epi.color[i], rgb);
    bool close = true;
    for (int c = 0; c < 3; ++c) close &= std::abs(rgb[c] - std::min(r.color[c], 1.0f)) <= 0.03f + 0.05f * r.color[c];
    shown.close += close;
  }
  return shown;
}

TEST(PunctualHighlights, AMetalSeenFromANewViewShowsTheNewViewsHighlight) {
  const Scene scene = metal_scene();
  RayScene rays(scene);
  const Shader shader(rays, ShaderSettings{});
  const ViewFrame shot(View{test::look({5, -1, 2.5f}, {0, 0, 1}), kSize, kSize});
  // 40 degrees around the ball: past the fade's end (6 lobe widths, 31 degrees).
  const float turn = glm::radians(40.0f);
  const glm::vec3 eye(5 * std::cos(turn) + std::sin(turn), 5 * std::sin(turn) - std::cos(turn), 2.5f);
  const ViewFrame now(View{test::look(eye, {0, 0, 1}), kSize, kSize});

  for (const bool reference_path : {false, true}) {
    const Shown kept = shown_from(shader, shot, now, 0.1f, reference_path);
    ASSERT_GT(kept.drawn, 300);
    EXPECT_EQ(kept.sampled, kept.drawn) << reference_path;           // none dropped as stale
    EXPECT_GT(kept.close, kept.drawn * 95 / 100) << reference_path;  // and they show the new view's colour
  }
  // Without: the stale highlights are dropped from the EPI (metal: mostly view-dependent).
  const Shown stale = shown_from(shader, shot, now, PointCacheSettings::kNoPunctualHighlights);
  EXPECT_LT(stale.sampled, stale.drawn / 3) << stale.close;
  // From the shading view itself both show what was shaded.
  const Shown same = shown_from(shader, shot, shot, 0.1f);
  EXPECT_GT(same.close, same.drawn * 98 / 100);
}

// The cache owns what recomputes its highlights: a copy still shows them after the shader and its
// ray scene are gone (render_points_bench copies a renderer's cache and drops the renderer: it
// crashed when the cache pointed at the shader), and moving a light in one copy leaves the other.
TEST(PunctualHighlights, ACopyOfTheCacheOwnsWhatRecomputesItsHighlights) {
  const Scene scene = metal_scene();
  const std::vector<glm::mat4> transforms(2, glm::mat4(1.0f));
  const ViewFrame shot(View{test::look({5, -1, 2.5f}, {0, 0, 1}), kSize, kSize});
  const ViewFrame now(View{test::look({4, 3, 3}, {0, 0, 1}), kSize, kSize});
  auto filled = [&](PointCache cache) {  // a copy: projecting ages the points
    cache.project(now, transforms, false);
    EpiImage epi(kSize, kSize);
    cache.fill_epi(epi);
    return epi.color;
  };
  std::optional<PointCache> copy;
  std::vector<uint32_t> expected;
  {
    RayScene rays(scene);
    const Shader shader(rays, ShaderSettings{});
    PointCache cache(kSize, kSize, PointCacheSettings{});
    cache.set_highlight_model(shader.punctual_specular_model());
    cache.insert(shot, shade_all(shader, shot), transforms);
    copy.emplace(cache);
    expected = filled(cache);
  }
  int highlighted = 0;
  for (const PunctualHighlight& h : copy->highlights()) highlighted += h.lights != 0;
  ASSERT_GT(highlighted, 100);
  PointCache moved(*copy);
  EXPECT_EQ(filled(*copy), expected);
  moved.move_highlight_light(0, {-2, 2, 4});
  const std::vector<uint32_t> after_move = filled(moved);
  int changed = 0;
  for (size_t i = 0; i < expected.size(); ++i) changed += after_move[i] != expected[i];
  EXPECT_GT(changed, 50);
  EXPECT_EQ(filled(*copy), expected);
}

}  // namespace
}  // namespace epi::render

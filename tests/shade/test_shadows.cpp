// Shadows and the light-blocker-receiver triples; moving objects.
#include <algorithm>

#include <gtest/gtest.h>

#include "shade/sampling.h"
#include "shade/shader.h"
#include "test_scenes.h"

namespace epi {
namespace {

struct ShadowScene {
  Scene scene;
  uint32_t floor, blocker, panel = kNone;
};

// A floor, a point light at (0, 0, 3), a 1 x 1 blocker plate at z = 1.5 above the origin;
// optionally a square area light at z = 3 around (4, 0).
ShadowScene make_shadow_scene(bool with_area_light) {
  ShadowScene s;
  uint32_t grey = test::add_material(s.scene, glm::vec3(0.5f));
  s.floor = test::add_object(s.scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, grey), "floor");
  s.blocker = test::add_object(s.scene, test::box_mesh({-0.5f, -0.5f, 1.45f}, {0.5f, 0.5f, 1.55f}, grey, false), "blocker");
  s.scene.punctual_lights.push_back(test::point_light({0, 0, 3}, glm::vec3(10.0f)));
  if (with_area_light) {
    uint32_t emitter = test::add_material(s.scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(5.0f));
    s.panel = test::add_object(s.scene, test::quad_mesh({3.5f, -0.5f, 3}, {0, 1, 0}, {1, 0, 0}, emitter), "panel");
    test::add_area_light(s.scene, s.panel);
  }
  return s;
}

ShadeBatch shade_points(const Shader& shader, const View& view, const std::vector<glm::vec3>& points) {
  std::vector<ShadeRequest> requests;
  for (size_t i = 0; i < points.size(); ++i) {
    Projection p = project(view, points[i]);
    requests.push_back({uint32_t(i), p.pixel.x, p.pixel.y});
  }
  ShadeBatch batch;
  shader.shade(view, requests, batch);
  return batch;
}

const View kView{test::look({6, -2, 1}, {0, 0, 0}), 128, 128};

TEST(Shadows, PointBehindABlockerIsBlackAndReportsTheTriple) {
  ShadowScene s = make_shadow_scene(false);
  RayScene rays(s.scene);
  Shader shader(rays, ShaderSettings{});
  ShadeBatch batch = shade_points(shader, kView, {{0, 0, 0}, {0.2f, -0.1f, 0}, {3, 0, 0}, {-2, 2, 0}});
  for (int i : {0, 1}) {
    const ShadeResult& r = batch.results[i];
    ASSERT_TRUE(r.hit);
    EXPECT_EQ(r.object, s.floor);
    EXPECT_EQ(r.color, glm::vec3(0.0f));
    ASSERT_EQ(r.triple_count, 1u);
    EXPECT_EQ(batch.triples_of(r)[0], (BlockerTriple{0, s.blocker, s.floor}));
  }
  for (int i : {2, 3}) {
    const ShadeResult& r = batch.results[i];
    ASSERT_TRUE(r.hit);
    EXPECT_GT(r.color.x, 0.0f);
    EXPECT_EQ(r.triple_count, 0u);
  }
}

// A blocker whose shadow lies inside another blocker's shadow draws no visible edge: the shadow ray
// names the first blocker only where nothing else blocks the light behind it (docs/render.md,
// "Shadow edges only where they show"). A wide plate at z = 2.5 shades the small box under it.
TEST(Shadows, ABlockerInsideAnotherBlockersShadowReportsNoTriple) {
  ShadowScene s = make_shadow_scene(false);
  const uint32_t grey = 0;  // make_shadow_scene's material
  const uint32_t plate = test::add_object(s.scene, test::quad_mesh({-1.5f, -1.5f, 2.5f}, {3, 0, 0}, {0, 3, 0}, grey), "plate");
  RayScene rays(s.scene);
  Shader shader(rays, ShaderSettings{});
  // (0, 0, 0): the box is nearest, the plate blocks the light behind it. (1.2, 0, 0) and (3, 0, 0):
  // towards the light they pass the box's side (x = 0.6, 1.5 at z = 1.5) and meet the plate.
  const ShadeBatch batch = shade_points(shader, kView, {{0, 0, 0}, {0.2f, -0.1f, 0}, {1.2f, 0, 0}, {3, 0, 0}});
  for (int i : {0, 1}) {
    const ShadeResult& r = batch.results[i];
    ASSERT_TRUE(r.hit);
    EXPECT_EQ(r.color, glm::vec3(0.0f));
    EXPECT_EQ(r.triple_count, 0u) << i;
  }
  for (int i : {2, 3}) {
    ASSERT_EQ(batch.results[i].triple_count, 1u) << i;
    EXPECT_EQ(batch.triples_of(batch.results[i])[0], (BlockerTriple{0, plate, s.floor})) << i;
  }
}

// A blocker resting on its receiver keeps its triple right at the contact, where the shadow ray meets
// the blocker about a ray offset from its start: the ray traced back from the light meets the box
// first, so the box counts as the only blocker (fails if the check never finds a sole blocker).
TEST(Shadows, ABlockerRestingOnTheReceiverReportsItsTripleAtTheContact) {
  Scene scene;
  const uint32_t grey = test::add_material(scene, glm::vec3(0.5f));
  const uint32_t floor = test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, grey), "floor");
  const uint32_t box = test::add_object(scene, test::box_mesh({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f}, grey, false), "box");
  scene.punctual_lights.push_back(test::point_light({2, 0, 3}, glm::vec3(10.0f)));
  RayScene rays(scene);
  Shader shader(rays, ShaderSettings{});
  const View view{test::look({-6, -2, 2}, {0, 0, 0}), 128, 128};
  for (const float gap : {1e-4f, 1e-3f, 0.05f}) {
    const ShadeBatch batch = shade_points(shader, view, {{-0.5f - gap, 0.1f, 0.0f}});
    const ShadeResult& r = batch.results[0];
    ASSERT_TRUE(r.hit);
    ASSERT_EQ(r.object, floor) << gap;
    EXPECT_EQ(r.color, glm::vec3(0.0f)) << gap;
    ASSERT_EQ(r.triple_count, 1u) << gap;
    EXPECT_EQ(batch.triples_of(r)[0], (BlockerTriple{0, box, floor})) << gap;
  }
}

TEST(Shadows, AreaLightTriplesAreNumberedAfterPunctualLightsAndDeduplicated) {
  ShadowScene s = make_shadow_scene(true);
  RayScene rays(s.scene);
  ShaderSettings settings;
  settings.area_light_samples = 64;
  Shader shader(rays, settings);
  // (1.5, 0, 0): the blocker hides part of the panel (at z = 3 over x in [3.5, 4.5]) but not the point light.
  // Panel as seen from here: the ray to its centre passes x = 0.5 + ... check below with geometry.
  glm::vec3 receiver(-2.0f, 0.0f, 0.0f);
  // From (-2, 0, 0) to the panel centre (4, 0, 3): at z = 1.5, x = 1.0: clear of the blocker; to the point light
  // (0, 0, 3): at z = 1.5, x = -1: clear. Pick a receiver the blocker shadows from the panel instead:
  receiver = glm::vec3(-3.0f, 0.0f, 0.0f);  // to (4, 0, 3) at z = 1.5: x = 0.5 (edge); to (3.5..4.5): partly blocked
  ShadeBatch batch = shade_points(shader, kView, {receiver, {0, 0, 0}, {6, 3, 0}});
  const ShadeResult& partial = batch.results[0];
  ASSERT_TRUE(partial.hit);
  auto triples = batch.triples_of(partial);
  ASSERT_EQ(triples.size(), 1u);  // 64 samples, many blocked, one triple
  EXPECT_EQ(triples[0], (BlockerTriple{1, s.blocker, s.floor}));
  EXPECT_GT(partial.color.x, 0.0f);  // penumbra: partly lit
  // Under the blocker: the point light is blocked, and the panel partly.
  auto under = batch.triples_of(batch.results[1]);
  EXPECT_NE(std::find(under.begin(), under.end(), BlockerTriple{0, s.blocker, s.floor}), under.end());
  for (size_t i = 0; i < under.size(); ++i)
    for (size_t j = i + 1; j < under.size(); ++j) EXPECT_FALSE(under[i] == under[j]);
  EXPECT_EQ(batch.results[2].triple_count, 0u);  // in the open
}

TEST(Shadows, RecordingBlockersDoesNotChangeColours) {
  ShadowScene s = make_shadow_scene(true);
  RayScene rays(s.scene);
  ShaderSettings settings;
  Shader recording(rays, settings);
  settings.record_blockers = false;
  Shader plain(rays, settings);
  std::vector<glm::vec3> points;
  for (int i = 0; i < 40; ++i) points.push_back({-3.0f + 0.2f * float(i), 0.1f * float(i % 7) - 0.3f, 0.0f});
  ShadeBatch a = shade_points(recording, kView, points), b = shade_points(plain, kView, points);
  EXPECT_FALSE(a.triples.empty());
  EXPECT_TRUE(b.triples.empty());
  for (size_t i = 0; i < points.size(); ++i) EXPECT_EQ(a.results[i].color, b.results[i].color) << i;
}

// ShadeRequest::blockers: `punctual` names the point light's blockers only, `none` none, and
// neither changes a colour; `all` names the area light's too (the blocker seen from the
// penumbra at (-3, 0)). Fewer rays without the point light's sole-blocker checks.
TEST(Shadows, ARequestNamesOnlyTheBlockersItAsksFor) {
  ShadowScene s = make_shadow_scene(true);
  RayScene rays(s.scene);
  Shader shader(rays, ShaderSettings{});
  std::vector<glm::vec3> points;
  for (int i = 0; i < 40; ++i) points.push_back({-3.0f + 0.2f * float(i), 0.1f * float(i % 7) - 0.3f, 0.0f});
  auto shade = [&](Blockers blockers) {
    std::vector<ShadeRequest> requests;
    for (size_t i = 0; i < points.size(); ++i) {
      const Projection p = project(kView, points[i]);
      requests.push_back({uint32_t(i), p.pixel.x, p.pixel.y});
      requests.back().blockers = blockers;
    }
    ShadeBatch batch;
    shader.shade(kView, requests, batch);
    return batch;
  };
  const ShadeBatch all = shade(Blockers::all), punctual = shade(Blockers::punctual), none = shade(Blockers::none);
  auto lights = [](const ShadeBatch& b, bool area) {
    return std::count_if(b.triples.begin(), b.triples.end(), [&](const BlockerTriple& t) { return (t.light >= 1) == area; });
  };
  EXPECT_GT(lights(all, true), 0);
  EXPECT_GT(lights(all, false), 0);
  EXPECT_EQ(lights(punctual, true), 0);
  EXPECT_EQ(lights(punctual, false), lights(all, false));
  EXPECT_TRUE(none.triples.empty());
  EXPECT_LT(none.rays, punctual.rays);
  EXPECT_EQ(punctual.rays, all.rays);  // an any-hit ray for each area sample instead of a closest-hit one
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(all.results[i].color, punctual.results[i].color) << i;
    EXPECT_EQ(all.results[i].color, none.results[i].color) << i;
  }
}

// Without area-light triples a hit's shadow rays to the area lights go as packets of 16 (from 4
// samples a hit on); with them (Blockers::all) one at a time. The same colours, bit for bit, and
// the same ray counts, for sample counts around the packet's size, for the direct, glossy and gi
// shaders (gi with 4 light samples at every path vertex: packets from a shared random stream).
TEST(Shadows, ShadowRaysInPacketsGiveTheSameBits) {
  ShadowScene s = make_shadow_scene(true);
  RayScene rays(s.scene);
  std::vector<glm::vec3> points;
  for (int i = 0; i < 30; ++i) points.push_back({-3.0f + 0.25f * float(i), 0.13f * float(i % 7) - 0.4f, 0.0f});
  for (const ShaderKind kind : {ShaderKind::direct, ShaderKind::glossy, ShaderKind::gi})
    for (const int samples : {1, 3, 4, 15, 16, 17, 40}) {
      ShaderSettings settings;
      settings.kind = kind, settings.area_light_samples = samples;
      settings.glossy_samples = 2, settings.gi_paths = 2, settings.gi_light_samples = 4;
      const Shader shader(rays, settings);
      ShadeBatch single, packets;
      for (const auto& [blockers, batch] : {std::pair{Blockers::all, &single}, {Blockers::punctual, &packets}}) {
        std::vector<ShadeRequest> requests;
        for (size_t i = 0; i < points.size(); ++i) {
          const Projection p = project(kView, points[i]);
          requests.push_back({uint32_t(i), p.pixel.x, p.pixel.y});
          requests.back().blockers = blockers;
        }
        shader.shade(kView, requests, *batch);
      }
      EXPECT_EQ(single.rays, packets.rays) << int(kind) << " " << samples;
      for (size_t i = 0; i < points.size(); ++i) {
        ASSERT_EQ(single.results[i].color, packets.results[i].color) << int(kind) << " " << samples << " point " << i;
        ASSERT_EQ(single.results[i].view_dependent, packets.results[i].view_dependent);
      }
    }
}

TEST(Shadows, MovingTheBlockerMovesTheShadow) {
  ShadowScene s = make_shadow_scene(false);
  RayScene rays(s.scene);
  Shader shader(rays, ShaderSettings{});
  ShadeBatch before = shade_points(shader, kView, {{0, 0, 0}, {3, 0, 0}});
  EXPECT_EQ(before.results[0].color, glm::vec3(0.0f));
  EXPECT_GT(before.results[1].color.x, 0.0f);
  // Shift the blocker by 1.5 in x: its shadow (scaled 2x from the light at height 3) moves by 3.
  rays.set_object_transform(s.blocker, glm::translate(glm::mat4(1.0f), glm::vec3(1.5f, 0, 0)));
  ShadeBatch after = shade_points(shader, kView, {{0, 0, 0}, {3, 0, 0}});
  EXPECT_GT(after.results[0].color.x, 0.0f);
  EXPECT_EQ(after.results[1].color, glm::vec3(0.0f));
  ASSERT_EQ(after.results[1].triple_count, 1u);
  EXPECT_EQ(after.triples_of(after.results[1])[0].blocker, s.blocker);
}

TEST(Shadows, MovingAnEmitterMovesItsLight) {
  ShadowScene s = make_shadow_scene(true);
  s.scene.punctual_lights.clear();
  RayScene rays(s.scene);
  ShaderSettings settings;
  settings.area_light_samples = 256;
  settings.specular = false;  // view-independent, so both points can be compared
  Shader shader(rays, settings);
  const glm::vec3 under_panel(4, 0, 0), far(-6, 0, 0);
  ShadeBatch before = shade_points(shader, kView, {under_panel, far});
  // Move the panel over (-6, 0): the light follows (area light copy, sampling and emission).
  rays.set_object_transform(s.panel, glm::translate(glm::mat4(1.0f), glm::vec3(-10, 0, 0)));
  EXPECT_NEAR(rays.area_lights()[0].triangle_vertices[0].x, s.scene.area_lights[0].triangle_vertices[0].x - 10, 1e-5f);
  ShadeBatch after = shade_points(shader, kView, {under_panel, far});
  EXPECT_NEAR(after.results[1].color.x, before.results[0].color.x, 0.02f * before.results[0].color.x);
  EXPECT_LT(after.results[0].color.x, 0.05f * before.results[0].color.x);
}

TEST(RayScene, RejectsBrokenScenesWithOneLine) {
  Scene scene;
  scene.source = "broken.gltf";
  uint32_t m = test::add_material(scene, glm::vec3(0.5f));
  Mesh mesh = test::quad_mesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, m);
  mesh.triangles[1][2] = 99;
  test::add_object(scene, mesh, "bad");
  try {
    RayScene rays(scene);
    FAIL() << "accepted an out-of-range index";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.gltf"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  scene.meshes[0].triangles[1][2] = 3;
  scene.objects[0].mesh = 5;
  EXPECT_THROW(RayScene{scene}, std::runtime_error);
  scene.objects[0].mesh = 0;
  scene.meshes[0].materials[0].material = 7;
  EXPECT_THROW(RayScene{scene}, std::runtime_error);
  scene.meshes[0].materials[0].material = 0;
  RayScene ok(scene);
  EXPECT_GT(ok.embree_bytes(), 0u);
  EXPECT_THROW(ok.set_object_transform(3, glm::mat4(1.0f)), std::out_of_range);
}

TEST(RayScene, EmptySceneAndEmptyMeshesTraceAsMisses) {
  Scene scene;
  test::add_material(scene, glm::vec3(0.5f));
  Mesh empty;
  test::add_object(scene, empty, "empty");
  RayScene rays(scene);
  Shader shader(rays, ShaderSettings{});
  ShadeBatch batch = shade_points(shader, kView, {{0, 0, 0}});
  EXPECT_FALSE(batch.results[0].hit);
  Scene nothing;
  RayScene none(nothing);
  EXPECT_FALSE(none.intersect(Ray{}).hit);
}

}  // namespace
}  // namespace epi

namespace epi {
namespace {

TEST(RayScene, PacketsFindTheSameHitsAsSingleRays) {
  Scene scene;
  uint32_t grey = test::add_material(scene, glm::vec3(0.5f));
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, grey), "floor");
  test::add_object(scene, test::sphere_mesh({0, 0, 1}, 1.0f, 24, 48, grey), "ball",
                   glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 0, 0)), 0.4f, glm::vec3(0, 1, 1)));
  RayScene rays(scene);
  ViewFrame frame(View{test::look({0, -5, 2}, {0, 0, 0.7f}), 97, 61});
  std::vector<Ray> batch;
  for (int y = 0; y < 61; ++y)
    for (int x = 0; x < 97; ++x) batch.push_back(frame.ray(float(x) + 0.5f, float(y) + 0.25f));
  size_t hits = 0;
  for (size_t begin = 0; begin < batch.size(); begin += 13) {  // partial packets too
    size_t n = std::min<size_t>(13, batch.size() - begin);
    RayHit packet[16];
    rays.intersect16(&batch[begin], n, packet);
    for (size_t i = 0; i < n; ++i) {
      RayHit single = rays.intersect(batch[begin + i]);
      ASSERT_EQ(single.hit, packet[i].hit);
      ASSERT_EQ(single.object, packet[i].object);
      ASSERT_EQ(single.triangle, packet[i].triangle);
      ASSERT_NEAR(single.t, packet[i].t, 1e-5f * single.t);  // bit-equal here; Embree promises no more
      ASSERT_NEAR(single.u, packet[i].u, 1e-5f);
      ASSERT_NEAR(single.v, packet[i].v, 1e-5f);
      hits += single.hit;
    }
  }
  EXPECT_GT(hits, batch.size() / 2);
}

// Shadow rays as a packet (occluded16) answer as one at a time: rays from points on a floor to
// random points around a sphere and a plate (grazing, inside the sphere's silhouette, ending just
// short of or just past the first surface), packets of every size from 1 to 16, the unused lanes
// ignored.
TEST(RayScene, ShadowPacketsAnswerAsSingleRays) {
  Scene scene;
  uint32_t grey = test::add_material(scene, glm::vec3(0.5f));
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, grey), "floor");
  test::add_object(scene, test::sphere_mesh({0, 0, 1}, 1.0f, 24, 48, grey), "ball");
  test::add_object(scene, test::quad_mesh({-3, -1, 2.5f}, {2, 0, 0}, {0, 2, 0}, grey), "plate");
  RayScene rays(scene);
  Rng rng(5);
  size_t blocked_count = 0, total = 0;
  for (int round = 0; round < 400; ++round) {
    const glm::vec3 origin(rng.uniform() * 8.0f - 4.0f, rng.uniform() * 8.0f - 4.0f, 1e-3f);
    const size_t n = size_t(round % 16) + 1;
    Ray packet[16];
    for (size_t i = 0; i < n; ++i) {
      const glm::vec3 target(rng.uniform() * 6.0f - 3.0f, rng.uniform() * 6.0f - 3.0f, rng.uniform() * 4.0f);
      const glm::vec3 d = target - origin;
      packet[i].origin = origin;
      packet[i].direction = glm::normalize(d);
      packet[i].tnear = 0.0f;
      packet[i].tfar = glm::length(d);
      // Some end a hair before or past the first surface they meet (not on it: there the packet
      // and the single ray may round differently).
      if (const RayHit hit = rays.intersect(packet[i]); hit.hit && i % 3 != 2) packet[i].tfar = hit.t * (i % 3 == 0 ? 0.9999f : 1.0001f);
    }
    bool blocked[16];
    rays.occluded16(packet, n, blocked);
    for (size_t i = 0; i < n; ++i) {
      ASSERT_EQ(blocked[i], rays.occluded(packet[i])) << "round " << round << " ray " << i;
      blocked_count += blocked[i], ++total;
    }
  }
  EXPECT_GT(blocked_count, total / 10);
  EXPECT_LT(blocked_count, total - total / 10);
}

}  // namespace
}  // namespace epi

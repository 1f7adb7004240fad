// The point cache against analytic set-ups: planes seen by a pinhole camera, whose hits,
// depths and projections are known exactly.
#include <cmath>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <algorithm>

#include <gtest/gtest.h>

#include "render/point_cache.h"
#include "shade/brdf.h"

namespace epi::render {
namespace {

Camera camera_at(glm::vec3 eye, glm::vec3 target, float fov = 40.0f) {
  Camera c;
  c.eye = eye, c.target = target, c.up = glm::vec3(0, 1, 0), c.yfov_degrees = fov;
  return c;
}

View view_of(const Camera& c, int w, int h) {
  View v;
  v.camera = c, v.width = w, v.height = h;
  return v;
}

// A shading result where the ray through (x, y) meets the plane z = plane_z (world space).
ShadeResult plane_hit(const ViewFrame& frame, float x, float y, float plane_z, uint32_t object, glm::vec3 color,
                      const glm::mat4& object_to_world = glm::mat4(1.0f)) {
  const Ray ray = frame.ray(x, y);
  const float t = (plane_z - ray.origin.z) / ray.direction.z;
  ShadeResult r;
  r.x = x, r.y = y, r.hit = t > 0.0f, r.object = object;
  r.position = ray.origin + t * ray.direction;
  r.normal = glm::vec3(0.0f, 0.0f, ray.direction.z < 0.0f ? 1.0f : -1.0f);
  (void)object_to_world;
  r.color = color;
  return r;
}

// One result at every pixel, at sub-pixel position (fx, fy).
ShadeBatch full_plane(const ViewFrame& frame, float plane_z, float fx = 0.5f, float fy = 0.5f, glm::vec3 color = glm::vec3(0.5f)) {
  ShadeBatch batch;
  for (int y = 0; y < frame.view().height; ++y)
    for (int x = 0; x < frame.view().width; ++x)
      batch.results.push_back(plane_hit(frame, float(x) + fx, float(y) + fy, plane_z, 0, color));
  return batch;
}

const std::vector<glm::mat4> kIdentity(4, glm::mat4(1.0f));

TEST(PointCache, CapacityIsSlightlyLargerThanThePixelCount) {
  PointCache cache(100, 50);
  EXPECT_GE(cache.capacity(), 5000u);
  EXPECT_LE(cache.capacity(), 6000u);
  EXPECT_EQ(cache.valid_points(), 0u);
  EXPECT_THROW(PointCache(0, 10), std::invalid_argument);
}

TEST(PointCache, StaticCameraAndPlaneGiveOnePointPerPixelAtItsSubPixelPosition) {
  const int w = 48, h = 32;
  const ViewFrame frame(view_of(camera_at({0.3f, -0.2f, 10.0f}, {0.3f, -0.2f, 0.0f}), w, h));
  for (const auto& [fx, fy] : {std::pair{0.6f, 0.4f}, std::pair{0.1f, 0.9f}, std::pair{0.7f, 0.3f}}) {
    PointCache cache(w, h);
    cache.insert(frame, full_plane(frame, 0.0f, fx, fy), kIdentity);
    const ProjectionCounts counts = cache.project(frame, kIdentity);
    EXPECT_EQ(counts.projected, size_t(w * h));
    EXPECT_EQ(counts.drawn, size_t(w * h));
    EXPECT_EQ(counts.culled, 0u);
    const PointImage& image = cache.image();
    const int region = std::min(3, int(fx * 4)) + 4 * std::min(3, int(fy * 4));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = image.index(x, y);
        ASSERT_GE(image.point[i], 0);
        EXPECT_EQ(image.region[i], region) << x << "," << y;
        EXPECT_NEAR(image.depth[i], 10.0f, 1e-4f);
        EXPECT_EQ(cache.points()[size_t(image.point[i])].image_id, int32_t(i));
      }
    EpiImage epi(w, h);
    cache.fill_epi(epi);
    for (size_t i = 0; i < epi.edge.size(); ++i) {
      EXPECT_TRUE(has_sample(epi.edge[i]));
      EXPECT_EQ(sample_region(epi.edge[i]), region);
      EXPECT_EQ(sample_age(epi.color[i]), 1);
    }
  }
}

// Points shaded from one camera, then projected from a moved camera: every point lands where
// ViewFrame::project says, and each pixel shows the nearest of the points landing in it.
TEST(PointCache, MovedCameraReprojectsPointsWhereProjectSaysWithAZBuffer) {
  const int w = 40, h = 40;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const ViewFrame shot(view_of(camera_at({0, 0, 8}, {0, 0, 0}), w, h));
  // Two planes (z = 0 and z = -2 behind it, only where the first has no sample).
  ShadeBatch batch;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float px = float(x) + unit(rng), py = float(y) + unit(rng);
      batch.results.push_back(plane_hit(shot, px, py, (x + y) % 3 ? 0.0f : -2.0f, 0, glm::vec3(unit(rng))));
    }
  for (int trial = 0; trial < 5; ++trial) {
    PointCache cache(w, h, PointCacheSettings{.depth_cull_offset = 1e9f});  // no culling here
    cache.insert(shot, batch, kIdentity);
    const glm::vec3 eye(2.0f * unit(rng) - 1.0f, 2.0f * unit(rng) - 1.0f, 6.0f + 3.0f * unit(rng));
    const ViewFrame moved(view_of(camera_at(eye, {0.5f * unit(rng), 0.2f, 0.0f}, 35.0f + 10.0f * unit(rng)), w, h));
    cache.project(moved, kIdentity);
    // Brute force: nearest point per pixel.
    std::vector<float> nearest(size_t(w * h), INFINITY);
    for (const CachePoint& p : cache.points()) {
      if (!p.valid) continue;
      const Projection proj = moved.project(p.local);
      const bool inside = proj.in_front() && proj.pixel.x >= 0 && proj.pixel.y >= 0 && proj.pixel.x < w && proj.pixel.y < h;
      if (!inside) {
        EXPECT_EQ(p.image_id, -1);
        continue;
      }
      const int px = int(proj.pixel.x), py = int(proj.pixel.y);
      EXPECT_EQ(p.image_id, py * w + px);
      nearest[size_t(py * w + px)] = std::min(nearest[size_t(py * w + px)], proj.depth);
    }
    const PointImage& image = cache.image();
    for (size_t i = 0; i < nearest.size(); ++i) {
      if (std::isinf(nearest[i])) {
        EXPECT_LT(image.point[i], 0);
        continue;
      }
      ASSERT_GE(image.point[i], 0);
      EXPECT_EQ(image.depth[i], nearest[i]);
      const Projection proj = moved.project(cache.points()[size_t(image.point[i])].local);
      const int x = int(i) % w, y = int(i) / w;
      const int region = std::min(3, int((proj.pixel.x - float(x)) * 4)) + 4 * std::min(3, int((proj.pixel.y - float(y)) * 4));
      EXPECT_EQ(image.region[i], region);
    }
  }
}

// A far plane fully sampled and a nearer square sampled at every other pixel of every other row:
// far points showing through the gaps of the near square are culled; far points outside it are
// kept. (At a quarter of the density the 3x3 mean is pulled at least 11% nearer than the far plane.)
TEST(PointCache, DepthCullRemovesPointsBehindANearerSurface) {
  const int w = 64, h = 64;
  const ViewFrame frame(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  PointCache cache(w, h);
  cache.insert(frame, full_plane(frame, 0.0f, 0.5f, 0.5f, glm::vec3(0.2f)), kIdentity);
  ShadeBatch near;
  for (int y = 16; y < 48; ++y)
    for (int x = 16; x < 48; ++x)
      if (x % 2 == 0 && y % 2 == 0) near.results.push_back(plane_hit(frame, x + 0.5f, y + 0.5f, 5.0f, 1, glm::vec3(0.9f)));
  // Overwriting must not replace far points: insert near points after projecting once.
  cache.project(frame, kIdentity);
  cache.insert(frame, near, kIdentity);
  const ProjectionCounts counts = cache.project(frame, kIdentity);
  EXPECT_GT(counts.culled, 0u);
  const PointImage& image = cache.image();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int32_t p = image.point[image.index(x, y)];
      const bool inner = x >= 18 && x < 46 && y >= 18 && y < 46;  // well inside the near square
      const bool outer = x < 14 || x >= 50 || y < 14 || y >= 50;
      if (inner) {
        EXPECT_TRUE(p < 0 || cache.points()[size_t(p)].object == 1) << x << "," << y;
      }
      if (outer) {
        ASSERT_GE(p, 0);
        EXPECT_EQ(cache.points()[size_t(p)].object, 0u);
      }
      if (x >= 16 && x < 48 && y >= 16 && y < 48 && x % 2 == 0 && y % 2 == 0) {
        ASSERT_GE(p, 0);
        EXPECT_EQ(cache.points()[size_t(p)].object, 1u);
      }
    }
}

TEST(PointCache, PointsFollowTheirMovingObject) {
  const int w = 64, h = 64;
  const ViewFrame frame(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  std::vector<glm::mat4> transforms = {glm::mat4(1.0f), glm::mat4(1.0f)};
  PointCache cache(w, h);
  ShadeBatch batch = full_plane(frame, 0.0f);
  for (ShadeResult& r : batch.results) {  // object 1: a square [-1, 1]^2 at z = 2
    const ShadeResult n = plane_hit(frame, r.x, r.y, 2.0f, 1, glm::vec3(1.0f));
    if (std::abs(n.position.x) < 1.0f && std::abs(n.position.y) < 1.0f) r = n;
  }
  cache.insert(frame, batch, transforms);
  cache.project(frame, transforms);
  transforms[1] = glm::translate(glm::mat4(1.0f), glm::vec3(1.5f, 0.5f, 0.0f));
  cache.project(frame, transforms);
  size_t moved = 0;
  for (const CachePoint& p : cache.points()) {
    if (!p.valid || p.object != 1) continue;
    const glm::vec3 world = cache.world_position(p, frame, transforms);
    EXPECT_GE(world.x, 0.5f - 1e-4f);
    EXPECT_LE(world.x, 2.5f + 1e-4f);
    EXPECT_GE(world.y, -0.5f - 1e-4f);
    EXPECT_LE(world.y, 1.5f + 1e-4f);
    const Projection proj = frame.project(world);
    EXPECT_EQ(p.image_id, int(proj.pixel.y) * w + int(proj.pixel.x));
    ++moved;
  }
  EXPECT_GT(moved, 100u);
}

TEST(PointCache, StalePointsExpireAfterTheMaximumAgeFasterOffScreen) {
  const int w = 32, h = 32;
  const ViewFrame frame(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  const ViewFrame away(view_of(camera_at({0, 0, 10}, {0, 0, 20}), w, h));  // looking the other way
  PointCacheSettings s;
  s.max_age = 20, s.offscreen_penalty = 3;
  for (bool offscreen : {false, true}) {
    PointCache cache(w, h, s);
    cache.insert(frame, full_plane(frame, 0.0f), kIdentity);
    int frames = 0;
    while (cache.valid_points() > 0 && frames < 100) {
      cache.project(offscreen ? away : frame, kIdentity);
      ++frames;
      if (!offscreen && frames <= s.max_age) {
        EXPECT_EQ(cache.valid_points(), size_t(w * h));
      }
    }
    // Age grows by 1 (+3 off screen) per frame; points older than max_age are freed.
    EXPECT_EQ(frames, offscreen ? (s.max_age + 4) / 4 : s.max_age + 1);
    cache.project(frame, kIdentity);
    EXPECT_EQ(cache.image().point[0], -1);
  }
}

// A result whose ray hits a nearer surface shows the cached point just behind the hit along it
// hidden, and that point's slot goes to the result. The eye unmoved, the hidden point lies in the
// 3x3 around where the hit lands in the last projection; moved sideways, pixels away along the
// ray's image there (parallax), where the search walks. A ray passing half a pixel beside the
// point (beyond the search's 0.35-pixel radius) leaves it alone.
TEST(PointCache, AResultTakesTheSlotOfTheCachedPointItsRayShowsHidden) {
  const int w = 64, h = 64;
  const ViewFrame last(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  for (const glm::vec2 move : {glm::vec2(0.0f), glm::vec2(0.5f, 0.0f), glm::vec2(-0.3f, 0.4f), glm::vec2(0.1f, -0.6f)})
    for (const float beside : {0.0f, 0.5f}) {
      SCOPED_TRACE(::testing::Message() << "eye moved " << move.x << "," << move.y << ", ray beside by " << beside);
      PointCache cache(w, h);
      cache.insert(last, full_plane(last, 0.0f), kIdentity);  // the far plane, a point per pixel
      cache.project(last, kIdentity);
      const int32_t far = cache.image().point[cache.image().index(40, 30)];
      ASSERT_GE(far, 0);
      const glm::vec3 eye(move.x, move.y, 10.0f);
      const ViewFrame shot(view_of(camera_at(eye, eye - glm::vec3(0, 0, 1)), w, h));
      const glm::vec2 at = shot.project(cache.points()[size_t(far)].local).pixel + beside;
      ShadeBatch batch;
      batch.results.push_back(plane_hit(shot, at.x, at.y, 5.0f, 1, glm::vec3(0.9f)));  // the near surface
      // Where the hit lands in the last projection: beside the far point's pixel when the eye moved.
      const glm::vec2 hit_last = last.project(batch.results[0].position).pixel;
      if (move != glm::vec2(0.0f)) ASSERT_GT(glm::distance(hit_last, glm::vec2(40.5f, 30.5f)), 2.0f);
      cache.insert(shot, batch, kIdentity);
      const CachePoint& slot = cache.points()[size_t(far)];
      if (beside == 0.0f) {
        EXPECT_EQ(cache.hidden_removed(), 1u);
        EXPECT_TRUE(slot.valid);
        EXPECT_EQ(slot.object, 1u);  // the result's
      } else {
        EXPECT_EQ(cache.hidden_removed(), 0u);
        EXPECT_EQ(slot.object, 0u);
      }
    }
}

TEST(PointCache, NewResultsRefineOrOverwriteOldPointsAndChangedShadingAgesTheNeighbourhood) {
  const int w = 32, h = 32;
  const ViewFrame frame(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  PointCache cache(w, h);
  cache.insert(frame, full_plane(frame, 0.0f, 0.5f, 0.5f, glm::vec3(0.5f)), kIdentity);
  cache.project(frame, kIdentity);
  const size_t before = cache.valid_points();
  auto slot_at = [&](int x, int y) { return size_t(cache.image().point[cache.image().index(x, y)]); };
  auto point_at = [&](int x, int y) -> const CachePoint& { return cache.points()[slot_at(x, y)]; };
  auto colour_at = [&](int x, int y) -> const PointColour& { return cache.colours()[slot_at(x, y)]; };
  // The same placement (epoch 0): the result refines the point drawn there (running mean, the
  // point keeps its position), no aging around it.
  ShadeBatch same;
  same.results.push_back(plane_hit(frame, 10.25f, 10.25f, 0.0f, 0, glm::vec3(0.7f)));
  cache.insert(frame, same, kIdentity);
  EXPECT_EQ(cache.valid_points(), before);
  EXPECT_EQ(cache.refined(), 1u);
  cache.project(frame, kIdentity);
  EXPECT_EQ(point_at(10, 10).age, 1);
  EXPECT_EQ(colour_at(10, 10).count, 2);
  EXPECT_NEAR(colour_at(10, 10).color.g, 0.6f, 1e-6f);
  EXPECT_EQ(point_at(11, 10).age, 2);
  EXPECT_EQ(cache.image().region[cache.image().index(10, 10)], 2 + 4 * 2);
  // A much brighter result shaded under a new placement (epoch 1): it replaces the point (its
  // own position, count 1) and the points in the 5x5 around it are aged.
  ShadeBatch changed;
  changed.results.push_back(plane_hit(frame, 20.25f, 20.25f, 0.0f, 0, glm::vec3(2.0f)));
  cache.insert(frame, changed, kIdentity, 1);
  EXPECT_EQ(cache.valid_points(), before);
  cache.project(frame, kIdentity);
  const int penalty = cache.settings().change_penalty;
  EXPECT_EQ(point_at(20, 20).age, 1);
  EXPECT_EQ(colour_at(20, 20).count, 1);
  EXPECT_EQ(cache.image().region[cache.image().index(20, 20)], 1 + 4 * 1);
  EXPECT_EQ(point_at(22, 22).age, 3 + penalty);
  EXPECT_EQ(point_at(23, 20).age, 3);
  // The same colour under the same epoch 1 again refines without aging anything.
  ShadeBatch again;
  again.results.push_back(plane_hit(frame, 20.75f, 20.75f, 0.0f, 0, glm::vec3(2.0f)));
  cache.insert(frame, again, kIdentity, 1);
  cache.project(frame, kIdentity);
  EXPECT_EQ(colour_at(20, 20).count, 2);
  EXPECT_EQ(point_at(22, 22).age, 4 + penalty);
}

// View-dependent shading: a point whose colour is mostly specular, shaded from one eye, gets a
// staleness of (view turned) / (lobe width), asks for a sample the sooner the more the view turned,
// and shows less of its view-dependent part past view_fade_start widths (none past view_fade_end);
// a diffuse point seen from the same turned eye is untouched.
TEST(PointCache, ViewDependentPointsGoStaleWithTheTurnOfTheViewAndDiffuseOnesDoNot) {
  const int w = 16, h = 16;
  const ViewFrame shot(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  ShadeBatch batch;
  ShadeResult glossy = plane_hit(shot, 4.5f, 8.5f, 0.0f, 0, glm::vec3(1.0f));
  glossy.view_dependent = glm::vec3(0.9f), glossy.lobe_width = 0.05f;
  ShadeResult diffuse = plane_hit(shot, 11.5f, 8.5f, 0.0f, 0, glm::vec3(1.0f));
  diffuse.lobe_width = 0.05f;  // a specular lobe, but nothing came through it
  batch.results = {glossy, diffuse};
  const PointCacheSettings settings;
  int last_priority = -1;
  for (const float turn : {0.0f, 0.04f, 0.075f, 0.1f, 0.2f}) {  // radians about the target, ~turn at the points
    PointCache cache(w, h, settings);
    cache.insert(shot, batch, kIdentity);
    const ViewFrame now(view_of(camera_at({10.0f * std::sin(turn), 0, 10.0f * std::cos(turn)}, {0, 0, 0}), w, h));
    cache.project(now, kIdentity);
    const CachePoint& g = cache.points()[0];
    const CachePoint& d = cache.points()[1];
    ASSERT_TRUE(g.valid && d.valid);
    EXPECT_EQ(g.age, 1);
    EXPECT_EQ(d.staleness, 0);
    const glm::vec3 eye_now = now.eye(), eye_then = shot.eye();
    const float staleness =
        std::acos(std::clamp(glm::dot(glm::normalize(eye_now - glossy.position), glm::normalize(eye_then - glossy.position)), -1.0f, 1.0f)) / 0.05f;
    EXPECT_NEAR(float(g.staleness) / 16.0f, staleness, 0.05f) << turn;
    EpiImage epi(w, h);
    cache.fill_epi(epi);
    const uint32_t dc = epi.color[size_t(d.image_id)];
    EXPECT_EQ(sample_age(dc), 1);
    EXPECT_EQ(dc & 0xffffffu, encode_epi_color8(1.0f) * 0x010101u);
    if (float(g.staleness) / 16.0f >= settings.view_fade_end) {
      // 90 % view-dependent and past the fade: not shown at all (its pixel is reconstructed).
      EXPECT_FALSE(has_sample(epi.edge[size_t(g.image_id)])) << turn;
      continue;
    }
    ASSERT_TRUE(has_sample(epi.edge[size_t(g.image_id)])) << turn;
    const uint32_t gc = epi.color[size_t(g.image_id)];
    EXPECT_GT(sample_age(gc), last_priority) << turn;  // rises with the turn
    last_priority = sample_age(gc);
    const float fade = std::clamp((staleness - settings.view_fade_start) / (settings.view_fade_end - settings.view_fade_start), 0.0f, 1.0f);
    const float shown = epi_color8_to_linear()[gc & 0xff];
    EXPECT_NEAR(shown, 1.0f - 0.9f * fade, 0.05f) << turn;  // staleness in 1/16 widths, colour in 8 bits
  }
}

// A glossy dielectric shaded at a grazing angle and then seen face-on: its diffuse part is shown
// times the face-on view's transmission, not the grazing one's (which would show a fifth of it:
// the dark dots of docs/render.md, "Diffuse transmission"); an emitter's colour (transmission 0)
// is shown as shaded; the reference path shows the same words.
TEST(PointCache, DiffusePartIsShownWithTheCurrentViewsTransmission) {
  const int w = 16, h = 16;
  const float grazing = std::acos(0.06f);
  const ViewFrame shot(view_of(camera_at({10.0f * std::sin(grazing), 0, 10.0f * std::cos(grazing)}, {0, 0, 0}), w, h));
  const ViewFrame face_on(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  const float albedo_light = 0.5f;  // the diffuse light before the interface lets it out
  ShadeBatch batch;
  ShadeResult plastic = plane_hit(shot, 8.0f, 8.0f, 0.0f, 0, glm::vec3(0.0f));
  const float then = diffuse_transmission(glm::dot(plastic.normal, glm::normalize(shot.eye() - plastic.position)));
  ASSERT_LT(then, 0.3f);
  plastic.color = glm::vec3(albedo_light * then), plastic.diffuse_transmission = then, plastic.lobe_width = 0.3f;
  ShadeResult lamp = plane_hit(shot, 8.0f, 11.0f, 0.0f, 0, glm::vec3(0.4f));  // emitter: not rescaled
  batch.results = {plastic, lamp};
  uint32_t words[2][2];
  for (const bool reference : {false, true}) {
    PointCacheSettings settings;
    settings.reference_path = reference;
    PointCache cache(w, h, settings);
    cache.insert(shot, batch, kIdentity);
    cache.project(face_on, kIdentity);
    EpiImage epi(w, h);
    cache.fill_epi(epi);
    for (int k = 0; k < 2; ++k) {
      const CachePoint& p = cache.points()[size_t(k)];
      ASSERT_TRUE(p.valid && p.image_id >= 0) << k;
      ASSERT_TRUE(has_sample(epi.edge[size_t(p.image_id)])) << k;
      words[reference][k] = epi.color[size_t(p.image_id)];
    }
    const float now = diffuse_transmission(glm::dot(plastic.normal, glm::normalize(face_on.eye() - plastic.position)));
    EXPECT_NEAR(epi_color8_to_linear()[words[reference][0] & 0xff], albedo_light * now, 0.03f * albedo_light) << reference;
    EXPECT_EQ(words[reference][1] & 0xffffffu, encode_epi_color8(0.4f) * 0x010101u) << reference;
  }
  EXPECT_EQ(words[0][0], words[1][0]);
  EXPECT_EQ(words[0][1], words[1][1]);
}

// Past the fade, a point that is mostly reflection is dropped from the EPI, one that is mostly
// diffuse keeps its diffuse part; both still occupy their pixel (they occlude what lies behind).
TEST(PointCache, StaleMostlyViewDependentPointsAreNotShownMostlyDiffuseOnesLoseTheirHighlight) {
  const int w = 16, h = 16;
  const ViewFrame shot(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  ShadeBatch batch;
  ShadeResult metal = plane_hit(shot, 4.5f, 8.5f, 0.0f, 0, glm::vec3(0.8f));
  metal.view_dependent = glm::vec3(0.6f), metal.lobe_width = 0.02f;  // 75 % reflection
  ShadeResult plastic = plane_hit(shot, 11.5f, 8.5f, 0.0f, 0, glm::vec3(0.8f));
  plastic.view_dependent = glm::vec3(0.2f), plastic.lobe_width = 0.02f;  // 25 % highlight
  batch.results = {metal, plastic};
  PointCache cache(w, h);
  cache.insert(shot, batch, kIdentity);
  const ViewFrame now(view_of(camera_at({10.0f * std::sin(0.3f), 0, 10.0f * std::cos(0.3f)}, {0, 0, 0}), w, h));
  cache.project(now, kIdentity);
  const CachePoint& m = cache.points()[0];
  const CachePoint& p = cache.points()[1];
  ASSERT_GE(float(m.staleness) / 16.0f, cache.settings().view_fade_end);
  ASSERT_GE(m.image_id, 0);
  ASSERT_GE(p.image_id, 0);
  EXPECT_EQ(cache.image().point[size_t(m.image_id)], 0);  // still drawn, as an occluder
  EpiImage epi(w, h);
  cache.fill_epi(epi);
  EXPECT_FALSE(has_sample(epi.edge[size_t(m.image_id)]));
  ASSERT_TRUE(has_sample(epi.edge[size_t(p.image_id)]));
  EXPECT_NEAR(epi_color8_to_linear()[epi.color[size_t(p.image_id)] & 0xff], 0.6f, 0.02f);  // diffuse part only

  // A lower threshold keeps the metal too (faded to its diffuse part).
  PointCacheSettings keep;
  keep.view_drop_share = 1.0f;
  PointCache kept(w, h, keep);
  kept.insert(shot, batch, kIdentity);
  kept.project(now, kIdentity);
  kept.fill_epi(epi);
  ASSERT_TRUE(has_sample(epi.edge[size_t(kept.points()[0].image_id)]));
  EXPECT_NEAR(epi_color8_to_linear()[epi.color[size_t(kept.points()[0].image_id)] & 0xff], 0.2f, 0.02f);
}

// A point is shaded on the side of its surface that faced the eye; seen from the other side
// (the camera crossed its plane, or it lies on the far side of a closed object) it is not drawn.
TEST(PointCache, PointsSeenFromBehindTheirSurfaceAreNotDrawn) {
  const int w = 16, h = 16;
  const ViewFrame front(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  ShadeBatch batch;
  batch.results = {plane_hit(front, 8.5f, 8.5f, 0.0f, 0, glm::vec3(0.5f))};
  // The plane turned by object transforms: 80 degrees keeps its front towards the eye, 100 turns it away.
  for (const float degrees : {0.0f, 80.0f, 100.0f, 180.0f}) {
    PointCache cache(w, h);
    cache.insert(front, batch, kIdentity);
    std::vector<glm::mat4> turned(4, glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::vec3(0, 1, 0)));
    const ProjectionCounts counts = cache.project(front, turned);
    const bool away = degrees > 90.0f;
    EXPECT_EQ(counts.back_facing, away ? 1u : 0u) << degrees;
    EXPECT_EQ(counts.drawn, away ? 0u : 1u) << degrees;
  }
  // The camera moved behind the plane.
  PointCache cache(w, h);
  cache.insert(front, batch, kIdentity);
  const ViewFrame behind(view_of(camera_at({0.5f, 0, -10}, {0, 0, 0}), w, h));
  EXPECT_EQ(cache.project(behind, kIdentity).drawn, 0u);
  EXPECT_EQ(cache.project(front, kIdentity).drawn, 1u);
}

// Convergence at rest: results on the same point under one placement are averaged; the priority
// age the EPI sees falls for a point whose results agree and rises for one whose results scatter.
TEST(PointCache, RefinedPointsAverageTheirResultsAndAskForSamplesByTheirUncertainty) {
  const int w = 8, h = 8;
  const ViewFrame frame(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  PointCache cache(w, h);
  cache.insert(frame, full_plane(frame, 0.0f, 0.5f, 0.5f, glm::vec3(0.5f)), kIdentity);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> noise(0.0f, 1.0f);
  double sum = 0.5;
  for (int k = 0; k < 50; ++k) {
    cache.project(frame, kIdentity);
    ShadeBatch batch;
    batch.results.push_back(plane_hit(frame, 2.3f, 2.6f, 0.0f, 0, glm::vec3(0.5f)));  // agrees
    const float v = noise(rng);
    sum += v;
    batch.results.push_back(plane_hit(frame, 5.4f, 5.7f, 0.0f, 0, glm::vec3(v)));  // scatters
    cache.insert(frame, batch, kIdentity);
  }
  for (int k = 0; k < 20; ++k) cache.project(frame, kIdentity);  // both now 20 frames old
  const size_t calm_slot = size_t(cache.image().point[cache.image().index(2, 2)]);
  const size_t noisy_slot = size_t(cache.image().point[cache.image().index(5, 5)]);
  const CachePoint& calm = cache.points()[calm_slot];
  EXPECT_EQ(cache.colours()[calm_slot].count, 51);
  EXPECT_EQ(cache.colours()[noisy_slot].count, 51);
  EXPECT_NEAR(cache.colours()[noisy_slot].color.r, sum / 51.0, 1e-4);
  EXPECT_EQ(calm.age, 20);
  EpiImage epi(w, h);
  cache.fill_epi(epi);
  const int calm_age = sample_age(epi.color[size_t(cache.image().index(2, 2))]);
  const int noisy_age = sample_age(epi.color[size_t(cache.image().index(5, 5))]);
  const int single_age = sample_age(epi.color[size_t(cache.image().index(0, 0))]);  // one result, older
  EXPECT_EQ(calm_age, 5);  // 20 x 1/4: converged
  EXPECT_GT(noisy_age, calm_age);
  EXPECT_EQ(single_age, cache.points()[size_t(cache.image().point[0])].age);  // factor 1
}

// Results of different effort (ShadeRequest::effort) refine a point as a weighted mean: a result of
// effort w counts as w results of effort 1 (the mean and its luminance spread against a brute-force
// weighted mean and sum of weighted squared deviations), and one result of effort w asks for
// samples as one whose error is 1/sqrt(w) of a single result's.
TEST(PointCache, ResultsOfHigherEffortWeighMoreInTheRunningMean) {
  const int w = 8, h = 8;
  const ViewFrame frame(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  PointCache cache(w, h);
  ShadeBatch first = full_plane(frame, 0.0f, 0.5f, 0.5f, glm::vec3(0.5f));
  for (ShadeResult& r : first.results) r.effort = 4;
  cache.insert(frame, first, kIdentity);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  std::uniform_int_distribution<int> effort(1, 8);
  std::vector<double> values{0.5}, weights{4.0};
  for (int k = 0; k < 40; ++k) {
    cache.project(frame, kIdentity);
    ShadeBatch batch;
    const float v = value(rng);
    batch.results.push_back(plane_hit(frame, 3.4f, 4.6f, 0.0f, 0, glm::vec3(v)));
    batch.results.back().effort = uint8_t(effort(rng));
    values.push_back(v), weights.push_back(batch.results.back().effort);
    cache.insert(frame, batch, kIdentity);
  }
  cache.project(frame, kIdentity);
  const size_t slot = size_t(cache.image().point[cache.image().index(3, 4)]);
  const PointColour& c = cache.colours()[slot];
  double total = 0.0, mean = 0.0, m2 = 0.0;
  for (size_t i = 0; i < values.size(); ++i) total += weights[i], mean += weights[i] * values[i];
  mean /= total;
  for (size_t i = 0; i < values.size(); ++i) m2 += weights[i] * (values[i] - mean) * (values[i] - mean);
  EXPECT_EQ(c.count, 41);
  EXPECT_EQ(c.weight, uint16_t(total));
  EXPECT_NEAR(c.color.r, mean, 1e-4);
  EXPECT_NEAR(c.luminance_m2, m2 * 1.0, 1e-3 * m2);  // a grey's luminance is its level
  // The plain mean would be off by more than that (the test can tell the two apart).
  double plain = 0.0;
  for (double v : values) plain += v / double(values.size());
  EXPECT_GT(std::abs(plain - mean), 1e-3);

  // One result of effort 4 (the rest of the plane): half a single result's error, so its
  // sampling age grows at half the rate of an effort-1 point's.
  PointCache single(w, h);
  ShadeBatch one = full_plane(frame, 0.0f, 0.5f, 0.5f, glm::vec3(0.5f));
  one.results[0].effort = 4;
  single.insert(frame, one, kIdentity);
  for (int k = 0; k < 20; ++k) single.project(frame, kIdentity);
  EpiImage epi(w, h);
  single.fill_epi(epi);
  EXPECT_EQ(sample_age(epi.color[0]), 10);  // 20 x 1/2
  EXPECT_EQ(sample_age(epi.color[1]), 20);  // effort 1: factor 1
}

// With the cloud full, new results overwrite the oldest points, not the next slots in round-robin
// order: slots 0..255 are refreshed in place (same surface), 256..294 stay old, the cursor is at 0.
TEST(PointCache, AFullCloudEvictsItsOldestPointsNeverThoseOfThisFrame) {
  const int w = 16, h = 16;
  const ViewFrame frame(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  PointCache cache(w, h);
  const size_t capacity = cache.capacity();
  ASSERT_EQ(capacity, 295u);
  cache.insert(frame, full_plane(frame, 0.0f), kIdentity);  // slots 0..255, drawn (region 10 < 15)
  ShadeBatch extra;
  for (size_t k = 0; k < capacity - size_t(w * h); ++k)
    extra.results.push_back(plane_hit(frame, float(k % w) + 0.9f, float(k / w) + 0.9f, 0.0f, 0, glm::vec3(0.5f)));
  cache.insert(frame, extra, kIdentity);  // slots 256..294, behind in the z-buffer order
  ASSERT_EQ(cache.valid_points(), capacity);
  for (int f = 0; f < 20; ++f) cache.project(frame, kIdentity);
  cache.insert(frame, full_plane(frame, 0.0f), kIdentity);  // refreshes the drawn points in place
  cache.project(frame, kIdentity);
  ASSERT_EQ(cache.valid_points(), capacity);

  auto ages = [&] {
    std::vector<int> a;
    for (const CachePoint& p : cache.points()) a.push_back(p.age);
    return a;
  };
  const std::vector<int> before = ages();
  ShadeBatch other;  // another object, behind: replaces nothing
  for (size_t k = 0; k < 30; ++k)
    other.results.push_back(plane_hit(frame, float(k % w) + 0.5f, float(k / w) + 0.5f, -1.0f, 1, glm::vec3(0.2f)));
  cache.insert(frame, other, kIdentity);
  std::vector<size_t> evicted;
  for (size_t i = 0; i < capacity; ++i)
    if (cache.points()[i].object == 1) evicted.push_back(i);
  ASSERT_EQ(evicted.size(), other.results.size());
  int youngest_evicted = 1 << 30, oldest_left = 0;
  double evicted_mean = 0.0, cloud_mean = 0.0;
  for (size_t i = 0; i < capacity; ++i) {
    cloud_mean += before[i] / double(capacity);
    if (cache.points()[i].object == 1) youngest_evicted = std::min(youngest_evicted, before[i]), evicted_mean += before[i];
    else oldest_left = std::max(oldest_left, before[i]);
  }
  evicted_mean /= double(evicted.size());
  EXPECT_GE(youngest_evicted, oldest_left);
  EXPECT_GE(evicted_mean, cloud_mean);

  // A second batch in the same frame takes the remaining old points first, then younger ones,
  // never the first batch's (not yet projected).
  const size_t old_left = size_t(std::count_if(cache.points().begin(), cache.points().end(),
                                               [](const CachePoint& p) { return p.object == 0 && p.age >= 20; }));
  ASSERT_EQ(old_left, 9u);
  ShadeBatch more;
  for (size_t k = 0; k < 14; ++k)
    more.results.push_back(plane_hit(frame, float(k) + 0.5f, 8.5f, -2.0f, 2, glm::vec3(0.1f)));
  cache.insert(frame, more, kIdentity);
  size_t first_batch_left = 0;
  for (size_t i : evicted) first_batch_left += cache.points()[i].object == 1;
  EXPECT_EQ(first_batch_left, evicted.size());
  EXPECT_EQ(std::count_if(cache.points().begin(), cache.points().end(),
                          [](const CachePoint& p) { return p.object == 0 && p.age >= 20; }),
            0);
}

TEST(PointCache, BackgroundPointsStayAtTheirDirectionWhenTheCameraTranslates) {
  const int w = 32, h = 32;
  const ViewFrame frame(view_of(camera_at({0, 0, 10}, {0, 0, 0}), w, h));
  ShadeBatch batch;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      ShadeResult r;
      r.x = x + 0.5f, r.y = y + 0.5f, r.hit = false, r.color = glm::vec3(0.1f);
      batch.results.push_back(r);
    }
  PointCache cache(w, h);
  cache.insert(frame, batch, kIdentity);
  const ViewFrame shifted(view_of(camera_at({3, 2, 10}, {3, 2, 0}), w, h));
  const ProjectionCounts counts = cache.project(shifted, kIdentity);
  EXPECT_EQ(counts.drawn, size_t(w * h));
  for (int i = 0; i < w * h; ++i) EXPECT_EQ(cache.points()[size_t(cache.image().point[size_t(i)])].image_id, i);
}

}  // namespace
}  // namespace epi::render

// The frame loop on a small analytic scene (a lit plane, a box on it, a point light):
// determinism of --sync, the exact budget, error falling with a still camera, moving objects,
// the asynchronous shader, and the staged reconstructor against core/epi's oracle.
#include <algorithm>
#include <array>
#include <atomic>
#include <condition_variable>
#include <future>
#include <mutex>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "epi/reconstruct.h"
#include "render/point_cache_detail.h"
#include "render/renderer.h"
#include "shade/render_image.h"
#include "test_scenes.h"

namespace epi::render {
namespace {

using test::plane_and_box;

struct Fixture {
  Scene scene = plane_and_box();
  RayScene ray_scene{scene};
  Shader shader{ray_scene, ShaderSettings{}};
};

double mean_abs_error(const RgbImage& a, const RgbImage& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
  return sum / double(a.pixels.size());
}

FrameSettings small_settings(RenderMode mode, bool sync = true) {
  FrameSettings s;
  s.mode = mode, s.width = 64, s.height = 64, s.sample_budget = 0.05, s.sync = sync, s.seed = 3;
  return s;
}

TEST(FrameLoop, SyncRunsAreDeterministicForASeed) {
  for (RenderMode mode : {RenderMode::epi, RenderMode::rendercache}) {
    std::vector<RgbImage> runs;
    for (uint64_t seed : {3u, 3u, 4u}) {
      Fixture f;
      FrameSettings s = small_settings(mode);
      s.seed = seed;
      s.predict_share = 0.25f;  // (off by default)
      FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
      Camera camera = f.scene.cameras[0];
      for (int k = 0; k < 6; ++k) {
        camera.eye.x += 0.05f;  // moving: predictive sampling too
        renderer.render(camera);
      }
      runs.push_back(renderer.render(camera));
    }
    EXPECT_EQ(runs[0].pixels, runs[1].pixels);
    EXPECT_NE(runs[0].pixels, runs[2].pixels);
  }
}

// A renderer built with another renderer's edge finder (as the viewer's session does when a
// setting such as the window size rebuilds the loop) renders the same frames as one that builds
// its own: images, priorities and edge pieces bit for bit, the camera and the lamp moving (the
// finder's cached shadow edges carried over). A finder built for other settings is refused.
TEST(FrameLoop, AReusedEdgeFinderGivesTheSameFrames) {
  Fixture f;
  FrameSettings first = small_settings(RenderMode::epi);
  auto finder = std::make_shared<edges::SceneEdgeFinder>(f.scene, *FrameRenderer::edge_finder_settings(first));
  auto run = [&](FrameRenderer& renderer, std::vector<float>& image, std::vector<Segment>& segments) {
    Camera camera = f.scene.cameras[0];
    std::vector<glm::vec3> lamp = {f.scene.punctual_lights[0].position};
    for (int k = 0; k < 6; ++k) {
      camera.eye.x += 0.05f, lamp[0].y += 0.1f;
      const RgbImage& frame = renderer.render(camera, {}, lamp);
      image.insert(image.end(), frame.pixels.begin(), frame.pixels.end());
      image.insert(image.end(), renderer.priority().begin(), renderer.priority().end());
      segments.insert(segments.end(), renderer.segments().begin(), renderer.segments().end());
    }
  };
  std::vector<float> unused_image;
  std::vector<Segment> unused_segments;
  {
    FrameRenderer before(f.scene, f.ray_scene, f.shader, first, finder);
    run(before, unused_image, unused_segments);
    EXPECT_EQ(before.edge_finder(), finder.get());
  }
  FrameSettings second = first;
  second.width = 48, second.height = 40, second.sample_budget = 0.08;
  std::vector<float> reused_image, own_image;
  std::vector<Segment> reused_segments, own_segments;
  {
    Fixture g;  // a fresh copy of the scene and its placement (`before` moved the lamp in f's)
    FrameRenderer own(g.scene, g.ray_scene, g.shader, second);
    run(own, own_image, own_segments);
  }
  Fixture h;  // another fresh copy: the finder was built from an identical scene
  FrameRenderer reused(h.scene, h.ray_scene, h.shader, second, finder);
  run(reused, reused_image, reused_segments);
  EXPECT_EQ(reused_image, own_image);
  ASSERT_EQ(reused_segments.size(), own_segments.size());
  for (size_t k = 0; k < own_segments.size(); ++k) {
    const Segment &a = reused_segments[k], &b = own_segments[k];
    ASSERT_TRUE(a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1) << k;
  }
  EXPECT_FALSE(own_segments.empty());
  FrameSettings no_shadows = first;
  no_shadows.shadow_edges = false;  // a finder without receiver trees
  EXPECT_THROW(FrameRenderer(f.scene, f.ray_scene, f.shader, no_shadows, finder), std::invalid_argument);
}

// The loop's parallel stages (filter_depth, project_edges, rasterization and edge pixels in
// bands, the masks, the dither's bands, predictive occupancy) give the same frames under 1 and
// 4 threads: images, priorities, edge pieces and boundary masks bit for bit, camera moving.
TEST(FrameLoop, SyncFramesAreTheSameWhateverTheThreadCount) {
  for (RenderMode mode : {RenderMode::epi, RenderMode::rendercache}) {
    struct Run {
      std::vector<float> image, priority;
      std::vector<Segment> segments;
      std::vector<uint8_t> masks;
    };
    std::vector<Run> runs;
    for (const int threads : {1, 4}) {
      tbb::task_arena arena(threads);
      arena.execute([&] {
        Fixture f;
        FrameSettings s = small_settings(mode);
        s.width = 150, s.height = 110;
        FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
        Camera camera = f.scene.cameras[0];
        Run run;
        for (int k = 0; k < 8; ++k) {
          camera.eye.x += 0.06f, camera.eye.y += 0.02f;
          const RgbImage& image = renderer.render(camera);
          run.image.insert(run.image.end(), image.pixels.begin(), image.pixels.end());
          run.priority.insert(run.priority.end(), renderer.priority().begin(), renderer.priority().end());
          run.segments.insert(run.segments.end(), renderer.segments().begin(), renderer.segments().end());
          const BoundaryMasks& m = renderer.masks();
          for (const auto* plane : {&m.top, &m.left, &m.centre_h, &m.centre_v}) run.masks.insert(run.masks.end(), plane->begin(), plane->end());
        }
        runs.push_back(std::move(run));
      });
    }
    EXPECT_EQ(runs[0].image, runs[1].image);
    EXPECT_EQ(runs[0].priority, runs[1].priority);
    ASSERT_EQ(runs[0].segments.size(), runs[1].segments.size());
    for (size_t k = 0; k < runs[0].segments.size(); ++k) {
      const Segment &a = runs[0].segments[k], &b = runs[1].segments[k];
      ASSERT_TRUE(a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1) << k;
    }
    EXPECT_EQ(runs[0].masks, runs[1].masks);
    if (mode == RenderMode::epi) {
      EXPECT_GT(runs[0].segments.size(), 8u);
    }
  }
}

TEST(FrameLoop, SyncShadesExactlyTheBudgetEveryFrame) {
  for (const bool as_async : {false, true}) {
    Fixture f;
    FrameSettings s = small_settings(RenderMode::epi);
    s.sync_as_async = as_async;  // the last frame's requests, chosen for its view: still the budget
    s.predict_share = 0.25f;     // predicted requests are part of the budget
    FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
    Camera camera = f.scene.cameras[0];
    const size_t budget = size_t(std::round(0.05 * 64 * 64));
    for (int k = 0; k < 5; ++k) {
      camera.eye.x += 0.3f, camera.target.x += 0.3f;  // a pan: gaps open on the right
      renderer.render(camera);
      EXPECT_EQ(renderer.stats().samples, budget) << as_async << " " << k;
      EXPECT_EQ(renderer.stats().requested, budget) << as_async << " " << k;
      EXPECT_LE(renderer.stats().predicted, budget / 4);
      if (k > 0) {
        EXPECT_GT(renderer.stats().predicted, 0u);  // the camera moves
      }
      const ClassCounts& c = renderer.stats().pixels;
      EXPECT_EQ(c.empty + c.simple + c.complex, 64 * 64);
    }
  }
}

// sync_as_async: deterministic for a seed, the same under 1 and 4 threads, and not the plain sync
// loop (its requests are made for the view that chose them and shaded a frame later).
TEST(FrameLoop, SyncAsAsyncIsDeterministicAndNotThePlainSyncLoop) {
  std::vector<std::vector<float>> runs;
  for (const auto& [as_async, threads] : {std::pair{true, 1}, std::pair{true, 4}, std::pair{false, 4}}) {
    tbb::task_arena arena(threads);
    arena.execute([&, as_async = as_async] {
      Fixture f;
      FrameSettings s = small_settings(RenderMode::epi);
      s.sync_as_async = as_async;
      FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
      Camera camera = f.scene.cameras[0];
      std::vector<float> frames;
      for (int k = 0; k < 6; ++k) {
        camera.eye.x += 0.06f;
        const RgbImage& image = renderer.render(camera);
        frames.insert(frames.end(), image.pixels.begin(), image.pixels.end());
      }
      runs.push_back(std::move(frames));
    });
  }
  EXPECT_TRUE(runs[0] == runs[1]);
  EXPECT_TRUE(runs[0] != runs[2]);
}

// FrameSettings::trace_ahead: a request is traced from the eye of the frame that draws its result.
// A pan at constant speed makes the extrapolation exact, so every point a frame integrated (age 1
// after its projection) was shaded from this frame's eye: sync (lag 0) with or without the
// setting, sync_as_async (lag 1) only with it; without it, from the eye a frame before.
TEST(FrameLoop, RequestsAreTracedFromTheEyeOfTheFrameThatDrawsThem) {
  for (const bool as_async : {false, true})
    for (const bool ahead : {true, false}) {
      Fixture f;
      FrameSettings s = small_settings(RenderMode::epi);
      s.sync_as_async = as_async, s.trace_ahead = ahead;
      s.predict_share = 0.0f;    // predicted requests have views of their own
      s.cache.refine = false;    // a refined point keeps the direction of its first result
      FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
      Camera camera = f.scene.cameras[0];
      for (int k = 0; k < 6; ++k) {
        camera.eye.x += 0.1f, camera.target.x += 0.1f;
        renderer.render(camera);
      }
      EXPECT_EQ(renderer.stats().result_lag, as_async ? 1.0 : 0.0);
      size_t fresh = 0, from_this_eye = 0;
      for (const CachePoint& p : renderer.cache().points()) {
        if (!p.valid || p.age != 1 || p.object == kNone) continue;
        const glm::vec3 world = glm::vec3(f.ray_scene.object_to_world(p.object) * glm::vec4(p.local, 1.0f));
        const float turned = std::acos(std::clamp(glm::dot(detail::unpack_unit(p.view), glm::normalize(camera.eye - world)), -1.0f, 1.0f));
        ++fresh, from_this_eye += turned < 2e-3f;
      }
      ASSERT_GT(fresh, 100u);
      if (!as_async || ahead) {
        EXPECT_EQ(from_this_eye, fresh) << as_async << ahead;
      } else {
        EXPECT_EQ(from_this_eye, 0u);
      }
    }
}

// A camera moving near the ray tracer's range: the extrapolated cameras (predicted requests,
// requests traced ahead) would leave it; the loop keeps the current camera instead of throwing.
TEST(FrameLoop, ACameraMovingAtTheEdgeOfTheRangeIsNotExtrapolatedBeyondIt) {
  for (const bool as_async : {false, true}) {
    Fixture f;
    FrameSettings s = small_settings(RenderMode::epi);
    s.sync_as_async = as_async;
    FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
    Camera camera = f.scene.cameras[0];
    for (const float x : {5e17f, 7e17f, 9e17f, 9.9e17f}) {
      camera.eye = {x, 1.0f, 5.0f}, camera.target = {x, 0.0f, 0.0f};
      EXPECT_NO_THROW(renderer.render(camera)) << as_async << " " << x;
    }
  }
}

TEST(FrameLoop, WithAStillCameraTheErrorKeepsFalling) {
  Fixture f;
  View view;
  view.camera = f.scene.cameras[0], view.width = 64, view.height = 64;
  const RgbImage reference = render_image(f.shader, view, 16);
  for (RenderMode mode : {RenderMode::epi, RenderMode::rendercache}) {
    FrameSettings s = small_settings(mode);
    s.sample_budget = 0.01;
    FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
    std::vector<double> errors;
    for (int k = 0; k < 24; ++k) {
      const RgbImage& image = renderer.render(view.camera);
      if (k % 4 == 0) errors.push_back(mean_abs_error(image, reference));
    }
    for (size_t k = 1; k < errors.size(); ++k) EXPECT_LT(errors[k], errors[k - 1] * 1.02) << "step " << k;
    EXPECT_LT(errors.back(), 0.6 * errors.front());
  }
}

// The box slides away; after a bounded number of frames the image where it stood matches the
// reference of the new placement (no stale box points, and the floor re-shaded).
TEST(FrameLoop, AMovedObjectLeavesNoStalePoints) {
  Fixture f;
  FrameSettings s = small_settings(RenderMode::epi);
  s.sample_budget = 0.1;
  FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
  const Camera camera = f.scene.cameras[0];
  std::vector<glm::mat4> transforms = {glm::mat4(1.0f), glm::mat4(1.0f)};
  for (int k = 0; k < 15; ++k) renderer.render(camera, transforms);
  // Where the box is now (pixels showing box points).
  std::vector<uint8_t> box_pixels(64 * 64, 0);
  for (size_t i = 0; i < box_pixels.size(); ++i) {
    const int32_t p = renderer.cache().image().point[i];
    box_pixels[i] = p >= 0 && renderer.cache().points()[size_t(p)].object == 1;
  }
  transforms[1] = glm::translate(glm::mat4(1.0f), glm::vec3(3.5f, -1.0f, 0.0f));
  const int bound = 30;
  for (int k = 0; k < bound; ++k) renderer.render(camera, transforms);
  Fixture moved;  // the reference for the new placement
  moved.ray_scene.set_object_transform(1, transforms[1]);
  View view;
  view.camera = camera, view.width = 64, view.height = 64;
  const RgbImage reference = render_image(moved.shader, view, 16);
  const RgbImage& image = renderer.render(camera, transforms);
  size_t old_pixels = 0, stale = 0;
  double error = 0.0;
  const ViewFrame frame(view);
  for (size_t i = 0; i < box_pixels.size(); ++i) {
    const RayHit hit = moved.ray_scene.intersect(frame.ray(float(i % 64) + 0.5f, float(i / 64) + 0.5f));
    if (!box_pixels[i] || !hit.hit || hit.object != 0) continue;  // where the box was and the floor is now
    ++old_pixels;
    const int32_t p = renderer.cache().image().point[i];
    if (p >= 0 && renderer.cache().points()[size_t(p)].object == 1) ++stale;
    for (int c = 0; c < 3; ++c) error += std::abs(image.pixels[i * 3 + size_t(c)] - reference.pixels[i * 3 + size_t(c)]);
  }
  ASSERT_GT(old_pixels, 100u);
  EXPECT_EQ(stale, 0u);
  EXPECT_LT(error / double(old_pixels * 3), 0.05);
}

// Random edges and samples: the staged schedule (the renderer's timed path) equals core/epi's
// oracle bit for bit.
TEST(StagedReconstructor, EqualsTheOracleBitForBit) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    const int w = 20 + int(rng() % 50), h = 10 + int(rng() % 40);
    EpiImage epi(w, h);
    const bool centre = trial % 2 == 0;
    BoundaryMasks masks(w, h, centre);
    std::vector<Segment> segments;
    for (int k = 0; k < 12; ++k) segments.push_back({unit(rng) * w, unit(rng) * h, unit(rng) * w, unit(rng) * h});
    rasterize_edges(masks, segments);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (unit(rng) < 0.3) {
          const float rgb[3] = {float(unit(rng)), float(unit(rng)), float(unit(rng))};
          epi.set_sample(x, y, unit(rng), unit(rng), rgb, int(rng() % 40));
        }
    for (Filter filter : {Filter::epi, Filter::rendercache}) {
      ReconstructSettings s;
      s.filter = filter;
      s.complex_filter = centre;
      const Reconstruction expected = reconstruct_oracle(epi, masks, s);
      Reconstructor staged;
      Reconstruction got;
      ReconstructTimes times;
      staged.staged(epi, masks, s, got, times);
      staged.staged(epi, masks, s, got, times);  // buffers reused
      EXPECT_EQ(got.image.pixels, expected.image.pixels);
      EXPECT_EQ(got.priority, expected.priority);
      EXPECT_EQ(got.cache, expected.cache);
      EXPECT_EQ(got.edge, expected.edge);
      EXPECT_EQ(got.counts.simple, expected.counts.simple);
      EXPECT_EQ(got.counts.complex, expected.counts.complex);
    }
  }
}

}  // namespace
}  // namespace epi::render

namespace epi::render {
namespace {

// Under a directional light, sliding the box by (dx, dy, 0) slides its shadow on the ground by the
// same amount: every shadow edge after the move is a shadow edge from before, translated. Moving
// only the camera recomputes no shadow edges.
TEST(FrameLoop, ShadowEdgesMoveWithTheirObject) {
  Scene scene = plane_and_box();
  scene.punctual_lights.clear();
  PunctualLight sun;
  sun.name = "sun", sun.type = LightType::directional;
  sun.direction = glm::normalize(glm::vec3(0.4f, 0.3f, -1.0f)), sun.intensity = glm::vec3(3.0f);
  scene.punctual_lights.push_back(sun);
  RayScene ray_scene(scene);
  Shader shader(ray_scene, ShaderSettings{});
  FrameRenderer renderer(scene, ray_scene, shader, small_settings(RenderMode::epi));
  Camera camera = scene.cameras[0];
  std::vector<glm::mat4> transforms = {glm::mat4(1.0f), glm::mat4(1.0f)};
  for (int k = 0; k < 6; ++k) renderer.render(camera, transforms);
  auto shadow_edges = [&] {
    std::vector<edges::SceneEdge> out;
    for (const edges::SceneEdge& e : renderer.scene_edges())
      if (e.kind == edges::EdgeKind::umbral || e.kind == edges::EdgeKind::penumbral || e.kind == edges::EdgeKind::shadow)
        out.push_back(e);
    return out;
  };
  const std::vector<edges::SceneEdge> before = shadow_edges();
  ASSERT_GT(before.size(), 4u);
  const size_t recomputed = renderer.edge_finder()->pairs_recomputed();
  camera.eye.x += 0.3f;
  renderer.render(camera, transforms);
  EXPECT_EQ(renderer.edge_finder()->pairs_recomputed(), recomputed);  // the camera alone moved

  const glm::dvec3 offset(0.7, -0.4, 0.0);
  transforms[1] = glm::translate(glm::mat4(1.0f), glm::vec3(offset));
  renderer.render(camera, transforms);
  EXPECT_GT(renderer.edge_finder()->pairs_recomputed(), recomputed);
  const std::vector<edges::SceneEdge> after = shadow_edges();
  ASSERT_GT(after.size(), 4u);
  // Edges may be split differently: compare points along them.
  auto on_some_edge = [](const std::vector<edges::SceneEdge>& list, uint32_t object, glm::dvec3 p) {
    return std::any_of(list.begin(), list.end(), [&](const edges::SceneEdge& e) {
      if (e.object != object) return false;
      const glm::dvec3 ab = e.b - e.a;
      const double t = std::clamp(glm::dot(p - e.a, ab) / std::max(glm::dot(ab, ab), 1e-30), 0.0, 1.0);
      return glm::length(p - (e.a + t * ab)) < 1e-4;
    });
  };
  for (const edges::SceneEdge& e : after)
    for (double t : {0.0, 0.3, 0.7, 1.0}) {
      const glm::dvec3 p = glm::mix(e.a, e.b, t);
      EXPECT_TRUE(on_some_edge(before, e.object, p - offset)) << "after (" << p.x << "," << p.y << "," << p.z << ")";
    }
  for (const edges::SceneEdge& e : before)
    for (double t : {0.0, 0.3, 0.7, 1.0}) {
      const glm::dvec3 p = glm::mix(e.a, e.b, t);
      EXPECT_TRUE(on_some_edge(after, e.object, p + offset)) << "before (" << p.x << "," << p.y << "," << p.z << ")";
    }
}

}  // namespace
}  // namespace epi::render

namespace epi::render {
namespace {

TEST(FrameLoop, TiledAndStagedReconstructionGiveTheSameFrames) {
  std::vector<RgbImage> runs;
  for (bool staged : {true, false}) {
    Fixture f;
    FrameSettings s = small_settings(RenderMode::epi);
    s.stage_timings = staged;
    FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
    Camera camera = f.scene.cameras[0];
    for (int k = 0; k < 5; ++k) {
      camera.eye.y += 0.05f;
      renderer.render(camera);
    }
    runs.push_back(renderer.render(camera));
  }
  EXPECT_EQ(runs[0].pixels, runs[1].pixels);
}

}  // namespace
}  // namespace epi::render

namespace epi::render {
namespace {

// Asynchronous shading while the box slides: once it stops, every box point lies on the box where
// it now is (results shaded for an old placement were placed with their shot's transforms).
TEST(FrameLoop, AsyncResultsFromAnOldPlacementMoveWithTheirObject) {
  Fixture f;
  FrameSettings s = small_settings(RenderMode::epi, false);
  s.sample_budget = 0.1;
  FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
  const Camera camera = f.scene.cameras[0];
  std::vector<glm::mat4> transforms = {glm::mat4(1.0f), glm::mat4(1.0f)};
  for (int k = 0; k < 30; ++k) {
    transforms[1] = glm::translate(glm::mat4(1.0f), glm::vec3(0.05f * float(k), 0.0f, 0.0f));
    renderer.render(camera, transforms);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  for (int k = 0; k < 20; ++k) {
    renderer.render(camera, transforms);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  // The reference geometry: the box at its final place.
  Fixture moved;
  moved.ray_scene.set_object_transform(1, transforms[1]);
  View view;
  view.camera = camera, view.width = 64, view.height = 64;
  const ViewFrame frame(view);
  size_t box_points = 0, misplaced = 0;
  for (const CachePoint& p : renderer.cache().points()) {
    if (!p.valid || p.object != 1) continue;
    const glm::vec3 world = renderer.cache().world_position(p, frame, transforms);
    const glm::vec3 local = glm::vec3(glm::inverse(transforms[1]) * glm::vec4(world, 1.0f));
    // On the surface of the box [-0.8, 0.8]^2 x [0, 1.6] (object space).
    const float inside = std::max({std::abs(local.x) - 0.8f, std::abs(local.y) - 0.8f, std::abs(local.z - 0.8f) - 0.8f});
    ++box_points;
    misplaced += std::abs(inside) > 1e-3f;
  }
  EXPECT_GT(box_points, 50u);
  EXPECT_EQ(misplaced, 0u);
}

}  // namespace
}  // namespace epi::render

namespace epi::render {
namespace {

// A steady pan: with predictive sampling the strip entering the view already holds points when
// it appears; without it, the strip waits for the priority image to ask for it.
TEST(FrameLoop, PredictiveSamplingFillsTheStripThatOpens) {
  size_t filled[2] = {0, 0};
  for (int predict = 0; predict < 2; ++predict) {
    Fixture f;
    FrameSettings s = small_settings(RenderMode::rendercache);
    s.predict_share = predict ? 0.25f : 0.0f;
    FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
    Camera camera = f.scene.cameras[0];
    for (int k = 0; k < 16; ++k) {
      camera.eye.x += 0.4f, camera.target.x += 0.4f;  // pan right ~4 px a frame: new columns enter on the right
      renderer.render(camera);
      if (k < 6) continue;
      const PointImage& image = renderer.cache().image();
      for (int y = 0; y < 64; ++y)
        for (int x = 56; x < 64; ++x) filled[predict] += image.point[image.index(x, y)] >= 0;
    }
  }
  EXPECT_GT(double(filled[1]), 1.1 * double(filled[0])) << filled[0] << " vs " << filled[1];
}

}  // namespace
}  // namespace epi::render

namespace epi::render {
namespace {

// A shader held by the test (the shading thread blocks before its first slice until released):
// frames must keep returning. They run on a std::async so that a regression (a frame waiting for
// the shader) fails the test after the timeout instead of hanging it.
TEST(FrameLoop, FramesReturnWhileTheShaderIsHeld) {
  Fixture f;
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<int> entered{0};
  FrameSettings s = small_settings(RenderMode::epi, false);
  s.before_shading_slice = [&] {
    ++entered;
    released.wait();
  };
  FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
  Camera camera = f.scene.cameras[0];
  auto frames = std::async(std::launch::async, [&] {
    for (int k = 0; k < 6; ++k) {
      camera.eye.x += 0.05f;
      renderer.render(camera);
    }
  });
  const bool returned = frames.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
  const int entered_while_held = entered.load();
  const size_t points_while_held = returned ? renderer.cache().valid_points() : 0;
  const size_t pending_while_held = returned ? renderer.pending_requests() : 0;
  release.set_value();
  frames.wait();
  EXPECT_TRUE(returned) << "frames waited for the held shader";
  // The shader never got past the hook while held (it may not even have reached it yet).
  EXPECT_LE(entered_while_held, 1);
  EXPECT_EQ(points_while_held, 0u);
  EXPECT_GT(pending_while_held, 0u);
}

// Waits (bounded) until the asynchronous shader has shaded everything submitted.
// Holds the asynchronous shader before each slice while `hold` is set, until release().
struct ShaderGate {
  std::promise<void> opened;
  std::shared_future<void> open = opened.get_future().share();
  std::atomic<bool> hold{false};
  FrameSettings around(FrameSettings s) {
    s.before_shading_slice = [this] {
      if (hold) open.wait();
    };
    return s;
  }
  void release() { opened.set_value(); }
};

void wait_for_shader(const FrameRenderer& renderer) {
  for (int k = 0; k < 20000 && renderer.pending_requests() > 0; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(2));  // the last slice's results are published after the count
}

// The adaptive core split (docs/render.md, "Cores"): while the shader is held with requests
// pending, the loop runs on the cores the shader leaves it (all but the shader's, at least one);
// once the shader has caught up, on all of them; with the shared split always on all of them.
TEST(FrameLoop, AdaptiveSplitGivesTheLoopOneCoreWhileTheShaderIsBehind) {
  const int cores = tbb::this_task_arena::max_concurrency();
  for (const CoreSplit split : {CoreSplit::adaptive, CoreSplit::shared}) {
    Fixture f;
    std::promise<void> release;
    std::shared_future<void> released = release.get_future().share();
    FrameSettings s = small_settings(RenderMode::epi, false);
    s.core_split = split;
    s.before_shading_slice = [&] { released.wait(); };
    FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
    const Camera camera = f.scene.cameras[0];
    renderer.render(camera);  // nothing submitted before it
    const int first = renderer.stats().loop_threads;
    renderer.render(camera);  // the first frame's requests are held: still pending at its end
    renderer.render(camera);
    const int behind = renderer.stats().loop_threads;
    const size_t pending = renderer.pending_requests();
    release.set_value();
    wait_for_shader(renderer);
    renderer.render(camera);  // all shaded by this frame's end
    renderer.render(camera);
    const int caught_up = renderer.stats().loop_threads;
    EXPECT_GT(pending, 0u);
    EXPECT_EQ(first, cores);
    EXPECT_EQ(caught_up, cores);
    EXPECT_EQ(behind, split == CoreSplit::adaptive ? 1 : cores) << "cores " << cores;  // the shader: cores - 1
  }
}

// Idle shading at rest (docs/render.md): with the view still and the shader done with every
// request, each frame asks for half as many again as the last, up to rest_sample_budget; a
// moved camera or object starts again from sample_budget; a shader that falls behind at rest
// gets fewer; with rest_sample_budget at sample_budget, or no share of the frame allowed for
// integrating results, nothing grows; sync mode never grows.
TEST(FrameLoop, AtRestTheBudgetGrowsWhileTheShaderKeepsUp) {
  Fixture f;
  FrameSettings s = small_settings(RenderMode::epi, false);
  s.sample_budget = 0.02, s.rest_sample_budget = 0.08;  // 82 and 328 requests of 4096 pixels
  s.motion_sample_budget = s.sample_budget;               // in motion: the next test
  s.grow_integrate_share = 1.0;  // integrating never takes the whole frame: growth by the shader alone
  FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
  Camera camera = f.scene.cameras[0];
  std::vector<size_t> asked;
  auto frame = [&](const Camera& c, std::span<const glm::mat4> objects = {}) {
    renderer.render(c, objects);
    asked.push_back(renderer.stats().requested);
    wait_for_shader(renderer);
  };
  for (int k = 0; k < 6; ++k) frame(camera);
  EXPECT_EQ(asked, (std::vector<size_t>{82, 123, 184, 276, 328, 328}));
  camera.eye.x += 0.05f;
  frame(camera);
  EXPECT_EQ(asked.back(), 82u) << "a moved camera starts again from the budget";
  frame(camera);
  EXPECT_EQ(asked.back(), 123u);
  const std::vector<glm::mat4> moved = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(0.1f, 0.0f, 0.0f))};
  frame(camera, moved);
  EXPECT_EQ(asked.back(), 82u) << "a moved object starts again from the budget";

  // A shader that falls behind at rest: the budget shrinks back.
  ShaderGate gate;
  FrameRenderer behind(f.scene, f.ray_scene, f.shader, gate.around(s));
  std::vector<size_t> behind_asked;
  for (int k = 0; k < 8; ++k) {
    if (k == 3) gate.hold = true;  // from the fourth frame's requests on, nothing is shaded
    behind.render(camera);
    behind_asked.push_back(behind.stats().requested);
    if (k < 3) wait_for_shader(behind);
  }
  gate.release();
  wait_for_shader(behind);
  EXPECT_EQ(behind_asked, (std::vector<size_t>{82, 123, 184, 276, 184, 123, 82, 82}));

  for (const int off_by : {0, 1, 2}) {  // rest budget at the budget, no share for integrating, sync
    const bool sync = off_by == 2;
    FrameSettings off = s;
    off.sync = sync;
    if (off_by == 0) off.rest_sample_budget = off.sample_budget;
    if (off_by == 1) off.grow_integrate_share = 0.0;
    FrameRenderer flat(f.scene, f.ray_scene, f.shader, off);
    for (int k = 0; k < 4; ++k) {
      flat.render(camera);
      if (!sync) wait_for_shader(flat);
      EXPECT_EQ(flat.stats().requested, 82u) << "case " << off_by << ", frame " << k;
      if (sync) EXPECT_EQ(flat.stats().samples, 82u) << "sync, frame " << k;
    }
  }
}

// Idle shading in motion (docs/render.md): with the camera moving every frame and the shader done
// with every request, the budget grows up to motion_sample_budget while frames take at most
// motion_frame_ms; a slower frame asks for sample_budget at once; at rest it goes on growing to
// rest_sample_budget; a shader that falls behind gets fewer; sync mode never grows.
TEST(FrameLoop, InMotionTheBudgetGrowsWhileTheShaderKeepsUpAndFramesAreFast) {
  Fixture f;
  FrameSettings s = small_settings(RenderMode::epi, false);
  s.sample_budget = 0.02, s.motion_sample_budget = 0.04, s.rest_sample_budget = 0.08;  // 82, 164, 328 of 4096
  s.grow_integrate_share = 1.0;
  s.motion_frame_ms = 1e9;  // every frame fast enough
  auto run = [&](const FrameSettings& settings, int moving, int still) {
    FrameRenderer renderer(f.scene, f.ray_scene, f.shader, settings);
    Camera camera = f.scene.cameras[0];
    std::vector<size_t> asked;
    for (int k = 0; k < moving + still; ++k) {
      if (k < moving) camera.eye.x += 0.01f;
      renderer.render(camera);
      asked.push_back(renderer.stats().requested);
      if (!settings.sync) wait_for_shader(renderer);
    }
    return asked;
  };
  EXPECT_EQ(run(s, 5, 3), (std::vector<size_t>{123, 164, 164, 164, 164, 246, 328, 328}));
  FrameSettings slow = s;
  slow.motion_frame_ms = 0.0;  // every frame slower than a display's: the budget in motion, then growth at rest
  EXPECT_EQ(run(slow, 4, 2), (std::vector<size_t>{82, 82, 82, 82, 123, 184}));
  FrameSettings off = s;
  off.motion_sample_budget = off.sample_budget;
  EXPECT_EQ(run(off, 4, 1), (std::vector<size_t>{82, 82, 82, 82, 123}));
  FrameSettings sync = s;
  sync.sync = true;
  EXPECT_EQ(run(sync, 4, 1), (std::vector<size_t>{82, 82, 82, 82, 82}));

  // A shader that falls behind in motion: the budget shrinks back.
  ShaderGate gate;
  FrameRenderer behind(f.scene, f.ray_scene, f.shader, gate.around(s));
  Camera camera = f.scene.cameras[0];
  std::vector<size_t> behind_asked;
  for (int k = 0; k < 6; ++k) {
    if (k == 2) gate.hold = true;
    camera.eye.x += 0.01f;
    behind.render(camera);
    behind_asked.push_back(behind.stats().requested);
    if (k < 2) wait_for_shader(behind);
  }
  gate.release();
  wait_for_shader(behind);
  EXPECT_EQ(behind_asked, (std::vector<size_t>{123, 164, 164, 109, 82, 82}));
}

// Effort where samples are sparse (docs/render.md): with an area light (whose samples effort
// multiplies), a sync frame over a sparse EPI asks for more than one effort a request and for
// exactly one once the still view has filled in; `sparse_effort` 1 and a scene whose shading
// samples nothing (a point light only) never do. Asynchronously the most effort grows by one after
// each frame whose requests were all shaded and halves after one whose were not, so a shader
// that falls behind is not asked for more.
TEST(FrameLoop, SparseRegionsAskForMoreEffortWhileTheShaderKeepsUp) {
  struct Lit {
    Scene scene = [] {
      Scene s = plane_and_box();
      const uint32_t glow = test::add_material(s, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(6.0f));
      const uint32_t panel = test::add_object(s, test::quad_mesh({-1, -1, 4}, {0, 2, 0}, {2, 0, 0}, glow), "panel");
      test::add_area_light(s, panel);
      return s;
    }();
    RayScene ray_scene{scene};
    Shader shader{ray_scene, ShaderSettings{}};
  } lit;
  ASSERT_TRUE(lit.shader.effort_matters());
  const Camera camera = lit.scene.cameras[0];
  auto efforts = [&](const Shader& shader, const Scene& scene, int most, int frames) {
    FrameSettings s = small_settings(RenderMode::epi);
    s.sample_budget = 0.02, s.sparse_effort = most;
    FrameRenderer renderer(scene, lit.ray_scene, shader, s);
    std::vector<double> per_request;
    for (int k = 0; k < frames; ++k) {
      renderer.render(camera);
      per_request.push_back(double(renderer.stats().effort) / double(renderer.stats().requested));
    }
    return per_request;
  };
  const std::vector<double> sparse = efforts(lit.shader, lit.scene, 4, 120);
  EXPECT_EQ(sparse[0], 1.0);  // the first frame has no EPI to look at
  EXPECT_GT(sparse[1], 2.0);  // a 2 % EPI: mostly sqrt(0.3 / 0.02) = 3.9, rounded to 4
  EXPECT_LE(sparse[1], 4.0);
  EXPECT_EQ(sparse.back(), 1.0) << "a still view that has filled in";
  for (double e : efforts(lit.shader, lit.scene, 1, 3)) EXPECT_EQ(e, 1.0);
  Fixture f;  // a point light only
  ASSERT_FALSE(f.shader.effort_matters());
  for (double e : efforts(f.shader, f.scene, 4, 3)) EXPECT_EQ(e, 1.0);

  // Asynchronous: the most effort follows the shader.
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<bool> hold{false};
  FrameSettings s = small_settings(RenderMode::epi, false);
  s.sample_budget = 0.02, s.sparse_effort = 4;
  s.before_shading_slice = [&] {
    if (hold) released.wait();
  };
  FrameRenderer renderer(lit.scene, lit.ray_scene, lit.shader, s);
  std::vector<int> most;
  auto frame = [&](bool wait) {
    renderer.render(camera);
    most.push_back(renderer.stats().most_effort);
    if (wait) wait_for_shader(renderer);
  };
  for (int k = 0; k < 5; ++k) frame(true);
  hold = true;  // nothing shaded from here on
  for (int k = 0; k < 3; ++k) frame(false);
  release.set_value();
  wait_for_shader(renderer);
  // Frame 0 has no EPI (the most, 2 after it, is not used); then 3, 4, 4, 4 while the shader
  // keeps up; behind: 4 (the first held frame's requests are chosen before the hold shows), 2, 1.
  EXPECT_EQ(most, (std::vector<int>{1, 3, 4, 4, 4, 4, 2, 1}));
}

// Async shading while the box moves every frame: results of every frame are integrated (not
// dropped because something moved), each drawn point lies where ray casting the current placement
// finds its surface, and no box point is drawn where the box no longer is.
TEST(FrameLoop, AsyncWithAnObjectMovingEveryFrameIntegratesSamplesInPlace) {
  Fixture f;
  FrameSettings s = small_settings(RenderMode::epi, false);
  s.sample_budget = 0.1;
  FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
  const Camera camera = f.scene.cameras[0];
  std::vector<glm::mat4> transforms = {glm::mat4(1.0f), glm::mat4(1.0f)};
  Fixture now;  // the oracle: the scene as placed this frame
  View view;
  view.camera = camera, view.width = 64, view.height = 64;
  const ViewFrame frame(view);
  for (int k = 0; k < 24; ++k) {
    transforms[1] = glm::translate(glm::mat4(1.0f), glm::vec3(0.12f * float(k), 0.04f * float(k), 0.0f));
    renderer.render(camera, transforms);
    if (k > 0) {
      EXPECT_GT(renderer.stats().samples, 64u * 64u / 20) << "frame " << k;
      EXPECT_LT(renderer.stats().sparseness, 20.0);
    }
    wait_for_shader(renderer);
  }
  now.ray_scene.set_object_transform(1, transforms[1]);
  const PointImage& image = renderer.cache().image();
  size_t drawn = 0, on_surface = 0, box_drawn = 0, stale = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const int32_t index = image.point[image.index(x, y)];
      if (index < 0) continue;
      const CachePoint& p = renderer.cache().points()[size_t(index)];
      if (p.object == kNone) continue;
      // The ray from the eye to the point finds the point's object at the point.
      const glm::vec3 world = renderer.cache().world_position(p, frame, transforms);
      const glm::vec3 to_point = world - frame.eye();
      Ray ray;
      ray.origin = frame.eye(), ray.direction = glm::normalize(to_point);
      const RayHit hit = now.ray_scene.intersect(ray);
      ++drawn;
      on_surface += hit.hit && hit.object == p.object && std::abs(hit.t - glm::length(to_point)) < 1e-3f * glm::length(to_point);
      if (p.object != 1) continue;
      // A box point where the box is not (no box within a pixel of here): left where it was.
      ++box_drawn;
      bool box_near = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const RayHit h = now.ray_scene.intersect(frame.ray(float(x + dx) + 0.5f, float(y + dy) + 0.5f));
          box_near |= h.hit && h.object == 1;
        }
      stale += !box_near;
    }
  EXPECT_GT(drawn, 64u * 64u / 2);
  EXPECT_GT(box_drawn, 100u);
  EXPECT_GE(double(on_surface), 0.97 * double(drawn));
  EXPECT_EQ(stale, 0u);
}

// An object moving every frame, asynchronous shading: the requests not yet started when the
// next frame moves the object are traced after the move (their shot's record split), not
// dropped. Dropped, they lived only from a frame's end to the next frame's start, and the shader
// starved (the soak run saw 277 of 300 frames without a result). Timing decides how many
// frames get results; with the requests kept, the shader has a whole frame to start them.
TEST(FrameLoop, AsyncWithAnObjectMovingEveryFrameKeepsTheShaderFed) {
  Fixture f;
  FrameSettings s = small_settings(RenderMode::epi, false);
  s.width = s.height = 48;
  FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
  std::vector<glm::mat4> objects;
  for (const Object& o : f.scene.objects) objects.push_back(o.object_to_world);
  constexpr int kFrames = 200;
  int fed = 0;
  size_t samples = 0;
  for (int k = 0; k < kFrames; ++k) {
    objects[1] = glm::translate(f.scene.objects[1].object_to_world, glm::vec3(0.002f * float(k), 0.0f, 0.0f));
    renderer.render(f.scene.cameras[0], objects);
    fed += renderer.stats().samples > 0, samples += renderer.stats().samples;
  }
  std::printf("frames with results: %d of %d, %zu results\n", fed, kFrames, samples);
  EXPECT_GT(fed, kFrames / 2);
}

// The shader gets through only the first slice of a frame's requests (a held shader, released
// for one slice): that prefix must cover the whole image in proportion, not the top rows.
TEST(FrameLoop, AsyncPrefixOfTheRequestsCoversTheWholeImage) {
  Fixture f;
  std::mutex mutex;
  std::condition_variable changed;
  int allowed = 1, entered = 0;
  FrameSettings s = small_settings(RenderMode::rendercache, false);
  s.width = s.height = 128, s.sample_budget = 0.5;  // 8192 requests: the first slice is an eighth
  s.before_shading_slice = [&] {
    std::unique_lock lock(mutex);
    ++entered;
    changed.notify_all();
    changed.wait(lock, [&] { return entered <= allowed; });
  };
  auto release_all = [&] {
    {
      std::lock_guard lock(mutex);
      allowed = 1 << 30;
    }
    changed.notify_all();
  };
  FrameRenderer renderer(f.scene, f.ray_scene, f.shader, s);
  renderer.render(f.scene.cameras[0]);
  bool second_slice_asked = false;
  {
    std::unique_lock lock(mutex);  // the first slice is shaded once the second is asked for
    second_slice_asked = changed.wait_for(lock, std::chrono::seconds(20), [&] { return entered == 2; });
  }
  if (!second_slice_asked) {
    release_all();  // else the renderer's destructor would wait for the held shader forever
    FAIL() << "the shader never asked for its second slice";
  }
  renderer.render(f.scene.cameras[0]);
  const size_t shaded = renderer.stats().samples;
  std::array<size_t, 4> quarters{};
  for (const CachePoint& p : renderer.cache().points())
    if (p.valid && p.image_id >= 0) ++quarters[size_t(p.image_id / 128 / 32)];
  release_all();
  EXPECT_GT(shaded, 100u);
  EXPECT_LE(shaded, 1024u);
  for (size_t q = 0; q < 4; ++q) EXPECT_GE(double(quarters[q]), 0.5 * double(shaded) / 4.0) << "quarter " << q;
}

}  // namespace
}  // namespace epi::render

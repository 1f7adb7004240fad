// Determinism whatever the thread count and batch split; the asynchronous shader; whole images.
#include <gtest/gtest.h>

#include <cstring>
#include <future>
#include <limits>

#include <tbb/task_arena.h>

#include "shade/async_shader.h"
#include "shade/render_image.h"
#include "test_scenes.h"

namespace epi {
namespace {

// Spheres on a floor under a point light and an area light: every code path has work to do.
Scene busy_scene() {
  Scene scene;
  uint32_t grey = test::add_material(scene, glm::vec3(0.6f));
  uint32_t gold = test::add_material(scene, glm::vec3(1.0f, 0.8f, 0.3f), 1.0f, 0.3f);
  uint32_t red = test::add_material(scene, glm::vec3(0.7f, 0.1f, 0.1f), 0.0f, 0.5f);
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(6.0f));
  test::add_object(scene, test::quad_mesh({-5, -5, 0}, {10, 0, 0}, {0, 10, 0}, grey), "floor");
  test::add_object(scene, test::sphere_mesh({-0.8f, 0, 0.7f}, 0.7f, 16, 32, gold), "gold");
  test::add_object(scene, test::sphere_mesh({0.9f, 0.3f, 0.5f}, 0.5f, 16, 32, red), "red");
  uint32_t panel = test::add_object(scene, test::quad_mesh({-0.5f, -0.5f, 3}, {0, 1, 0}, {1, 0, 0}, emitter), "panel");
  test::add_area_light(scene, panel);
  scene.punctual_lights.push_back(test::point_light({2, -2, 3}, glm::vec3(8.0f)));
  return scene;
}

const View kView{test::look({0, -5, 2}, {0, 0, 0.5f}), 96, 64};

std::vector<ShadeRequest> scattered_requests(size_t n) {
  std::vector<ShadeRequest> requests;
  for (size_t i = 0; i < n; ++i) {
    float x = std::fmod(float(i) * 37.618f, 96.0f), y = std::fmod(float(i) * 13.271f, 64.0f);
    requests.push_back({uint32_t(i), x, y});
  }
  return requests;
}

void expect_identical(const ShadeBatch& a, const ShadeBatch& b) {
  ASSERT_EQ(a.results.size(), b.results.size());
  for (size_t i = 0; i < a.results.size(); ++i) {
    const ShadeResult &ra = a.results[i], &rb = b.results[i];
    ASSERT_EQ(ra.id, rb.id);
    ASSERT_EQ(std::memcmp(&ra.color, &rb.color, sizeof ra.color), 0) << "request " << ra.id;
    ASSERT_EQ(std::memcmp(&ra.position, &rb.position, sizeof ra.position), 0);
    ASSERT_EQ(ra.object, rb.object);
    auto ta = a.triples_of(ra), tb = b.triples_of(rb);
    ASSERT_TRUE(std::equal(ta.begin(), ta.end(), tb.begin(), tb.end())) << "request " << ra.id;
  }
  EXPECT_EQ(a.rays, b.rays);
}

class Determinism : public ::testing::TestWithParam<ShaderKind> {};

TEST_P(Determinism, SameBitsForAnyThreadCountAndBatchSplit) {
  Scene scene = busy_scene();
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = GetParam();
  settings.area_light_samples = 8;
  settings.glossy_samples = 4;
  settings.gi_paths = 4;
  Shader shader(rays, settings);
  const std::vector<ShadeRequest> requests = scattered_requests(400);

  ShadeBatch one_thread, two_threads, split;
  tbb::task_arena(1).execute([&] { shader.shade(kView, requests, one_thread); });
  tbb::task_arena(2).execute([&] { shader.shade(kView, requests, two_threads); });
  for (size_t begin = 0; begin < requests.size(); begin += 7)
    shader.shade(kView, std::span(requests).subspan(begin, std::min<size_t>(7, requests.size() - begin)), split);
  expect_identical(one_thread, two_threads);
  expect_identical(one_thread, split);
  size_t hits = 0;
  for (const ShadeResult& r : one_thread.results) hits += r.hit;
  EXPECT_GT(hits, 200u);
  EXPECT_FALSE(one_thread.triples.empty());  // the spheres shadow the floor

  settings.seed = 2;  // another seed: other noise
  Shader reseeded(rays, settings);
  ShadeBatch other;
  reseeded.shade(kView, requests, other);
  size_t differing = 0;
  for (size_t i = 0; i < requests.size(); ++i) differing += other.results[i].color != one_thread.results[i].color;
  EXPECT_GT(differing, 10u);
}

INSTANTIATE_TEST_SUITE_P(Kinds, Determinism, ::testing::Values(ShaderKind::direct, ShaderKind::glossy, ShaderKind::gi));

TEST(Robustness, ColoursAreFiniteAndNonNegativeEverywhere) {
  Scene scene = busy_scene();
  RayScene rays(scene);
  std::vector<ShadeRequest> requests = scattered_requests(300);
  const float inf = std::numeric_limits<float>::infinity();
  for (glm::vec2 p : {glm::vec2(0, 0), glm::vec2(96, 64), glm::vec2(-1e6f, 3), glm::vec2(1e30f, -1e30f),
                      glm::vec2(std::nanf(""), 1), glm::vec2(inf, 0), glm::vec2(1e-30f, 1e-30f)})
    requests.push_back({uint32_t(requests.size()), p.x, p.y});
  for (ShaderKind kind : {ShaderKind::direct, ShaderKind::glossy, ShaderKind::gi}) {
    ShaderSettings settings;
    settings.kind = kind;
    settings.area_light_samples = 4;
    settings.glossy_samples = 4;
    settings.gi_paths = 4;
    Shader shader(rays, settings);
    ShadeBatch batch;
    shader.shade(kView, requests, batch);
    for (const ShadeResult& r : batch.results) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(r.color[c])) << r.id;
        ASSERT_GE(r.color[c], 0.0f) << r.id;
      }
      if (r.hit) {
        ASSERT_NEAR(glm::length(r.normal), 1.0f, 1e-4f);
        ASSERT_LT(glm::dot(r.normal, r.position - kView.camera.eye), 0.0f);  // faces the camera
        ASSERT_LT(r.object, scene.objects.size());
      } else {
        ASSERT_EQ(r.object, kNone);
      }
    }
    EXPECT_FALSE(batch.results[300 + 4].hit);  // NaN position
    EXPECT_FALSE(batch.results[300 + 5].hit);  // infinite position
  }
  ShaderSettings bad;
  bad.area_light_samples = -1;
  EXPECT_THROW(Shader(rays, bad), std::invalid_argument);
}

TEST(AsyncShader, DeliversWhatTheSynchronousShaderComputes) {
  Scene scene = busy_scene();
  RayScene rays(scene);
  ShaderSettings settings;
  settings.area_light_samples = 4;
  Shader shader(rays, settings);
  const std::vector<ShadeRequest> requests = scattered_requests(1000);
  ShadeBatch expected;
  shader.shade(kView, requests, expected);

  AsyncShader async(shader, 2, 64);
  ShadeBatch taken;
  taken.triples.push_back({9, 9, 9});  // results are appended after what is already there
  async.submit(kView, std::vector<ShadeRequest>(requests.begin(), requests.begin() + 300));
  async.submit(kView, std::vector<ShadeRequest>(requests.begin() + 300, requests.end()));
  size_t polls = 0;
  while (taken.results.size() < requests.size() && polls < 100000) {
    async.take_results(taken);
    ++polls;
    std::this_thread::yield();
  }
  async.wait_idle();
  async.take_results(taken);
  EXPECT_EQ(async.pending_requests(), 0u);
  ASSERT_EQ(taken.results.size(), requests.size());
  taken.triples.erase(taken.triples.begin());
  for (ShadeResult& r : taken.results) r.triple_begin -= 1;
  expect_identical(expected, taken);
}

TEST(AsyncShader, CancelsUpdatesBetweenBatchesAndShutsDown) {
  Scene scene = busy_scene();
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::gi;
  settings.gi_paths = 2;
  Shader shader(rays, settings);
  {
    AsyncShader async(shader, 1, 16);
    async.submit(kView, scattered_requests(2000));
    size_t dropped = async.cancel_pending();
    async.wait_idle();
    ShadeBatch taken;
    size_t got = async.take_results(taken);
    EXPECT_EQ(got + dropped, 2000u);

    // Hold the worker in an update: everything submitted meanwhile can be cancelled.
    std::promise<void> gate;
    std::shared_future<void> opened = gate.get_future().share();
    async.run_between_batches([opened] { opened.wait(); });
    async.submit(kView, scattered_requests(300));
    EXPECT_EQ(async.pending_requests(), 300u);
    EXPECT_EQ(async.cancel_pending(), 300u);
    // An update queued now runs before every request not yet started: it names the first of
    // each queued batch (the renderer splits its shots' placement records there).
    std::vector<ShadeRequest> later = scattered_requests(50);
    for (ShadeRequest& r : later) r.id += 1000;
    async.submit(kView, scattered_requests(20));
    async.submit(kView, later);
    EXPECT_EQ(async.run_between_batches([] {}), (std::vector<uint32_t>{0u, 1000u}));
    EXPECT_EQ(async.cancel_pending(), 70u);
    EXPECT_TRUE(async.run_between_batches([] {}).empty());
    gate.set_value();
    async.wait_idle();
    taken.clear();
    EXPECT_EQ(async.take_results(taken), 0u);

    // Move the floor down by 0.5 between batches: later results see it there.
    bool moved = false;
    async.run_between_batches([&] {
      rays.set_object_transform(0, glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -0.5f)));
      moved = true;
    });
    async.submit(kView, {ShadeRequest{1, 48.0f, 60.0f}});
    async.wait_idle();
    EXPECT_TRUE(moved);
    taken.clear();
    ASSERT_EQ(async.take_results(taken), 1u);
    ASSERT_TRUE(taken.results[0].hit);
    EXPECT_NEAR(taken.results[0].position.z, -0.5f, 1e-4f);
    async.submit(kView, scattered_requests(5000));  // destroyed with work pending: must not hang
  }
  SUCCEED();
}

TEST(RenderImage, DeterministicAcrossThreadCountsWithMonotoneProgress) {
  Scene scene = busy_scene();
  RayScene rays(scene);
  ShaderSettings settings;
  settings.area_light_samples = 2;
  Shader shader(rays, settings);
  RgbImage one, two;
  std::vector<double> fractions;
  RenderStats stats;
  tbb::task_arena(1).execute([&] { one = render_image(shader, kView, 4, {}, nullptr); });
  tbb::task_arena(2).execute([&] { two = render_image(shader, kView, 4, [&](double f) { fractions.push_back(f); }, &stats); });
  ASSERT_EQ(one.pixels.size(), size_t(96 * 64 * 3));
  EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(float)), 0);
  ASSERT_FALSE(fractions.empty());
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_EQ(stats.samples, uint64_t(96 * 64 * 4));
  EXPECT_GT(stats.rays, stats.samples);
  EXPECT_GT(stats.seconds, 0.0);
  EXPECT_THROW(render_image(shader, kView, 0), std::invalid_argument);
}

TEST(RenderImage, OneSampleHitsPixelCentres) {
  // A plane under a directional light: constant radiance wherever the centre ray hits it.
  Scene scene;
  uint32_t grey = test::add_material(scene, glm::vec3(0.5f));
  test::add_object(scene, test::quad_mesh({-100, -100, 0}, {200, 0, 0}, {0, 200, 0}, grey), "floor");
  PunctualLight sun;
  sun.type = LightType::directional;
  sun.direction = glm::vec3(0, 0, -1);
  sun.intensity = glm::vec3(1.0f);
  scene.punctual_lights.push_back(sun);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.specular = false;
  Shader shader(rays, settings);
  View view{test::look({0, -3, 2}, {0, 0, 0}), 40, 30};
  RgbImage image = render_image(shader, view, 1);
  ViewFrame frame(view);
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      Ray ray = frame.ray(float(x) + 0.5f, float(y) + 0.5f);
      float expected = ray.direction.z < 0.0f ? 0.5f / float(M_PI) : 0.0f;  // misses above the horizon
      ASSERT_NEAR(image.at(x, y)[0], expected, 1e-6f) << x << "," << y;
    }
}

}  // namespace
}  // namespace epi

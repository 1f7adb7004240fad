// Energy checks in a closed "furnace" room: every wall emits Le and reflects with albedo rho,
// so the radiance everywhere is Le / (1 - rho) (all bounces) and Le (1 + rho) (direct only).
#include <gtest/gtest.h>

#include "shade/shader.h"
#include "test_scenes.h"

namespace epi {
namespace {

constexpr float kLe = 1.0f;

Scene furnace(float albedo, float metallic = 0.0f, float roughness = 1.0f) {
  Scene scene;
  uint32_t wall = test::add_material(scene, glm::vec3(albedo), metallic, roughness, glm::vec3(kLe));
  uint32_t room = test::add_object(scene, test::box_mesh({-1, -1, -1}, {1, 1, 1}, wall, true), "room");
  test::add_area_light(scene, room);
  return scene;
}

// Mean colour over a grid of pixels away from the room's edges.
glm::vec3 mean_radiance(const Shader& shader) {
  View view{test::look({0.1f, -0.2f, 0.05f}, {0.3f, 1.0f, 0.1f}, 60.0f), 64, 64};
  std::vector<ShadeRequest> requests;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) requests.push_back({uint32_t(requests.size()), 8.0f * float(i) + 4.0f, 8.0f * float(j) + 4.0f});
  ShadeBatch batch;
  shader.shade(view, requests, batch);
  glm::dvec3 sum(0.0);
  for (const ShadeResult& r : batch.results) {
    EXPECT_TRUE(r.hit);
    sum += glm::dvec3(r.color);
  }
  return glm::vec3(sum / double(batch.results.size()));
}

TEST(Furnace, DirectLightingOfAnEmittingRoom) {
  Scene scene = furnace(0.5f);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.specular = false;
  settings.area_light_samples = 64;
  Shader shader(rays, settings);
  EXPECT_NEAR(mean_radiance(shader).x, kLe * 1.5f, 0.02f * 1.5f);
}

TEST(Furnace, PathTracingConvergesToTheGeometricSeries) {
  Scene scene = furnace(0.5f);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::gi;
  settings.specular = false;
  settings.area_light_samples = 16;
  settings.gi_paths = 32;
  settings.gi_max_bounces = 40;
  Shader shader(rays, settings);
  EXPECT_NEAR(mean_radiance(shader).x, kLe / (1.0f - 0.5f), 0.03f * 2.0f);
  EXPECT_GT(shader.rays_traced(), 64u * 32u * 2u);
}

TEST(Furnace, LightsListedInAnotherOrderAreLightSampledOnly) {
  // An area light whose triangles are not in mesh order has no triangle map: BRDF-sampled hits
  // leave it to light sampling. The furnace must still converge.
  Scene scene = furnace(0.5f);
  AreaLight& light = scene.area_lights[0];
  const size_t n = light.triangle_materials.size();
  std::vector<glm::vec3> vertices;
  for (size_t t = n; t-- > 0;) vertices.insert(vertices.end(), &light.triangle_vertices[3 * t], &light.triangle_vertices[3 * t] + 3);
  light.triangle_vertices = vertices;
  light.triangle_materials.assign(n, light.triangle_materials[0]);
  for (size_t t = 0; t < n; ++t) light.triangle_cdf[t] = float(t + 1) / float(n);  // all faces have equal area
  light.triangle_materials.push_back(0);  // one extra entry breaks the mesh-order match...
  light.triangle_vertices.insert(light.triangle_vertices.end(), 3, glm::vec3(0.0f));
  light.triangle_cdf.push_back(1.0f);  // ...at zero probability
  RayScene rays(scene);
  EXPECT_FALSE(rays.area_light_mapped(0));
  ShaderSettings settings;
  settings.kind = ShaderKind::gi;
  settings.specular = false;
  settings.gi_paths = 64;
  settings.gi_max_bounces = 40;
  Shader shader(rays, settings);
  // Light sampling alone has heavy tails near the room's edges (1/d^2): a looser bound.
  EXPECT_NEAR(mean_radiance(shader).x, kLe / (1.0f - 0.5f), 0.05f * 2.0f);
}

TEST(Furnace, OnePointConvergesTightly) {
  // Away from the room's edges the estimators have light tails: many paths at one point pin
  // the truncated series Le (1 + rho + rho^2 + rho^3) down to a fraction of a percent.
  Scene scene = furnace(0.5f);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::gi;
  settings.specular = false;
  settings.area_light_samples = 256;
  settings.gi_paths = 100000;
  settings.gi_max_bounces = 2;
  Shader shader(rays, settings);
  View view{test::look({0.1f, -0.2f, 0.05f}, {0.3f, 1.0f, 0.1f}, 60.0f), 64, 64};
  ShadeBatch batch;
  ShadeRequest centre{0, 32.0f, 32.0f};
  shader.shade(view, std::span(&centre, 1), batch);
  EXPECT_NEAR(batch.results[0].color.x, kLe * 1.875f, 0.005f * 1.875f);
}

TEST(Furnace, BounceLimitTruncatesTheSeries) {
  // One bounce after the primary hit: Le (1 + rho + rho^2).
  Scene scene = furnace(0.5f);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::gi;
  settings.specular = false;
  settings.gi_paths = 32;
  settings.gi_max_bounces = 1;
  Shader shader(rays, settings);
  EXPECT_NEAR(mean_radiance(shader).x, kLe * 1.75f, 0.03f * 1.75f);
}

TEST(Furnace, GlossyMetalRoomStaysBelowTheWhiteLimit) {
  // A white metal room: the BRDF loses a little energy (separable Smith), never gains it.
  Scene scene = furnace(1.0f, 1.0f, 0.3f);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::gi;
  settings.gi_paths = 32;
  settings.gi_max_bounces = 6;
  Shader shader(rays, settings);
  float radiance = mean_radiance(shader).x;
  EXPECT_LE(radiance, kLe * 8.0f * 1.03f);  // at most Le (emission + direct + 6 bounces)
  EXPECT_GE(radiance, kLe * 6.0f);
}

}  // namespace
}  // namespace epi

namespace epi {
namespace {

// A floor under a square panel: with no light samples at the primary hit, one bounce of gi
// finds the panel by BRDF sampling alone (weight 1), and must still give Lambert's formula.
TEST(Mis, BrdfSamplingAloneFindsTheLight) {
  Scene scene;
  uint32_t floor = test::add_material(scene, glm::vec3(0.7f));
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, floor), "floor");
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(5.0f));
  uint32_t panel = test::add_object(scene, test::quad_mesh({-0.5f, -0.5f, 1}, {0, 1, 0}, {1, 0, 0}, emitter), "panel");
  test::add_area_light(scene, panel);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.specular = false;
  settings.kind = ShaderKind::gi;
  settings.area_light_samples = 0;
  settings.gi_paths = 65536;
  settings.gi_max_bounces = 1;
  Shader gi(rays, settings);
  View view{test::look({3, -2, 1.5f}, {0, 0, 0}), 64, 64};
  std::vector<ShadeRequest> requests;
  for (int i = 0; i < 4; ++i) requests.push_back({uint32_t(i), 16.0f + 8.0f * float(i), 30.0f + 3.0f * float(i)});
  ShadeBatch batch;
  gi.shade(view, requests, batch);
  for (const ShadeResult& r : batch.results) {
    ASSERT_TRUE(r.hit);
    double sum = 0.0;  // Lambert's formula (see test_analytic.cpp)
    const glm::dvec3 square[4] = {{-0.5, -0.5, 1}, {0.5, -0.5, 1}, {0.5, 0.5, 1}, {-0.5, 0.5, 1}};
    for (int i = 0; i < 4; ++i) {
      glm::dvec3 a = glm::normalize(square[i] - glm::dvec3(r.position)), b = glm::normalize(square[(i + 1) % 4] - glm::dvec3(r.position));
      sum += std::acos(glm::dot(a, b)) * glm::normalize(glm::cross(a, b)).z;
    }
    double expected = 0.7 / M_PI * 5.0 / 2.0 * std::abs(sum);
    EXPECT_NEAR(r.color.x, expected, 0.04 * expected) << r.id;  // ~1.7% noise
  }
}

// Light seen in a glossy metal wall from a Lambertian floor (a two-bounce path). At the wall,
// light sampling and BRDF sampling are combined by the power heuristic; turning light samples
// off there (gi_light_samples = 0) leaves BRDF sampling alone. Both must agree on average.
TEST(Mis, CombinedAndBrdfOnlyEstimatesAgree) {
  Scene scene;
  uint32_t white = test::add_material(scene, glm::vec3(0.8f));
  uint32_t metal = test::add_material(scene, glm::vec3(0.9f), 1.0f, 0.25f);
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(10.0f));
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, white), "floor");
  test::add_object(scene, test::quad_mesh({-10, 2, 0}, {20, 0, 0}, {0, 0, 10}, metal), "wall");  // y = 2, facing -y
  uint32_t panel = test::add_object(scene, test::quad_mesh({-0.5f, 0.5f, 2}, {0, 1, 0}, {1, 0, 0}, emitter), "panel");
  test::add_area_light(scene, panel);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::gi;
  settings.area_light_samples = 4;
  settings.gi_paths = 2048;
  settings.gi_max_bounces = 2;
  settings.gi_roulette_bounce = 10;
  Shader combined(rays, settings);
  settings.gi_light_samples = 0;
  Shader brdf_only(rays, settings);
  View view{test::look({0, -4, 1.5f}, {0, 0.5f, 0}), 32, 32};
  std::vector<ShadeRequest> requests;
  for (int i = 0; i < 8; ++i) requests.push_back({uint32_t(i), 4.0f + 3.0f * float(i), 24.0f + 0.5f * float(i)});
  ShadeBatch a, b;
  combined.shade(view, requests, a);
  brdf_only.shade(view, requests, b);
  double sum_a = 0.0, sum_b = 0.0;
  for (size_t i = 0; i < requests.size(); ++i) {
    ASSERT_TRUE(a.results[i].hit);
    ASSERT_EQ(a.results[i].object, 0u);
    sum_a += a.results[i].color.x;
    sum_b += b.results[i].color.x;
  }
  EXPECT_NEAR(sum_a, sum_b, 0.03 * sum_b);
}

TEST(Furnace, PathClampBoundsEachPath) {
  Scene scene = furnace(0.5f);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::gi;
  settings.specular = false;
  settings.gi_paths = 8;
  settings.gi_path_clamp = 0.1f;
  Shader shader(rays, settings);
  float radiance = mean_radiance(shader).x;
  EXPECT_LE(radiance, kLe * 1.5f * 1.02f + 0.1f);  // emission + direct + at most the clamp
  EXPECT_GE(radiance, kLe * 1.5f * 0.98f);
  settings.gi_path_clamp = -1.0f;
  EXPECT_THROW(Shader(rays, settings), std::invalid_argument);
}

}  // namespace
}  // namespace epi

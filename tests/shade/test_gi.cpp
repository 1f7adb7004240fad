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

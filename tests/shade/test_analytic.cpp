// Direct lighting against closed forms: point, directional and spot lights on a Lambertian
// plane, a square area light (Lambert's polygon formula), emission, specular and glossy.
#include <gtest/gtest.h>

#include "shade/brdf.h"
#include "shade/sampling.h"
#include "shade/shader.h"
#include "test_scenes.h"

namespace epi {
namespace {

constexpr float kAlbedo = 0.6f;
constexpr float kInvPi = float(1.0 / M_PI);

// A 20 x 20 Lambertian plane at z = 0 facing +z; returns its object index.
uint32_t add_floor(Scene& scene, float albedo = kAlbedo) {
  uint32_t m = test::add_material(scene, glm::vec3(albedo));
  return test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, m), "floor");
}

View low_view() { return View{test::look({6, -1, 2.5f}, {0, 0, 0}), 256, 256}; }

ShadeResult shade_at(const Shader& shader, const View& view, glm::vec3 world, ShadeBatch* batch_out = nullptr) {
  Projection p = project(view, world);
  ShadeBatch batch;
  ShadeRequest request{0, p.pixel.x, p.pixel.y};
  shader.shade(view, std::span(&request, 1), batch);
  if (batch_out) *batch_out = batch;
  return batch.results.at(0);
}

ShaderSettings lambert_settings() {
  ShaderSettings s;
  s.specular = false;
  return s;
}

TEST(Analytic, PointLightOnLambertianPlane) {
  Scene scene;
  uint32_t floor = add_floor(scene);
  const glm::vec3 light_pos(0.3f, -0.2f, 2.0f), intensity(10.0f, 5.0f, 2.0f);
  scene.punctual_lights.push_back(test::point_light(light_pos, intensity));
  RayScene rays(scene);
  Shader shader(rays, lambert_settings());
  const View view = low_view();
  for (glm::vec3 target : {glm::vec3(0, 0, 0), glm::vec3(1.5f, 0.7f, 0), glm::vec3(-2, -3, 0), glm::vec3(3, 2.5f, 0)}) {
    ShadeResult r = shade_at(shader, view, target);
    ASSERT_TRUE(r.hit);
    EXPECT_EQ(r.object, floor);
    EXPECT_NEAR(r.position.z, 0.0f, 1e-5f);
    EXPECT_LT(glm::distance(r.position, target), 1e-3f);
    EXPECT_NEAR(glm::distance(r.normal, glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    glm::vec3 to_light = light_pos - r.position;
    float d = glm::length(to_light);
    glm::vec3 expected = kAlbedo * kInvPi * intensity * (to_light.z / d) / (d * d);  // rho/pi * I cos / d^2
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.color[c], expected[c], 1e-5f * expected[c]) << "at " << target.x;
    EXPECT_EQ(r.triple_count, 0u);
  }
}

TEST(Analytic, PlaneSeenFromBelowFacesTheRay) {
  Scene scene;
  add_floor(scene);
  scene.punctual_lights.push_back(test::point_light({0, 0, 2}, glm::vec3(5)));
  RayScene rays(scene);
  Shader shader(rays, lambert_settings());
  View view{test::look({1, 1, -3}, {0, 0, 0}), 64, 64};
  ShadeResult r = shade_at(shader, view, {0, 0, 0});
  ASSERT_TRUE(r.hit);
  EXPECT_NEAR(glm::distance(r.normal, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
  EXPECT_EQ(r.color, glm::vec3(0.0f));  // the light is on the other side
}

TEST(Analytic, DirectionalLight) {
  Scene scene;
  add_floor(scene);
  PunctualLight sun;
  sun.type = LightType::directional;
  sun.direction = glm::normalize(glm::vec3(1, 1, -2));
  sun.intensity = glm::vec3(3.0f);
  scene.punctual_lights.push_back(sun);
  RayScene rays(scene);
  Shader shader(rays, lambert_settings());
  float expected = kAlbedo * kInvPi * 3.0f * (2.0f / std::sqrt(6.0f));
  for (glm::vec3 target : {glm::vec3(0, 0, 0), glm::vec3(-4, 3, 0), glm::vec3(2, -2, 0)}) {
    ShadeResult r = shade_at(shader, low_view(), target);
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.color.x, expected, 1e-5f * expected);
  }
}

TEST(Analytic, SpotConeFalloff) {
  Scene scene;
  add_floor(scene);
  PunctualLight spot = test::point_light({0, 0, 2}, glm::vec3(8.0f));
  spot.type = LightType::spot;
  spot.direction = glm::vec3(0, 0, -1);
  const float inner = std::cos(glm::radians(20.0f)), outer = std::cos(glm::radians(35.0f));
  spot.inner_cone_cos = inner;
  spot.outer_cone_cos = outer;
  scene.punctual_lights.push_back(spot);
  RayScene rays(scene);
  Shader shader(rays, lambert_settings());
  int inside = 0, between = 0, outside = 0;
  for (float radius = 0.0f; radius < 2.5f; radius += 0.1f) {
    ShadeResult r = shade_at(shader, low_view(), {radius, 0.3f * radius, 0});
    ASSERT_TRUE(r.hit);
    glm::vec3 to_light = glm::vec3(0, 0, 2) - r.position;
    float d = glm::length(to_light), cos_axis = to_light.z / d;
    float t = std::clamp((cos_axis - outer) / (inner - outer), 0.0f, 1.0f);
    float expected = kAlbedo * kInvPi * 8.0f * (to_light.z / d) / (d * d) * t * t;
    EXPECT_NEAR(r.color.x, expected, 1e-5f * expected + 1e-7f) << "radius " << radius;
    if (cos_axis >= inner) {
      ++inside;
      EXPECT_GT(r.color.x, 0.0f);
    } else if (cos_axis <= outer) {
      ++outside;
      EXPECT_EQ(r.color.x, 0.0f);
    } else {
      ++between;
    }
  }
  EXPECT_GT(inside, 3);
  EXPECT_GT(between, 3);
  EXPECT_GT(outside, 3);
}

// Irradiance from a uniform Lambertian polygon (Lambert's formula): E = L/2 sum theta_i n.Gamma_i.
double polygon_irradiance(const std::vector<glm::dvec3>& polygon, glm::dvec3 p, glm::dvec3 n, double radiance) {
  double sum = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    glm::dvec3 a = glm::normalize(polygon[i] - p), b = glm::normalize(polygon[(i + 1) % polygon.size()] - p);
    double theta = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += theta * glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return radiance / 2.0 * std::abs(sum);
}

TEST(Analytic, SquareAreaLightMatchesLambertsFormula) {
  Scene scene;
  add_floor(scene);
  const float radiance = 4.0f;
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(radiance));
  // A unit square at z = 1 facing down.
  uint32_t light = test::add_object(scene, test::quad_mesh({-0.5f, -0.5f, 1}, {0, 1, 0}, {1, 0, 0}, emitter), "panel");
  test::add_area_light(scene, light);
  ASSERT_NEAR(scene.area_lights[0].area, 1.0f, 1e-6f);
  RayScene rays(scene);
  ShaderSettings settings = lambert_settings();
  settings.area_light_samples = 1024;
  Shader shader(rays, settings);
  const std::vector<glm::dvec3> square = {{-0.5, -0.5, 1}, {0.5, -0.5, 1}, {0.5, 0.5, 1}, {-0.5, 0.5, 1}};
  for (glm::vec3 target : {glm::vec3(0, 0, 0), glm::vec3(0.4f, 0.1f, 0), glm::vec3(1.5f, -0.5f, 0), glm::vec3(-2, 1, 0)}) {
    ShadeResult r = shade_at(shader, View{test::look({5, 0.3f, 0.4f}, target), 64, 64}, target);
    ASSERT_TRUE(r.hit);
    ASSERT_NEAR(r.position.z, 0.0f, 1e-5f);
    double expected = kAlbedo / M_PI * polygon_irradiance(square, glm::dvec3(r.position), {0, 0, 1}, radiance);
    EXPECT_NEAR(r.color.x, expected, 0.01 * expected) << "at " << target.x << "," << target.y << " hit " << r.position.x << "," << r.position.y << " object " << r.object;
  }
}

// Two small area lights of equal power, one near the shaded point and one far: each hit's
// light choices are stratified (shader.cpp, LightChoiceStrata), so with two samples every hit
// takes one of each light and the estimate hardly varies, where independent choices would give
// two near samples, two far ones or one of each (a spread of about half the mean); and the
// estimate stays unbiased (its mean is Lambert's formula summed over the lights) for sample
// counts that do and do not divide evenly between the lights.
TEST(Analytic, LightChoicesAreStratifiedAndUnbiased) {
  Scene scene;
  add_floor(scene);
  const float radiance = 50.0f, half = 0.1f;
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(radiance));
  const glm::vec2 centres[2] = {{-1.0f, 0.0f}, {1.5f, 0.0f}};
  std::vector<std::vector<glm::dvec3>> squares;
  for (const glm::vec2 c : centres) {
    uint32_t light = test::add_object(scene, test::quad_mesh({c.x - half, c.y - half, 1}, {0, 2 * half, 0}, {2 * half, 0, 0}, emitter), "panel");
    test::add_area_light(scene, light);
    squares.push_back({{c.x - half, c.y - half, 1}, {c.x + half, c.y - half, 1}, {c.x + half, c.y + half, 1}, {c.x - half, c.y + half, 1}});
  }
  RayScene rays(scene);
  ASSERT_EQ(rays.area_light_cdf().size(), 2u);
  const glm::vec3 target(-0.8f, 0.1f, 0.0f);
  const View view{test::look({-0.8f, -3.0f, 2.0f}, target), 64, 64};
  const Projection p = project(view, target);
  for (const int samples : {2, 3, 16}) {
    ShaderSettings settings = lambert_settings();
    settings.area_light_samples = samples;
    const Shader shader(rays, settings);
    double sum = 0.0, sum2 = 0.0;
    const int n = 400;
    for (int k = 0; k < n; ++k) {
      ShadeRequest request{0, p.pixel.x + 0.002f * float(k % 20), p.pixel.y + 0.002f * float(k / 20)};  // other streams
      ShadeBatch batch;
      shader.shade(view, std::span(&request, 1), batch);
      const ShadeResult& r = batch.results.at(0);
      ASSERT_TRUE(r.hit);
      double expected = 0.0;
      for (const auto& square : squares) expected += kAlbedo / M_PI * polygon_irradiance(square, glm::dvec3(r.position), {0, 0, 1}, radiance);
      const double v = r.color.x / expected;  // relative to the point's own closed form
      sum += v, sum2 += v * v;
    }
    const double mean = sum / n, spread = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    EXPECT_NEAR(mean, 1.0, 0.02) << samples << " samples";
    // An even count splits evenly (independent choices: a spread of about 0.5 with two samples);
    // three give one light two samples and the other one, which light varying by hit.
    if (samples % 2 == 0) EXPECT_LT(spread, 0.05) << samples << " samples, half of them on each light";
  }
}

TEST(Analytic, EmissionSeenDirectly) {
  Scene scene;
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(1.0f, 2.0f, 3.0f));
  uint32_t panel = test::add_object(scene, test::quad_mesh({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, emitter), "panel");
  test::add_area_light(scene, panel);
  RayScene rays(scene);
  Shader shader(rays, ShaderSettings{});
  ShadeResult front = shade_at(shader, View{test::look({0.2f, 0.1f, 3}, {0, 0, 0}), 32, 32}, {0, 0, 0});
  ASSERT_TRUE(front.hit);
  EXPECT_EQ(front.color, glm::vec3(1.0f, 2.0f, 3.0f));
  ShadeResult back = shade_at(shader, View{test::look({0.2f, 0.1f, -3}, {0, 0, 0}), 32, 32}, {0, 0, 0});
  ASSERT_TRUE(back.hit);
  EXPECT_EQ(back.color, glm::vec3(0.0f));  // emission leaves the front face only
  ShadeBatch batch;
  ShadeRequest miss{5, 0.5f, 0.5f};
  shader.shade(View{test::look({0, 0, 3}, {0, 0, 10}), 32, 32}, std::span(&miss, 1), batch);
  EXPECT_FALSE(batch.results[0].hit);
  EXPECT_EQ(batch.results[0].object, kNone);
  EXPECT_EQ(batch.results[0].id, 5u);
  EXPECT_EQ(batch.results[0].color, glm::vec3(0.0f));
}

TEST(Analytic, MirroredEmitterEmitsFromItsTransformedFront) {
  // A panel facing +z in object space, mirrored by z -> -z and lifted to z = 1: its front
  // (the transformed normal) faces down, towards the floor.
  Scene scene;
  add_floor(scene);
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(3.0f));
  glm::mat4 mirror = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 1)), glm::vec3(1, 1, -1));
  uint32_t panel = test::add_object(scene, test::quad_mesh({-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, emitter), "panel", mirror);
  test::add_area_light(scene, panel);
  RayScene rays(scene);
  ShaderSettings settings = lambert_settings();
  settings.area_light_samples = 256;
  Shader shader(rays, settings);
  const std::vector<glm::dvec3> square = {{-0.5, -0.5, 1}, {0.5, -0.5, 1}, {0.5, 0.5, 1}, {-0.5, 0.5, 1}};
  ShadeResult lit = shade_at(shader, low_view(), {0.2f, 0.1f, 0});
  double expected = kAlbedo / M_PI * polygon_irradiance(square, glm::dvec3(lit.position), {0, 0, 1}, 3.0);
  EXPECT_NEAR(lit.color.x, expected, 0.02 * expected);
  ShadeResult seen = shade_at(shader, View{test::look({0.1f, 0.1f, 0.5f}, {0, 0, 1}), 16, 16}, {0, 0, 1});
  ASSERT_EQ(seen.object, panel);
  EXPECT_EQ(seen.color, glm::vec3(3.0f));
  // Moving it keeps the orientation (build_area_light swaps the winding for mirrors too).
  rays.set_object_transform(panel, glm::translate(glm::mat4(1.0f), glm::vec3(2, 0, 0)) * mirror);
  ShadeResult moved = shade_at(shader, low_view(), glm::vec3(2.2f, 0.1f, 0));
  std::vector<glm::dvec3> shifted = square;
  for (auto& p : shifted) p.x += 2;
  double expected_moved = kAlbedo / M_PI * polygon_irradiance(shifted, glm::dvec3(moved.position), {0, 0, 1}, 3.0);
  EXPECT_NEAR(moved.color.x, expected_moved, 0.02 * expected_moved);
}

TEST(Analytic, PointLightRangeWindow) {
  Scene scene;
  add_floor(scene);
  PunctualLight light = test::point_light({0, 0, 1}, glm::vec3(6.0f));
  light.range = 3.0f;
  scene.punctual_lights.push_back(light);
  RayScene rays(scene);
  Shader shader(rays, lambert_settings());
  for (float x : {0.0f, 1.0f, 2.0f, 2.7f, 3.5f}) {
    ShadeResult r = shade_at(shader, low_view(), {x, 0.2f, 0});
    glm::vec3 to_light = glm::vec3(0, 0, 1) - r.position;
    float d = glm::length(to_light);
    float window = std::clamp(1.0f - std::pow(d / 3.0f, 4.0f), 0.0f, 1.0f);
    float expected = kAlbedo * kInvPi * 6.0f * (to_light.z / d) / (d * d) * window;
    EXPECT_NEAR(r.color.x, expected, 1e-5f * expected + 1e-7f) << x;
    if (d >= 3.0f) {
      EXPECT_EQ(r.color.x, 0.0f);
    }
  }
}

TEST(Analytic, SmoothSphereUnderTheSun) {
  // Interpolated normals of a finely tessellated sphere give the analytic n.l shading, and
  // points on the lit side never shadow themselves (no (sun, ball, ball) triple).
  Scene scene;
  uint32_t white = test::add_material(scene, glm::vec3(kAlbedo));
  uint32_t ball = test::add_object(scene, test::sphere_mesh({0, 0, 0}, 1.0f, 96, 192, white), "ball");
  PunctualLight sun;
  sun.type = LightType::directional;
  sun.direction = glm::normalize(glm::vec3(-1, 2, -1));
  sun.intensity = glm::vec3(2.0f);
  scene.punctual_lights.push_back(sun);
  RayScene rays(scene);
  Shader shader(rays, lambert_settings());
  View view{test::look({3, -3, 2}, {0, 0, 0}, 40.0f), 96, 96};
  std::vector<ShadeRequest> requests;
  for (int j = 0; j < 24; ++j)
    for (int i = 0; i < 24; ++i) requests.push_back({uint32_t(requests.size()), 4.0f * float(i) + 2.0f, 4.0f * float(j) + 2.0f});
  ShadeBatch batch;
  shader.shade(view, requests, batch);
  int lit = 0;
  for (const ShadeResult& r : batch.results) {
    if (!r.hit) continue;
    EXPECT_EQ(r.object, ball);
    glm::vec3 n = glm::normalize(r.position);
    float cos_sun = glm::dot(n, -sun.direction);
    if (cos_sun > 0.05f) {
      ++lit;
      EXPECT_NEAR(r.color.x, kAlbedo * kInvPi * 2.0f * cos_sun, 0.01f * kAlbedo * kInvPi * 2.0f) << r.id;
      EXPECT_EQ(r.triple_count, 0u) << r.id;
    } else if (cos_sun < -0.05f) {
      EXPECT_EQ(r.color.x, 0.0f);
    }
  }
  EXPECT_GT(lit, 50);
}

TEST(Analytic, SphericalLuminaire) {
  // A uniformly emitting sphere of radius R seen from distance d at elevation angle theta
  // (fully above the horizon): E = pi L (R/d)^2 cos(theta). Its far side faces away and is
  // never traced; it reports no triple with itself.
  Scene scene;
  add_floor(scene);
  uint32_t glow = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(2.0f));
  const glm::vec3 centre(0, 0, 2.0f);
  const float radius = 0.5f;
  uint32_t bulb = test::add_object(scene, test::sphere_mesh(centre, radius, 64, 128, glow), "bulb");
  test::add_area_light(scene, bulb);
  RayScene rays(scene);
  ShaderSettings settings = lambert_settings();
  settings.area_light_samples = 4096;
  Shader shader(rays, settings);
  for (glm::vec3 target : {glm::vec3(0, 0, 0), glm::vec3(1, 0.5f, 0), glm::vec3(-1.5f, -1, 0)}) {
    ShadeBatch batch;
    ShadeResult r = shade_at(shader, low_view(), target, &batch);
    ASSERT_TRUE(r.hit);
    glm::vec3 to_centre = centre - r.position;
    float d = glm::length(to_centre);
    // The tessellated sphere is a little smaller than the true one: (1 - ~0.1%) in area.
    float expected = kAlbedo * kInvPi * float(M_PI) * 2.0f * (radius / d) * (radius / d) * (to_centre.z / d);
    EXPECT_NEAR(r.color.x, expected, 0.015f * expected) << target.x;
    EXPECT_EQ(r.triple_count, 0u);
  }
}

// An independent GGX + Schlick + separable Smith evaluation, written out from the formulas.
double reference_specular(double alpha, double f0, glm::dvec3 n, glm::dvec3 wo, glm::dvec3 wi) {
  glm::dvec3 h = glm::normalize(wo + wi);
  double nh = glm::dot(n, h), nl = glm::dot(n, wi), nv = glm::dot(n, wo), vh = glm::dot(wo, h);
  double a2 = alpha * alpha;
  double d = a2 / (M_PI * std::pow(nh * nh * (a2 - 1) + 1, 2));
  auto g1 = [&](double c) { return 2 * c / (c + std::sqrt(a2 + (1 - a2) * c * c)); };
  double f = f0 + (1 - f0) * std::pow(1 - vh, 5);
  return (1 - f) * 0.0 + f * d * g1(nl) * g1(nv) / (4 * nl * nv);
}

TEST(Analytic, SpecularHighlightOfAMetal) {
  Scene scene;
  uint32_t metal = test::add_material(scene, glm::vec3(0.9f), 1.0f, 0.4f);
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, metal), "floor");
  const glm::vec3 light_pos(-2, 0.5f, 2);
  scene.punctual_lights.push_back(test::point_light(light_pos, glm::vec3(10.0f)));
  RayScene rays(scene);
  Shader shader(rays, ShaderSettings{});
  const View view = low_view();
  for (glm::vec3 target : {glm::vec3(0, 0, 0), glm::vec3(1, 0.2f, 0), glm::vec3(-0.5f, 0.5f, 0), glm::vec3(3, -1, 0)}) {
    ShadeResult r = shade_at(shader, view, target);
    ASSERT_TRUE(r.hit);
    glm::dvec3 p(r.position), wi = glm::normalize(glm::dvec3(light_pos) - p), wo = glm::normalize(glm::dvec3(view.camera.eye) - p);
    double d2 = glm::dot(glm::dvec3(light_pos) - p, glm::dvec3(light_pos) - p);
    double expected = reference_specular(0.16, 0.9, {0, 0, 1}, wo, wi) * 10.0 * wi.z / d2;  // metal: no diffuse
    EXPECT_NEAR(r.color.x, expected, 1e-4 * expected + 1e-7);
  }
}

// The punctual lights' specular part of a result, recomputed for other eyes by
// the shader's PunctualSpecularModel from the result's lights, normals and material, equals what the
// shader computes from those eyes (docs/render.md, "Punctual highlights"). A smooth metal sphere
// under a point light and a spot light, a box shadowing part of it from the point light; a
// dielectric floor beside it.
TEST(Analytic, PunctualSpecularIsTheShadersHighlightFromAnyEye) {
  Scene scene;
  const uint32_t metal = test::add_material(scene, glm::vec3(0.9f, 0.7f, 0.3f), 1.0f, 0.3f);
  const uint32_t plastic = test::add_material(scene, glm::vec3(0.5f), 0.0f, 0.5f);
  test::add_object(scene, test::sphere_mesh({0, 0, 1}, 1.0f, 48, 96, metal), "ball");
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, plastic), "floor");
  test::add_object(scene, test::box_mesh({1.6f, -0.3f, 1.2f}, {1.9f, 0.3f, 1.5f}, plastic, false), "blocker");
  scene.punctual_lights.push_back(test::point_light({3, 0, 1.6f}, glm::vec3(20.0f)));
  PunctualLight spot = test::point_light({-1, -3, 4}, glm::vec3(30.0f, 25.0f, 20.0f));
  spot.type = LightType::spot;
  spot.direction = glm::normalize(glm::vec3(1, 3, -3));
  spot.inner_cone_cos = 0.95f, spot.outer_cone_cos = 0.8f;
  scene.punctual_lights.push_back(spot);
  RayScene rays(scene);
  Shader shader(rays, ShaderSettings{});
  const PunctualSpecularModel model = shader.punctual_specular_model();
  const glm::vec3 eyes[] = {{5, -1, 2.5f}, {4, 3, 3}, {-2, -5, 2}, {0.5f, -4, 5}};
  int compared = 0, blocked = 0, turned = 0;
  for (int k = 0; k < 400; ++k) {
    // Points on the sphere's upper half and on the floor around it.
    const float phi = 0.37f * float(k), z = 0.2f + 0.8f * float(k % 20) / 20.0f;
    const glm::vec3 target = k % 4 == 3 ? glm::vec3(2.5f * std::cos(phi), 2.5f * std::sin(phi), 0.0f)
                                        : glm::vec3(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), 1 + z);
    const View from{test::look(eyes[k % 4], target), 512, 512};
    const ShadeResult a = shade_at(shader, from, target);
    if (!a.hit || glm::distance(a.position, target) > 1e-3f) continue;
    blocked += (a.punctual_lights & 1u) == 0 && a.object == 0;
    const PunctualSurface surface{a.position, a.shading_normal, a.normal, a.material, a.punctual_lights};
    // From the shading eye: the result's own highlight.
    const glm::vec3 own = model.specular(surface, from.camera.eye);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(own[c], a.punctual_specular[c], 1e-5f * (1 + a.punctual_specular[c])) << k;
    // From the other eyes that see the same point: what the shader computes there.
    for (const glm::vec3& eye : eyes) {
      const View to{test::look(eye, target), 512, 512};
      const ShadeResult b = shade_at(shader, to, target);
      if (!b.hit || b.object != a.object || glm::distance(b.position, a.position) > 1e-4f) continue;
      ASSERT_EQ(b.punctual_lights, a.punctual_lights) << k;
      const glm::vec3 now = model.specular(surface, eye);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(now[c], b.punctual_specular[c], 2e-3f * (b.punctual_specular[c] + 0.01f)) << k;
      ++compared;
      turned += glm::distance(now, own) > 0.05f * (glm::length(own) + 0.01f);
    }
    // Without lights nothing is reflected; the metal's light is all specular.
    EXPECT_EQ(model.specular({a.position, a.shading_normal, a.normal, a.material, 0}, from.camera.eye),
              glm::vec3(0.0f));
    if (a.object == 0)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.punctual_specular[c], a.color[c], 1e-6f * (1 + a.color[c]));
  }
  EXPECT_GT(compared, 250);  // 333 when written
  EXPECT_GT(blocked, 5);   // the box shadows part of the ball from the point light
  EXPECT_GT(turned, 80);    // the highlights moved with the eye (107 when written)
}

TEST(Analytic, GlossyReflectionSeesALitWall) {
  // A near-mirror white metal floor reflects a Lambertian wall lit by a directional light;
  // F0 = 1 makes the reflection equal to the wall's radiance (G ~ 1 at low roughness).
  Scene scene;
  uint32_t mirror = test::add_material(scene, glm::vec3(1.0f), 1.0f, 0.05f);
  uint32_t white = test::add_material(scene, glm::vec3(kAlbedo));
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, mirror), "floor");
  test::add_object(scene, test::quad_mesh({-3, -10, 0}, {0, 20, 0}, {0, 0, 20}, white), "wall");  // x = -3 facing +x
  PunctualLight sun;
  sun.type = LightType::directional;
  sun.direction = glm::normalize(glm::vec3(-1, 0.3f, -0.2f));  // hits the wall; its mirror image misses the camera
  sun.intensity = glm::vec3(2.0f);
  scene.punctual_lights.push_back(sun);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::glossy;
  settings.glossy_samples = 64;
  Shader glossy(rays, settings);
  settings.kind = ShaderKind::direct;
  Shader direct(rays, settings);
  const glm::vec3 eye(2, 0, 1);
  const View view{test::look(eye, {-1, 0, 0}), 64, 64};
  for (glm::vec3 target : {glm::vec3(-1, 0, 0), glm::vec3(-1.5f, 0.5f, 0), glm::vec3(-2, -0.5f, 0)}) {
    ShadeResult g = shade_at(glossy, view, target), d = shade_at(direct, view, target);
    ASSERT_TRUE(g.hit);
    // The wall point seen in the mirror, and its radiance towards the floor point.
    glm::vec3 mirrored_eye(eye.x, eye.y, -eye.z);
    glm::vec3 dir = glm::normalize(g.position - mirrored_eye);
    glm::vec3 wall_point = g.position + dir * ((-3.0f - g.position.x) / dir.x);
    ShadeResult w = shade_at(direct, View{test::look(g.position + glm::vec3(0, 0, 1e-3f), wall_point), 64, 64}, wall_point);
    ASSERT_TRUE(w.hit);
    ASSERT_EQ(w.object, 1u);
    EXPECT_GT(w.color.x, 0.1f);
    EXPECT_LT(d.color.x, 1e-3f * w.color.x);
    EXPECT_NEAR(g.color.x - d.color.x, w.color.x, 0.03f * w.color.x) << "at " << target.x;
  }
}

}  // namespace
}  // namespace epi

namespace epi {
namespace {

TEST(Analytic, MirrorLikeFloorReflectsAnAreaLight) {
  // A near-mirror white metal floor under a big emitter: where the whole GGX lobe sees the
  // emitter, the reflected radiance is Le times the lobe's directional albedo. Glossy mode
  // finds it by MIS of light samples and GGX rays; light samples alone are far noisier.
  Scene scene;
  uint32_t mirror = test::add_material(scene, glm::vec3(1.0f), 1.0f, 0.1f);
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, mirror), "floor");
  const float le = 2.0f;
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(le));
  uint32_t panel = test::add_object(scene, test::quad_mesh({-1, -1, 1}, {0, 2, 0}, {2, 0, 0}, emitter), "panel");
  test::add_area_light(scene, panel);
  RayScene rays(scene);
  ShaderSettings settings;
  settings.kind = ShaderKind::glossy;
  settings.area_light_samples = 16;
  settings.glossy_samples = 64;
  Shader glossy(rays, settings);
  settings.kind = ShaderKind::direct;
  Shader direct(rays, settings);
  const glm::vec3 eye(0, -3, 1);
  const View view{test::look(eye, {0, -1.5f, 0}), 64, 64};
  double glossy_error = 0.0, direct_error = 0.0;
  int points = 0;
  for (float dx : {-0.2f, 0.0f, 0.15f})
    for (float dy : {-0.1f, 0.0f, 0.1f}) {
      ShadeResult g = shade_at(glossy, view, {dx, -1.5f + dy, 0}), d = shade_at(direct, view, {dx, -1.5f + dy, 0});
      ASSERT_TRUE(g.hit);
      // Directional albedo of the GGX lobe for wo, by importance sampling the half vector.
      BrdfParams brdf = BrdfParams::from(scene.materials[mirror], true);
      glm::vec3 wo = glm::normalize(eye - g.position);
      double albedo = 0.0;
      const int n = 4096;
      Rng rng(99);
      for (int i = 0; i < n; ++i) {
        glm::vec3 h = sample_ggx_half(rng.uniform(), rng.uniform(), brdf.alpha);
        float v_dot_h = glm::dot(wo, h);
        glm::vec3 wi = 2.0f * v_dot_h * h - wo;
        if (v_dot_h <= 0.0f || wi.z <= 0.0f) continue;
        albedo += smith_g1(wi.z, brdf.alpha) * smith_g1(wo.z, brdf.alpha) * v_dot_h / (wo.z * h.z);  // F = 1
      }
      double expected = le * albedo / n;
      EXPECT_NEAR(g.color.x, expected, 0.05 * expected) << dx << "," << dy;
      glossy_error += std::abs(g.color.x - expected) / expected;
      direct_error += std::abs(d.color.x - expected) / expected;
      ++points;
    }
  EXPECT_LT(glossy_error, 0.5 * direct_error);
}

// A request's effort (ShadeRequest::effort) multiplies the primary hit's estimates: with effort k
// the shader gives the bits a shader with k times the area-light samples, glossy rays and gi paths
// gives (and traces as many rays), for each shader kind; effort 0 counts as 1; and the estimate's
// spread over many points of a penumbra shrinks at least as 1 / sqrt(k).
TEST(Analytic, EffortMultipliesThePrimaryHitsSampleCounts) {
  Scene scene;
  uint32_t floor = test::add_material(scene, glm::vec3(0.7f), 0.0f, 0.4f);  // a glossy dielectric
  test::add_object(scene, test::quad_mesh({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, floor), "floor");
  uint32_t grey = test::add_material(scene, glm::vec3(0.5f));
  test::add_object(scene, test::quad_mesh({-0.4f, -0.4f, 0.5f}, {0.8f, 0, 0}, {0, 0.8f, 0}, grey), "blocker");
  uint32_t emitter = test::add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(4.0f));
  uint32_t light = test::add_object(scene, test::quad_mesh({-0.5f, -0.5f, 1.5f}, {0, 1, 0}, {1, 0, 0}, emitter), "panel");
  test::add_area_light(scene, light);
  RayScene rays(scene);
  const View view{test::look({3, 0.5f, 3}, {0, 0, 0}), 64, 64};
  const ViewFrame frame(view);
  for (const ShaderKind kind : {ShaderKind::direct, ShaderKind::glossy, ShaderKind::gi}) {
    ShaderSettings settings;
    settings.kind = kind, settings.area_light_samples = 4, settings.glossy_samples = 2, settings.gi_paths = 2;
    const Shader shader(rays, settings);
    for (const int effort : {0, 1, 3, 5}) {
      const Shader reference(rays, with_effort(settings, std::max(effort, 1)));
      for (float x : {20.5f, 31.25f, 40.75f}) {
        ShadeRequest request{0, x, 33.5f};
        request.effort = uint8_t(effort);
        std::vector<BlockerTriple> triples, reference_triples;
        uint64_t n = 0, reference_n = 0;
        const ShadeResult r = shader.shade_one(frame, request, triples, n);
        request.effort = 1;
        const ShadeResult e = reference.shade_one(frame, request, reference_triples, reference_n);
        ASSERT_TRUE(r.hit);
        EXPECT_EQ(int(r.effort), std::max(effort, 1));
        EXPECT_EQ(n, reference_n);
        EXPECT_EQ(r.color, e.color) << int(kind) << " effort " << effort << " at " << x;
        EXPECT_EQ(r.view_dependent, e.view_dependent);
        EXPECT_EQ(triples, reference_triples);
      }
    }
  }
  // The spread of the direct estimate in the penumbra, effort 1 against 4.
  ShaderSettings settings = lambert_settings();
  settings.area_light_samples = 4;
  const Shader shader(rays, settings);
  auto spread = [&](int effort) {
    double sum = 0.0, sum2 = 0.0;
    const int n = 400;
    for (int k = 0; k < n; ++k) {
      const glm::vec3 target(0.55f + 0.0001f * float(k % 20), 0.0f, 0.0f);  // same irradiance, other streams
      const Projection p = project(view, target);
      ShadeRequest request{0, p.pixel.x + 0.001f * float(k / 20), p.pixel.y};
      request.effort = uint8_t(effort);
      ShadeBatch batch;
      shader.shade(view, std::span(&request, 1), batch);
      const double v = batch.results[0].color.x;
      sum += v, sum2 += v * v;
    }
    return std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  };
  const double one = spread(1), four = spread(4);
  EXPECT_GT(one, 0.0);
  EXPECT_LT(four, 0.5 * one);  // 1 / sqrt(4) or better (the samples are stratified)
}

}  // namespace
}  // namespace epi

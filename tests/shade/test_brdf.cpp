// The BRDF and the warps: normalisation, reciprocity, energy, sampling densities.
#include <gtest/gtest.h>

#include "shade/brdf.h"
#include "shade/sampling.h"

namespace epi {
namespace {

glm::vec3 from_angles(float theta, float phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Midpoint quadrature of g(direction) over the upper hemisphere.
template <class G>
double integrate_hemisphere(G g, int n_theta = 500, int n_phi = 1000) {
  double sum = 0.0;
  for (int i = 0; i < n_theta; ++i) {
    double theta = (i + 0.5) * (M_PI / 2) / n_theta;
    for (int j = 0; j < n_phi; ++j) {
      double phi = (j + 0.5) * 2 * M_PI / n_phi;
      sum += g(from_angles(float(theta), float(phi))) * std::sin(theta);
    }
  }
  return sum * (M_PI / 2 / n_theta) * (2 * M_PI / n_phi);
}

TEST(Brdf, GgxDistributionIsNormalised) {
  for (float alpha : {0.1f, 0.3f, 0.6f, 1.0f}) {
    double integral = integrate_hemisphere([&](glm::vec3 h) { return ggx_d(h.z, alpha) * h.z; }, 4000, 4);
    EXPECT_NEAR(integral, 1.0, 2e-3) << "alpha " << alpha;
  }
}

TEST(Brdf, ReciprocalAndNonNegative) {
  Rng rng(7);
  const glm::vec3 n(0, 0, 1);
  for (int i = 0; i < 2000; ++i) {
    Material m;
    m.base_color = {rng.uniform(), rng.uniform(), rng.uniform()};
    m.metallic = rng.uniform();
    m.roughness = rng.uniform();
    BrdfParams p = BrdfParams::from(m, true);
    glm::vec3 a = from_angles(rng.uniform() * 1.5f, rng.uniform() * 6.28f);
    glm::vec3 b = from_angles(rng.uniform() * 1.5f, rng.uniform() * 6.28f);
    glm::vec3 fab = eval_brdf(p, n, a, b), fba = eval_brdf(p, n, b, a);
    for (int c = 0; c < 3; ++c) {
      ASSERT_GE(fab[c], 0.0f);
      ASSERT_NEAR(fab[c], fba[c], 1e-4f * std::max(1.0f, fab[c]));
    }
    EXPECT_EQ(eval_brdf(p, n, a, glm::vec3(b.x, b.y, -b.z)), glm::vec3(0.0f));  // below the surface
  }
}

TEST(Brdf, LambertOnlyIsAlbedoOverPi) {
  Material m;
  m.base_color = glm::vec3(0.25f, 0.5f, 0.75f);
  BrdfParams p = BrdfParams::from(m, false);
  double albedo = integrate_hemisphere([&](glm::vec3 wi) { return eval_brdf(p, {0, 0, 1}, from_angles(0.7f, 1.0f), wi).y * wi.z; });
  EXPECT_NEAR(albedo, 0.5, 1e-3);
}

TEST(Brdf, NeverCreatesEnergy) {
  // Directional albedo of a white surface stays below 1 (the separable Smith G and Schlick
  // Fresnel lose some energy at high roughness; they never add it).
  for (float metallic : {0.0f, 1.0f})
    for (float roughness : {0.2f, 0.5f, 1.0f})
      for (float theta_o : {0.0f, 0.8f, 1.4f}) {
        Material m;
        m.base_color = glm::vec3(1.0f);
        m.metallic = metallic;
        m.roughness = roughness;
        BrdfParams p = BrdfParams::from(m, true);
        glm::vec3 wo = from_angles(theta_o, 0.3f);
        double albedo = integrate_hemisphere([&](glm::vec3 wi) { return eval_brdf(p, {0, 0, 1}, wo, wi).x * wi.z; });
        EXPECT_LE(albedo, 1.0 + 5e-3) << metallic << " " << roughness << " " << theta_o;
        EXPECT_GT(albedo, 0.3) << metallic << " " << roughness << " " << theta_o;
      }
}

TEST(Sampling, WarpsFollowTheirDensities) {
  // Sample means against quadrature of the stated densities.
  const int n = 200000;
  Rng rng(3);
  double cos_mean = 0.0, h_mean = 0.0, tri_mean_a = 0.0;
  const float alpha = 0.4f;
  for (int i = 0; i < n; ++i) {
    float u1 = rng.uniform(), u2 = rng.uniform();
    glm::vec3 d = sample_cosine_hemisphere(u1, u2);
    ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
    cos_mean += d.z;
    h_mean += sample_ggx_half(u1, u2, alpha).z;
    glm::vec3 b = sample_triangle(u1, u2);
    ASSERT_NEAR(b.x + b.y + b.z, 1.0f, 1e-6f);
    tri_mean_a += b.x;
  }
  EXPECT_NEAR(cos_mean / n, 2.0 / 3.0, 3e-3);  // E[cos] under cos/pi
  double expected_h = integrate_hemisphere([&](glm::vec3 h) { return ggx_d(h.z, alpha) * h.z * h.z; }, 4000, 4);
  EXPECT_NEAR(h_mean / n, expected_h, 3e-3);
  EXPECT_NEAR(tri_mean_a / n, 1.0 / 3.0, 3e-3);  // uniform on the triangle: centroid
}

TEST(Sampling, FrameIsOrthonormal) {
  Rng rng(11);
  for (int i = 0; i < 1000; ++i) {
    glm::vec3 n = glm::normalize(glm::vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f));
    if (i == 0) n = glm::vec3(0, 0, -1);
    Frame f(n);
    EXPECT_NEAR(glm::dot(f.t, f.b), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.t, n), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(f.to_world({0, 0, 1}), n), 0.0f, 1e-6f);
  }
}

}  // namespace
}  // namespace epi

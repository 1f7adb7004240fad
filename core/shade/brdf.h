// glTF 2.0 metallic-roughness BRDF: Lambert diffuse plus GGX (Trowbridge-Reitz) specular
// with the separable Smith G and Schlick's Fresnel, F0 = mix(0.04, base_color, metallic).
// All directions are unit vectors in world space; n is the shading normal.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace epi {

struct BrdfParams {
  glm::vec3 diffuse{0.0f};  // base_color * (1 - metallic)
  glm::vec3 f0{0.04f};
  float alpha = 1.0f;       // roughness^2, clamped away from 0
  bool specular = true;     // false: the diffuse lobe alone (no Fresnel weighting)

  static BrdfParams from(const Material& m, bool specular) {
    BrdfParams p;
    float metallic = std::clamp(m.metallic, 0.0f, 1.0f);
    float roughness = std::clamp(m.roughness, 0.03f, 1.0f);
    p.diffuse = m.base_color * (1.0f - metallic);
    p.f0 = glm::mix(glm::vec3(0.04f), m.base_color, metallic);
    p.alpha = roughness * roughness;
    p.specular = specular;
    return p;
  }
};

inline float ggx_d(float n_dot_h, float alpha) {
  float a2 = alpha * alpha;
  float d = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
  return a2 / (float(M_PI) * d * d);
}
inline float smith_g1(float n_dot_v, float alpha) {
  float a2 = alpha * alpha;
  return 2.0f * n_dot_v / (n_dot_v + std::sqrt(a2 + (1.0f - a2) * n_dot_v * n_dot_v));
}
inline glm::vec3 schlick(const glm::vec3& f0, float cos_theta) {
  float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
  float m5 = (m * m) * (m * m) * m;
  return f0 + (glm::vec3(1.0f) - f0) * m5;
}

// The share of the diffuse lobe's light that its interface lets out towards a direction at
// cosine c to the normal, 1 - F(c) with a dielectric's F0 of 0.04 (eval_brdf_lobes' `transmitted`,
// outgoing half). It makes a diffuse colour depend on the view: 0.18 at c = 0.04, 0.93 at 0.5.
// The point cache shows a point's diffuse part scaled by its ratio between the current view and the
// view it was shaded from (docs/render.md, "Diffuse transmission").
inline float diffuse_transmission(float c) { return 1.0f - schlick(glm::vec3(0.04f), c).x; }

// The two lobes of f(wi, wo); zero when either direction is below the shading hemisphere.
struct BrdfValue {
  glm::vec3 diffuse{0.0f}, specular{0.0f};
  glm::vec3 sum() const { return diffuse + specular; }
};
inline BrdfValue eval_brdf_lobes(const BrdfParams& p, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
  BrdfValue value;
  float n_dot_l = glm::dot(n, wi), n_dot_v = glm::dot(n, wo);
  if (n_dot_l <= 0.0f || n_dot_v <= 0.0f) return value;
  if (!p.specular) {
    value.diffuse = p.diffuse * float(1.0 / M_PI);
    return value;
  }
  glm::vec3 h = glm::normalize(wi + wo);
  float v_dot_h = std::max(glm::dot(wo, h), 0.0f);
  glm::vec3 f = schlick(p.f0, v_dot_h);
  float d = ggx_d(std::max(glm::dot(n, h), 0.0f), p.alpha);
  float g = smith_g1(n_dot_l, p.alpha) * smith_g1(n_dot_v, p.alpha);
  // The diffuse lobe gets what the specular interface transmits, in and out (reciprocal,
  // and unlike glTF's (1 - F(v.h)) weighting it does not create energy at grazing angles).
  glm::vec3 transmitted = (glm::vec3(1.0f) - schlick(p.f0, n_dot_l)) * (glm::vec3(1.0f) - schlick(p.f0, n_dot_v));
  value.diffuse = transmitted * p.diffuse * float(1.0 / M_PI);
  value.specular = f * (d * g / (4.0f * n_dot_l * n_dot_v));
  return value;
}

// f(wi, wo).
inline glm::vec3 eval_brdf(const BrdfParams& p, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
  return eval_brdf_lobes(p, n, wo, wi).sum();
}

// A half vector from D(h) * (n.h), in the local frame (z = normal); pdf(h) = D(h) * (n.h).
inline glm::vec3 sample_ggx_half(float u1, float u2, float alpha) {
  float a2 = alpha * alpha;
  float cos2 = (1.0f - u1) / (1.0f + (a2 - 1.0f) * u1);
  float cos_t = std::sqrt(std::max(cos2, 0.0f)), sin_t = std::sqrt(std::max(0.0f, 1.0f - cos2));
  float phi = 2.0f * float(M_PI) * u2;
  return glm::vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
}

// pdf of wi = reflect(-wo, h) when h is drawn by sample_ggx_half.
inline float ggx_reflection_pdf(const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi, float alpha) {
  glm::vec3 h = glm::normalize(wi + wo);
  float n_dot_h = glm::dot(n, h), v_dot_h = glm::dot(wo, h);
  if (n_dot_h <= 0.0f || v_dot_h <= 0.0f) return 0.0f;
  return ggx_d(n_dot_h, alpha) * n_dot_h / (4.0f * v_dot_h);
}

inline float rgb_luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace epi

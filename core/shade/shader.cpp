#include "shade/shader.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/concurrent_vector.h>
#include <tbb/parallel_for.h>

#include "shade/brdf.h"
#include "shade/sampling.h"

namespace epi {

namespace {

// Random streams of one request, one per use.
enum Stream : uint64_t { kStreamArea = 1, kStreamGlossy = 2, kStreamPath = 3, kStreamLightChoice = 5 };

float max_abs(const glm::vec3& p) { return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}); }
float max_component(const glm::vec3& c) { return std::max({c.x, c.y, c.z}); }

// Index i with cdf[i-1] <= u < cdf[i], and u rescaled to [0, 1) within that interval.
size_t pick(const std::vector<float>& cdf, float& u) {
  size_t i = size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
  i = std::min(i, cdf.size() - 1);
  float lo = i == 0 ? 0.0f : cdf[i - 1];
  float width = cdf[i] - lo;
  u = width > 0.0f ? std::clamp((u - lo) / width, 0.0f, 0.99999994f) : 0.5f;
  return i;
}
float probability(const std::vector<float>& cdf, size_t i) { return cdf[i] - (i == 0 ? 0.0f : cdf[i - 1]); }

// How many light and BRDF samples look for the same light (multiple importance sampling);
// specular_only: the BRDF samples come from the GGX lobe alone (glossy mode).
struct MisCounts {
  int light = 0, brdf = 0;
  bool specular_only = false;
};
// The power heuristic (Veach): weight of a sample whose strategy has density a, against b.
float power_heuristic(float a, float b) {
  if (!(b > 0.0f)) return 1.0f;  // the other strategy cannot produce this sample
  if (!(a > 0.0f)) return 0.0f;
  float r = b / a;
  return 1.0f / (1.0f + r * r);  // = a^2 / (a^2 + b^2), without overflow
}

// Stratum j of n on a sqrt(n) x sqrt(n) grid (random beyond the grid).
// The light choices of a hit's n area-light samples, stratified as the points on the lights are:
// sample j draws its choice from stratum (step j + offset) mod n of [0, 1), with `offset` random
// per hit (each sample's choice then uniform on [0, 1) and independent of its point on the light,
// so the estimate stays unbiased) and `step` coprime to n near n (sqrt 5 - 1) / 2 (consecutive
// samples, whose points lie in neighbouring strata, choose far apart). Each light then gets its
// share of the samples to within one, where independent choices split them at random
// (docs/render.md, "Light choice").
struct LightChoiceStrata {
  uint32_t n = 1, step = 1, offset = 0;
  LightChoiceStrata(int samples, uint32_t random) : n(uint32_t(std::max(samples, 1))), offset(random % n) {
    step = std::max(1u, uint32_t(std::lround(double(n) * 0.6180339887)));
    while (std::gcd(step, n) != 1) ++step;
  }
  float choice(int j, float jitter) const {
    const uint32_t stratum = uint32_t((uint64_t(step) * uint64_t(j) + offset) % n);
    return std::min((float(stratum) + jitter) / float(n), 0x1.fffffep-1f);
  }
};

glm::vec2 stratified(int j, int n, Rng& rng) {
  int m = int(std::sqrt(double(n)));
  float a = rng.uniform(), b = rng.uniform();
  if (j >= m * m) return {a, b};
  return {(float(j % m) + a) / float(m), (float(j / m) + b) / float(m)};
}

// Punctual light `light`'s direction wi from `position` and the radiance arriving there (its
// distance, range and cone falloff); false when the light is at the point.
bool punctual_incoming(const PunctualLight& light, const glm::vec3& position, glm::vec3& wi, glm::vec3& incoming) {
  incoming = light.intensity;
  if (light.type == LightType::directional) {
    wi = -glm::normalize(light.direction);
    return true;
  }
  glm::vec3 to_light = light.position - position;
  float d2 = glm::dot(to_light, to_light);
  float distance = std::sqrt(d2);
  if (!(distance > 0.0f)) return false;
  wi = to_light / distance;
  float attenuation = 1.0f / d2;
  if (light.range > 0.0f) {
    float r = distance / light.range;
    attenuation *= std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
  }
  if (light.type == LightType::spot) {
    float cd = glm::dot(glm::normalize(light.direction), -wi);
    float span = light.inner_cone_cos - light.outer_cone_cos;
    float t = span > 0.0f ? std::clamp((cd - light.outer_cone_cos) / span, 0.0f, 1.0f) : (cd > light.outer_cone_cos ? 1.0f : 0.0f);
    attenuation *= t * t;
  }
  incoming *= attenuation;
  return true;
}

}  // namespace

// A shading point: where a ray met a surface, oriented towards the ray's origin.
struct Shader::Surface {
  glm::vec3 position, geometric_normal, shading_normal, wo;
  uint32_t object = kNone, triangle = kNone;
  const Material* material = nullptr;
  bool front_face = true;
  float offset = 0.0f;  // absolute ray-start offset
};

// Whether the scene has area lights that emit (their sampling CDF ends at a positive total).
static bool lights_by_area(const RayScene& scene) { return !scene.area_light_cdf().empty() && scene.area_light_cdf().back() > 0.0f; }

// Area-light samples per hit from which their shadow rays go as packets (RayScene::occluded16).
constexpr int kPacketMinSamples = 4;

// Everything one request needs while tracing: counters and the triples it met.
struct Shader::Tracer {
  const RayScene& scene;
  const ShaderSettings& settings;
  std::vector<BlockerTriple>* triples;  // null: do not record
  size_t first_triple = 0;
  uint64_t rays = 0;
  bool area_triples = true;  // with triples: area lights' too (ShadeRequest::blockers)

  RayHit trace(const Ray& ray) {
    ++rays;
    return scene.intersect(ray);
  }

  Surface surface(const RayHit& hit, const Ray& ray) const {
    const Scene& s = scene.scene();
    const Mesh& mesh = s.meshes[s.objects[hit.object].mesh];
    const glm::uvec3& tri = mesh.triangles[hit.triangle];
    const glm::vec3 w(1.0f - hit.u - hit.v, hit.u, hit.v);
    const glm::vec3 &p0 = mesh.positions[tri[0]], &p1 = mesh.positions[tri[1]], &p2 = mesh.positions[tri[2]];
    const glm::mat3& to_world_normal = scene.normal_to_world(hit.object);
    Surface out;
    out.object = hit.object;
    out.triangle = hit.triangle;
    out.position = glm::vec3(scene.object_to_world(hit.object) * glm::vec4(w.x * p0 + w.y * p1 + w.z * p2, 1.0f));
    out.wo = -ray.direction;
    glm::vec3 ng = to_world_normal * glm::cross(p1 - p0, p2 - p0);
    float length = glm::length(ng);
    ng = length > 0.0f ? ng / length : out.wo;
    out.front_face = glm::dot(ng, ray.direction) < 0.0f;
    if (!out.front_face) ng = -ng;
    out.geometric_normal = ng;
    out.shading_normal = ng;
    if (!mesh.normals.empty()) {
      glm::vec3 ns = to_world_normal * (w.x * mesh.normals[tri[0]] + w.y * mesh.normals[tri[1]] + w.z * mesh.normals[tri[2]]);
      float ns_length = glm::length(ns);
      if (ns_length > 0.0f) {
        ns /= ns_length;
        if (!out.front_face) ns = -ns;
        if (glm::dot(ns, out.wo) > 0.0f) out.shading_normal = ns;
      }
    }
    out.material = &s.materials[mesh.material_of(hit.triangle)];
    out.offset = settings.ray_offset * std::max(1.0f, max_abs(out.position));
    return out;
  }

  Ray spawn(const Surface& s, const glm::vec3& direction, float tfar = 1e30f) const {
    Ray r;
    float side = glm::dot(direction, s.geometric_normal) >= 0.0f ? 1.0f : -1.0f;
    r.origin = s.position + side * s.offset * s.geometric_normal;
    r.direction = direction;
    r.tnear = 0.0f;
    r.tfar = tfar;
    return r;
  }

  // A shadow ray from s to a point, stopping end_offset short of it.
  Ray spawn_to(const Surface& s, const glm::vec3& target, const glm::vec3& wi, float end_offset) const {
    Ray r = spawn(s, wi);
    glm::vec3 to_target = target - r.origin;
    float distance = glm::length(to_target);
    r.direction = to_target / distance;
    r.tfar = std::max(0.0f, distance - end_offset);
    return r;
  }

  // Whether the light is visible along the shadow ray; a blocked ray reports its triple.
  bool visible(const Surface& s, const Ray& shadow_ray, uint32_t light, uint32_t light_object) {
    ++rays;
    // An unblocked ray costs about the same either way; a blocked one is named by intersect.
    const bool punctual = light < scene.punctual_lights().size();
    if (!triples || !settings.record_blockers || (!punctual && !area_triples)) return !scene.occluded(shadow_ray);
    RayHit hit = scene.intersect(shadow_ray);
    if (!hit.hit) return true;
    if (hit.object != light_object) {
      BlockerTriple t{light, hit.object, s.object};
      // Hard shadows only: area lights' triples (soft edges, off by default) are kept as found,
      // since their many samples per result would pay the check many times.
      if (std::find(triples->begin() + std::ptrdiff_t(first_triple), triples->end(), t) == triples->end() &&
          (!punctual || sole_blocker(shadow_ray, hit, light_object)))
        triples->push_back(t);
    }
    return false;
  }

  // Whether nothing but the first blocker lies on the rest of the shadow ray: only then does that
  // blocker's shadow edge show here. Where another object also blocks the light (a ceiling panel's
  // shadow on a ceiling that a wall shades anyway), the edge is invisible, and it would only make
  // its pixels complex (docs/render.md, "Shadow edges only where they show"). The ray is traced
  // back from its far end (the light) to the first blocker: the first thing it meets from that side
  // is the first blocker itself (any of its faces) when nothing else is in the way.
  bool sole_blocker(const Ray& ray, const RayHit& first, uint32_t light_object) {
    if (!(ray.tfar < 1e29f)) return true;  // directional: no far end to start from
    Ray back;
    back.origin = ray.origin + ray.direction * ray.tfar;
    back.direction = -ray.direction;
    back.tnear = 0.0f;
    // Just past the blocker's face, by at most half the way from the ray's start to it, so that the
    // ray back never reaches the receiver (a blocker resting on it: a contact shadow).
    back.tfar = (ray.tfar - first.t) + std::min(settings.ray_offset * std::max(1.0f, ray.tfar), 0.5f * first.t);
    ++rays;
    const RayHit hit = scene.intersect(back);
    return !hit.hit || hit.object == first.object || hit.object == light_object;
  }

  // Reflected radiance from punctual light i, per lobe.
  BrdfValue punctual(const Surface& s, const BrdfParams& brdf, uint32_t i) {
    const PunctualLight& light = scene.punctual_lights()[i];
    glm::vec3 wi, incoming;
    if (!punctual_incoming(light, s.position, wi, incoming)) return {};
    float cos_s = glm::dot(s.shading_normal, wi);
    if (cos_s <= 0.0f || glm::dot(s.geometric_normal, wi) <= 0.0f || max_component(incoming) <= 0.0f) return {};
    BrdfValue f = eval_brdf_lobes(brdf, s.shading_normal, s.wo, wi);
    if (max_component(f.sum()) <= 0.0f) return {};
    Ray shadow = light.type == LightType::directional ? spawn(s, wi) : spawn_to(s, light.position, wi, s.offset);
    if (!visible(s, shadow, i, kNone)) return {};
    return {f.diffuse * incoming * cos_s, f.specular * incoming * cos_s};
  }

  // One area-light sample before its shadow ray: light by power, triangle by power, point
  // uniformly; u picks the triangle and the point, u0 the light. `value`: reflected radiance / pdf
  // per lobe if the light is visible, MIS-weighted against mis.brdf BRDF samples when the path
  // tracer also reaches lights by BRDF sampling; false where the sample adds nothing whatever the
  // shadow ray finds.
  struct AreaSample {
    Ray shadow;
    uint32_t light = 0, light_object = 0;  // the light's number (punctual lights first) and object
    BrdfValue value;
  };
  bool prepare_area_sample(const Surface& s, const BrdfParams& brdf, float u0, glm::vec2 u, MisCounts mis, AreaSample& out) {
    const std::vector<AreaLight>& lights = scene.area_lights();
    size_t l = pick(scene.area_light_cdf(), u0);
    const AreaLight& light = lights[l];
    if (light.triangle_cdf.empty()) return false;
    size_t k = pick(light.triangle_cdf, u.x);
    const glm::vec3* v = &light.triangle_vertices[3 * k];
    glm::vec3 b = sample_triangle(u.x, u.y);
    glm::vec3 point = b.x * v[0] + b.y * v[1] + b.z * v[2];
    glm::vec3 cross = glm::cross(v[1] - v[0], v[2] - v[0]);
    float double_area = glm::length(cross);
    glm::vec3 to_light = point - s.position;
    float d2 = glm::dot(to_light, to_light);
    if (!(double_area > 0.0f) || !(d2 > 0.0f)) return false;
    float distance = std::sqrt(d2);
    glm::vec3 wi = to_light / distance;
    float cos_light = -glm::dot(cross / double_area, wi);  // emission leaves the front face
    float cos_s = glm::dot(s.shading_normal, wi);
    if (cos_light <= 0.0f || cos_s <= 0.0f || glm::dot(s.geometric_normal, wi) <= 0.0f) return false;
    BrdfValue lobes = eval_brdf_lobes(brdf, s.shading_normal, s.wo, wi);
    const glm::vec3& emission = scene.scene().materials[light.triangle_materials[k]].emission;
    if (max_component(lobes.sum()) <= 0.0f || max_component(emission) <= 0.0f) return false;
    float pdf_area = probability(scene.area_light_cdf(), l) * probability(light.triangle_cdf, k) / (0.5f * double_area);
    float light_offset = settings.ray_offset * std::max(1.0f, max_abs(point));
    out.shadow = spawn_to(s, point, wi, light_offset);
    out.light = uint32_t(scene.punctual_lights().size() + l);
    out.light_object = light.object;
    BrdfValue f = lobes;
    if (mis.brdf > 0 && scene.area_light_mapped(l)) {
      float pdf_light = pdf_area * d2 / cos_light;  // solid angle
      if (mis.specular_only) {
        float pdf_glossy = ggx_reflection_pdf(s.shading_normal, s.wo, wi, brdf.alpha);
        f.specular *= power_heuristic(float(mis.light) * pdf_light, float(mis.brdf) * pdf_glossy);
      } else {
        const float weight = power_heuristic(float(mis.light) * pdf_light, float(mis.brdf) * brdf_pdf(s, brdf, wi));
        f.diffuse *= weight, f.specular *= weight;
      }
    }
    const glm::vec3 scale = emission * (cos_s * cos_light / (d2 * pdf_area));
    out.value = {f.diffuse * scale, f.specular * scale};
    return true;
  }

  BrdfValue area_sample(const Surface& s, const BrdfParams& brdf, float u0, glm::vec2 u, MisCounts mis) {
    AreaSample a;
    if (!prepare_area_sample(s, brdf, u0, u, mis, a) || !visible(s, a.shadow, a.light, a.light_object)) return {};
    return a.value;
  }

  // Solid-angle density with which one area-light sample from s picks the point hit on an
  // emitter (0 when no area light covers it; infinite for an unmapped light, which light
  // sampling alone then covers).
  float light_pdf(const Surface& s, const Surface& emitter) const {
    uint32_t l = scene.area_light_of_object(emitter.object);
    if (l == kNone) return 0.0f;
    if (!scene.area_light_mapped(l)) return std::numeric_limits<float>::infinity();
    uint32_t k = scene.light_triangle(l, emitter.triangle);
    if (k == kNone) return 0.0f;
    const AreaLight& light = scene.area_lights()[l];
    const glm::vec3* v = &light.triangle_vertices[3 * k];
    float area = 0.5f * glm::length(glm::cross(v[1] - v[0], v[2] - v[0]));
    glm::vec3 to_light = emitter.position - s.position;
    float d2 = glm::dot(to_light, to_light);
    float cos_light = glm::dot(emitter.geometric_normal, emitter.wo);
    if (!(area > 0.0f) || !(cos_light > 0.0f)) return 0.0f;
    return probability(scene.area_light_cdf(), l) * probability(light.triangle_cdf, k) / area * d2 / cos_light;
  }

  bool has_area_lights() const { return lights_by_area(scene); }

  // Direct lighting: every punctual light once, area lights with n stratified samples from
  // one stream each (primary hits), or from the given stream (deeper hits). brdf_samples > 0:
  // that many BRDF samples will also look for the lights from s (multiple importance sampling).
  // Per lobe: the specular lobe's share is what depends on the eye (docs/render.md, "View-dependent shading").
  // With `lights` and `punctual_specular`: which of punctual lights 0-31 gave light, and their
  // specular part (ShadeResult's fields of those names).
  BrdfValue direct_lobes(const Surface& s, int n, uint64_t key, Rng* stream, int brdf_samples = 0, bool specular_only = false,
                         uint32_t* lights = nullptr, glm::vec3* punctual_specular = nullptr) {
    BrdfParams brdf = BrdfParams::from(*s.material, settings.specular);
    BrdfValue sum;
    auto add = [](BrdfValue& to, const BrdfValue& v) { to.diffuse += v.diffuse, to.specular += v.specular; };
    for (uint32_t i = 0; i < scene.punctual_lights().size(); ++i) {
      const BrdfValue v = punctual(s, brdf, i);
      add(sum, v);
      if (lights && i < 32 && max_component(v.sum()) > 0.0f) *lights |= 1u << i, *punctual_specular += v.specular;
    }
    if (n > 0 && has_area_lights()) {
      BrdfValue area;
      // Where no triple is recorded, the samples' shadow rays leave from one point towards the
      // lights: traced 16 at a time as a packet, then summed in sample order (the same
      // bits as one at a time: docs/render.md, "Shadow rays in packets").
      const bool packets = n >= kPacketMinSamples && (!triples || !settings.record_blockers || !area_triples);
      Ray shadows[16];
      BrdfValue values[16];
      int batched = 0;
      auto flush = [&] {
        bool blocked[16];
        scene.occluded16(shadows, size_t(batched), blocked);
        rays += uint64_t(batched);
        for (int i = 0; i < batched; ++i)
          if (!blocked[i]) add(area, values[i]);
        batched = 0;
      };
      // With one area light the choice is no choice: nothing drawn for it (the same bits as before).
      const bool choose = scene.area_light_cdf().size() > 1 && n > 1;
      const LightChoiceStrata choices(n, !choose ? 0u : stream ? stream->next() : Rng(key, kStreamLightChoice, 0).next());
      for (int j = 0; j < n; ++j) {
        Rng own = stream ? Rng(0) : Rng(key, kStreamArea, uint64_t(j));
        Rng& rng = stream ? *stream : own;
        glm::vec2 u = stratified(j, n, rng);
        const MisCounts mis{n, brdf_samples, specular_only};
        const float jitter = rng.uniform();
        const float u0 = choose ? choices.choice(j, jitter) : jitter;
        if (!packets) {
          add(area, area_sample(s, brdf, u0, u, mis));
        } else if (AreaSample a; prepare_area_sample(s, brdf, u0, u, mis, a)) {
          shadows[batched] = a.shadow, values[batched] = a.value;
          if (++batched == 16) flush();
        }
      }
      if (batched > 0) flush();
      sum.diffuse += area.diffuse / float(n), sum.specular += area.specular / float(n);
    }
    return sum;
  }
  glm::vec3 direct(const Surface& s, int n, uint64_t key, Rng* stream, int brdf_samples = 0, bool specular_only = false) {
    return direct_lobes(s, n, key, stream, brdf_samples, specular_only).sum();
  }

  glm::vec3 emitted(const Surface& s) const { return s.front_face ? s.material->emission : glm::vec3(0.0f); }

  // Glossy reflection: n rays from the GGX lobe, each reflected hit lit directly; a reflected
  // emitter adds its emission, MIS-weighted against the primary hit's light samples.
  glm::vec3 glossy(const Surface& s, uint64_t key) {
    if (!settings.specular || settings.glossy_samples <= 0) return glm::vec3(0.0f);
    BrdfParams brdf = BrdfParams::from(*s.material, true);
    const glm::vec3& n = s.shading_normal;
    float n_dot_v = glm::dot(n, s.wo);
    Frame frame(n);
    glm::vec3 sum(0.0f);
    for (int j = 0; j < settings.glossy_samples; ++j) {
      Rng rng(key, kStreamGlossy, uint64_t(j));
      glm::vec2 u = stratified(j, settings.glossy_samples, rng);
      glm::vec3 h = frame.to_world(sample_ggx_half(u.x, u.y, brdf.alpha));
      float v_dot_h = glm::dot(s.wo, h), n_dot_h = glm::dot(n, h);
      if (v_dot_h <= 0.0f || n_dot_h <= 0.0f) continue;
      glm::vec3 wi = 2.0f * v_dot_h * h - s.wo;
      float n_dot_l = glm::dot(n, wi);
      if (n_dot_l <= 0.0f || glm::dot(s.geometric_normal, wi) <= 0.0f) continue;
      // f_spec * cos / pdf with pdf = D (n.h) / (4 v.h)
      glm::vec3 weight = schlick(brdf.f0, v_dot_h) *
                         (smith_g1(n_dot_l, brdf.alpha) * smith_g1(n_dot_v, brdf.alpha) * v_dot_h / (n_dot_v * n_dot_h));
      Ray ray = spawn(s, wi);
      RayHit hit = trace(ray);
      if (!hit.hit) continue;
      Surface reflected = surface(hit, ray);
      sum += weight * direct(reflected, settings.glossy_light_samples, 0, &rng);
      if (max_component(emitted(reflected)) > 0.0f) {
        float pdf_glossy = ggx_reflection_pdf(n, s.wo, wi, brdf.alpha);
        float pdf_light = has_area_lights() ? light_pdf(s, reflected) : 0.0f;
        sum += weight * emitted(reflected) *
               power_heuristic(float(settings.glossy_samples) * pdf_glossy, float(settings.area_light_samples) * pdf_light);
      }
    }
    return sum / float(settings.glossy_samples);
  }

  // Probability of sampling the GGX lobe rather than the cosine lobe; < 0: nothing reflects.
  float specular_probability(const Surface& s, const BrdfParams& brdf) const {
    if (!settings.specular) return 0.0f;
    float spec = rgb_luminance(schlick(brdf.f0, glm::dot(s.shading_normal, s.wo)));
    float diff = rgb_luminance(brdf.diffuse) * (1.0f - spec);
    if (spec + diff <= 0.0f) return -1.0f;
    return diff <= 0.0f ? 1.0f : std::clamp(spec / (spec + diff), 0.1f, 0.9f);
  }

  // Density of sample_brdf's direction wi (solid angle).
  float brdf_pdf(const Surface& s, const BrdfParams& brdf, const glm::vec3& wi) const {
    float p_specular = specular_probability(s, brdf);
    float cos_i = glm::dot(s.shading_normal, wi);
    if (p_specular < 0.0f || cos_i <= 0.0f) return 0.0f;
    float pdf = (1.0f - p_specular) * cos_i * float(1.0 / M_PI);
    if (p_specular > 0.0f) pdf += p_specular * ggx_reflection_pdf(s.shading_normal, s.wo, wi, brdf.alpha);
    return pdf;
  }

  // Samples the BRDF at s: a direction, f * cos / pdf and the pdf; false when the path ends.
  bool sample_brdf(const Surface& s, Rng& rng, glm::vec3& wi, glm::vec3& weight, float& pdf) const {
    BrdfParams brdf = BrdfParams::from(*s.material, settings.specular);
    const glm::vec3& n = s.shading_normal;
    Frame frame(n);
    float p_specular = specular_probability(s, brdf);
    if (p_specular < 0.0f) return false;
    float choice = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    if (choice < p_specular) {
      glm::vec3 h = frame.to_world(sample_ggx_half(u1, u2, brdf.alpha));
      wi = 2.0f * glm::dot(s.wo, h) * h - s.wo;
    } else {
      wi = frame.to_world(sample_cosine_hemisphere(u1, u2));
    }
    float cos_i = glm::dot(n, wi);
    if (cos_i <= 0.0f || glm::dot(s.geometric_normal, wi) <= 0.0f) return false;
    pdf = brdf_pdf(s, brdf, wi);
    if (!(pdf > 0.0f)) return false;
    weight = eval_brdf(brdf, n, s.wo, wi) * (cos_i / pdf);
    return max_component(weight) > 0.0f;
  }

  // Indirect light by path tracing: next-event estimation at every vertex, combined with the
  // BRDF-sampled hits on emitters by the power heuristic; Russian roulette.
  // view_dependent (optional) receives the part that left the primary hit through its specular
  // lobe (each path's contribution split by the lobes' shares of f at its first direction).
  glm::vec3 indirect(const Surface& primary, uint64_t key, glm::vec3* view_dependent = nullptr) {
    if (settings.gi_paths <= 0 || settings.gi_max_bounces <= 0) return glm::vec3(0.0f);
    glm::vec3 sum(0.0f), sum_specular(0.0f);
    const BrdfParams primary_brdf = BrdfParams::from(*primary.material, settings.specular);
    const bool lights = has_area_lights();
    for (int p = 0; p < settings.gi_paths; ++p) {
      Rng rng(key, kStreamPath, uint64_t(p));
      glm::vec3 path(0.0f);
      glm::vec3 throughput(1.0f);
      glm::vec3 specular_share(0.0f);
      Surface s = primary;
      // The primary hit's light samples are not MIS-weighted (there are many, and most paths
      // miss small lights): its BRDF samples leave the area lights to them (weight 0).
      MisCounts counts{settings.area_light_samples, 0};
      for (int bounce = 1; bounce <= settings.gi_max_bounces; ++bounce) {
        glm::vec3 wi, weight;
        float pdf = 0.0f;
        if (!sample_brdf(s, rng, wi, weight, pdf)) break;
        if (bounce == 1) {
          const BrdfValue lobes = eval_brdf_lobes(primary_brdf, s.shading_normal, s.wo, wi);
          const glm::vec3 total = lobes.sum();
          for (int c = 0; c < 3; ++c) specular_share[c] = total[c] > 0.0f ? lobes.specular[c] / total[c] : 0.0f;
        }
        throughput *= weight;
        Ray ray = spawn(s, wi);
        RayHit hit = trace(ray);
        if (!hit.hit) break;
        Surface next = surface(hit, ray);
        if (max_component(emitted(next)) > 0.0f) {
          float pdf_light = lights ? light_pdf(s, next) : 0.0f;
          path += throughput * emitted(next) * power_heuristic(float(counts.brdf) * pdf, float(counts.light) * pdf_light);
        }
        s = next;
        const bool continues = bounce < settings.gi_max_bounces;
        counts = MisCounts{settings.gi_light_samples, continues ? 1 : 0};
        path += throughput * direct(s, settings.gi_light_samples, 0, &rng, counts.brdf);
        if (bounce >= settings.gi_roulette_bounce) {
          float survive = std::min(0.95f, max_component(throughput));
          if (rng.uniform() >= survive) break;
          throughput /= survive;
        }
      }
      float luminance = rgb_luminance(path);
      if (settings.gi_path_clamp > 0.0f && luminance > settings.gi_path_clamp) path *= settings.gi_path_clamp / luminance;
      sum += path;
      sum_specular += path * specular_share;
    }
    if (view_dependent) *view_dependent += sum_specular / float(settings.gi_paths);
    return sum / float(settings.gi_paths);
  }
};

Shader::Shader(const RayScene& scene, const ShaderSettings& settings) : scene_(scene), settings_(settings) {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("shader settings: ") + what);
  };
  require(settings.area_light_samples >= 0 && settings.glossy_samples >= 0 && settings.glossy_light_samples >= 0 &&
              settings.gi_paths >= 0 && settings.gi_light_samples >= 0,
          "sample counts must not be negative");
  require(settings.gi_max_bounces >= 0 && settings.gi_roulette_bounce >= 1, "bounce limits must be >= 0 and >= 1");
  require(settings.gi_path_clamp >= 0.0f, "gi_path_clamp must not be negative");
  require(settings.ray_offset > 0.0f && settings.ray_offset < 0.1f, "ray_offset must be in (0, 0.1)");
  // (Once, here: in the asynchronous loop the ray scene's lights belong to the shading thread.)
  const bool area = settings.area_light_samples > 0 && lights_by_area(scene);
  const bool glossy = settings.kind == ShaderKind::glossy && settings.specular && settings.glossy_samples > 0;
  const bool gi = settings.kind == ShaderKind::gi && settings.gi_paths > 0 && settings.gi_max_bounces > 0;
  effort_matters_ = area || glossy || gi;
}

ShaderSettings with_effort(const ShaderSettings& settings, int effort) {
  ShaderSettings out = settings;
  out.area_light_samples *= effort, out.glossy_samples *= effort, out.gi_paths *= effort;
  return out;
}

ShadeResult Shader::shade_one(const ViewFrame& frame, const ShadeRequest& request, std::vector<BlockerTriple>& triples,
                              uint64_t& rays) const {
  ShadeResult result;
  result.id = request.id;
  result.x = request.x;
  result.y = request.y;
  result.effort = effort_matters() ? std::max<uint8_t>(request.effort, 1) : 1;
  result.triple_begin = uint32_t(triples.size());
  if (!std::isfinite(request.x) || !std::isfinite(request.y)) return result;  // no ray: a miss
  ShaderSettings scaled;
  const ShaderSettings& settings = request.effort > 1 ? (scaled = with_effort(settings_, request.effort), scaled) : settings_;
  Tracer tracer{scene_, settings, request.blockers == Blockers::none ? nullptr : &triples, triples.size(), 0,
                request.blockers == Blockers::all};
  Ray ray = frame.ray(request.x, request.y);
  RayHit hit = tracer.trace(ray);
  if (hit.hit) {
    Surface s = tracer.surface(hit, ray);
    uint64_t key = request_key(settings.seed, request.x, request.y);
    // Glossy mode: the GGX rays also find the area lights; MIS shares the specular lobe.
    const bool glossy_rays = settings.kind == ShaderKind::glossy && settings.specular && settings.glossy_samples > 0;
    const BrdfValue direct = tracer.direct_lobes(s, settings.area_light_samples, key, nullptr,
                                                 glossy_rays ? settings.glossy_samples : 0, true, &result.punctual_lights,
                                                 &result.punctual_specular);
    const glm::vec3 emitted = tracer.emitted(s);
    glm::vec3 color = emitted + direct.sum();
    glm::vec3 view_dependent = direct.specular;
    tracer.triples = nullptr;  // triples come from the primary hit's shadow rays only
    if (settings.kind == ShaderKind::glossy) {
      const glm::vec3 glossy = tracer.glossy(s, key);
      color += glossy, view_dependent += glossy;
    }
    if (settings.kind == ShaderKind::gi) color += tracer.indirect(s, key, &view_dependent);
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(color[c])) color[c] = 0.0f;
      if (!std::isfinite(view_dependent[c])) view_dependent[c] = 0.0f;
      view_dependent[c] = std::clamp(view_dependent[c], 0.0f, color[c]);
      if (!std::isfinite(result.punctual_specular[c])) result.punctual_specular[c] = 0.0f;
      result.punctual_specular[c] = std::clamp(result.punctual_specular[c], 0.0f, view_dependent[c]);
    }
    result.shading_normal = s.shading_normal;
    result.material = uint32_t(s.material - scene_.scene().materials.data());
    result.view_dependent = view_dependent;
    result.lobe_width = settings.specular ? BrdfParams::from(*s.material, true).alpha : 0.0f;
    const bool emits = emitted.x > 0.0f || emitted.y > 0.0f || emitted.z > 0.0f;
    result.diffuse_transmission =
        settings.specular && !emits ? diffuse_transmission(glm::dot(s.geometric_normal, s.wo)) : 0.0f;
    result.hit = true;
    result.object = s.object;
    result.triangle = s.triangle;
    result.position = s.position;
    result.normal = s.geometric_normal;
    result.color = color;
  }
  result.triple_count = uint32_t(triples.size()) - result.triple_begin;
  rays += tracer.rays;
  return result;
}

PunctualSpecularModel Shader::punctual_specular_model() const {
  PunctualSpecularModel model;
  if (settings_.specular)
    for (const Material& m : scene_.scene().materials) model.materials.push_back(BrdfParams::from(m, true));
  model.lights = scene_.punctual_lights();
  return model;
}

glm::vec3 PunctualSpecularModel::specular(const PunctualSurface& s, const glm::vec3& eye) const {
  if (s.lights == 0 || s.material >= materials.size()) return glm::vec3(0.0f);
  const BrdfParams& brdf = materials[s.material];
  const glm::vec3 wo = glm::normalize(eye - s.position);
  // As Tracer::surface chooses it: the interpolated normal where it faces the eye.
  const glm::vec3& n = glm::dot(s.shading_normal, wo) > 0.0f ? s.shading_normal : s.geometric_normal;
  glm::vec3 sum(0.0f);
  for (uint32_t i = 0; i < std::min<size_t>(lights.size(), 32); ++i) {
    glm::vec3 wi, incoming;
    if (!(s.lights >> i & 1u) || !punctual_incoming(lights[i], s.position, wi, incoming)) continue;
    const float cos_s = glm::dot(n, wi);
    if (cos_s <= 0.0f) continue;
    sum += eval_brdf_lobes(brdf, n, wo, wi).specular * incoming * cos_s;
  }
  return sum;
}

void Shader::shade(const View& view, std::span<const ShadeRequest> requests, ShadeBatch& out) const {
  shade(ViewFrame(view), requests, out);
}

void Shader::shade(const ViewFrame& frame, std::span<const ShadeRequest> requests, ShadeBatch& out) const {
  struct Chunk {
    size_t begin, end;
    std::vector<BlockerTriple> triples;
    uint64_t rays;
  };
  const auto start = std::chrono::steady_clock::now();
  const size_t base = out.results.size();
  out.results.resize(base + requests.size());
  tbb::concurrent_vector<Chunk> chunks;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, requests.size(), 16), [&](const tbb::blocked_range<size_t>& range) {
    FlushDenormals flush;
    Chunk chunk{range.begin(), range.end(), {}, 0};
    for (size_t i = range.begin(); i < range.end(); ++i)
      out.results[base + i] = shade_one(frame, requests[i], chunk.triples, chunk.rays);
    chunks.push_back(std::move(chunk));
  });
  // Concatenate the triples in request order.
  std::vector<const Chunk*> ordered;
  for (const Chunk& c : chunks) ordered.push_back(&c);
  std::sort(ordered.begin(), ordered.end(), [](const Chunk* a, const Chunk* b) { return a->begin < b->begin; });
  uint64_t rays = 0;
  for (const Chunk* c : ordered) {
    uint32_t offset = uint32_t(out.triples.size());
    for (size_t i = c->begin; i < c->end; ++i) out.results[base + i].triple_begin += offset;
    out.triples.insert(out.triples.end(), c->triples.begin(), c->triples.end());
    rays += c->rays;
  }
  out.rays += rays;
  add_rays(rays);
  const auto elapsed = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start);
  shading_ns_.fetch_add(uint64_t(elapsed.count()), std::memory_order_relaxed);
}

}  // namespace epi

// The expensive "external shader" of the render cache and the edge-and-point image:
// shades batches of image-space requests with Embree, in parallel over requests (TBB).
// Output for a given seed is bit-identical whatever the thread count or batch split.
#pragma once

#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "shade/brdf.h"
#include "shade/ray_scene.h"
#include "shade/view.h"

namespace epi {

enum class ShaderKind { direct, glossy, gi };

struct ShaderSettings {
  ShaderKind kind = ShaderKind::direct;  // direct lighting only, + glossy reflection, or + path-traced indirect
  int area_light_samples = 16;           // shadow rays to area lights per primary hit
  int glossy_samples = 8;                // GGX-lobe reflection rays per hit (glossy)
  int glossy_light_samples = 4;          // area-light shadow rays at each reflected hit (glossy)
  int gi_paths = 16;                     // indirect paths per hit (gi)
  int gi_light_samples = 1;              // area-light shadow rays per path vertex (gi)
  int gi_max_bounces = 8;                // longest path, in bounces after the primary hit (gi)
  int gi_roulette_bounce = 3;            // Russian roulette from this bounce on (gi)
  float gi_path_clamp = 0.0f;            // cap on one path's indirect luminance (gi; 0: off; > 0 trades bias for no fireflies)
  bool specular = true;                  // false: Lambertian only (glTF base colour * (1 - metallic))
  bool record_blockers = true;           // report light-blocker-receiver triples (shadow rays find the blocker)
  uint64_t seed = 1;                     // every random stream derives from this
  float ray_offset = 1e-4f;              // secondary ray start offset, relative to the hit's coordinate scale
};

// settings with the primary hit's sample counts (area-light samples, glossy rays, gi paths)
// multiplied by effort (ShadeRequest::effort).
ShaderSettings with_effort(const ShaderSettings& settings, int effort);

// Which lights' blocked shadow rays name their blocker (BlockerTriple) for a request: a triple
// costs a closest-hit ray where an any-hit one answers visibility, and the sole-blocker check a ray
// more. The renderer asks only for those its edges use (docs/render.md, "Triples only where used").
enum class Blockers : uint8_t { all, punctual, none };

struct ShadeRequest {
  uint32_t id = 0;
  float x = 0.0f, y = 0.0f;  // pixel position with sub-pixel offset (see view.h); may lie outside the image; non-finite: a miss
  // The primary hit's estimates (area-light samples, glossy rays, gi paths) take this many times
  // their settings' counts (0 counts as 1): the renderer spends more where one result will be
  // spread over many pixels (docs/render.md, "Effort where samples are sparse").
  uint8_t effort = 1;
  Blockers blockers = Blockers::all;  // with ShaderSettings::record_blockers (none where that is false)
};

// A light whose shadow ray from the receiver was blocked by the blocker object.
struct BlockerTriple {
  uint32_t light = 0;  // punctual lights first, then area lights (see lights.h)
  uint32_t blocker = 0;
  uint32_t receiver = 0;
  bool operator==(const BlockerTriple&) const = default;
};

struct ShadeResult {
  uint32_t id = 0;
  float x = 0.0f, y = 0.0f;
  bool hit = false;
  uint8_t effort = 1;         // the request's (ShadeRequest::effort, at least 1)
  uint32_t object = kNone;    // kNone on a miss
  uint32_t triangle = kNone;
  glm::vec3 position{0.0f};   // first hit, world space
  glm::vec3 normal{0.0f};     // geometric, world space, facing the ray
  glm::vec3 color{0.0f};      // linear RGB radiance towards the eye
  // The part of color that depends on the eye's direction (what left the hit through the specular
  // lobe: direct specular, glossy reflection, gi paths that started in the specular lobe).
  glm::vec3 view_dependent{0.0f};
  float lobe_width = 0.0f;    // the specular lobe's width at the hit (GGX alpha, ~radians); 0: none
  // diffuse_transmission (brdf.h) towards the eye at the hit, about the geometric normal: the
  // factor by which the diffuse part of color depends on the view; 0 where color must not be
  // rescaled with the view (misses, emitters, whose emission does not pass the interface).
  float diffuse_transmission = 0.0f;
  uint32_t triple_begin = 0;  // into ShadeBatch::triples
  uint32_t triple_count = 0;
  // Of view_dependent, the specular reflection of punctual lights 0-31 at the hit, and what
  // PunctualSpecularModel recomputes it from for another eye (docs/render.md, "Punctual
  // highlights"): the lights that reach the hit (bit i: light i is unblocked, in its range and
  // cone, and lights the hit's front), the shading normal (world space, facing the ray) and the
  // material (Scene::materials).
  glm::vec3 punctual_specular{0.0f};
  uint32_t punctual_lights = 0;
  glm::vec3 shading_normal{0.0f};
  uint32_t material = kNone;
};

// A surface point as PunctualSpecularModel sees it (world space; ShadeResult's fields).
struct PunctualSurface {
  glm::vec3 position{0.0f}, shading_normal{0.0f}, geometric_normal{0.0f};
  uint32_t material = kNone;
  uint32_t lights = 0;
};

// What recomputes a result's punctual specular for another eye without rays (docs/render.md,
// "Punctual highlights"): the materials' lobes and the punctual lights, copied from the shader so
// that whoever keeps it (the point cache) owns it. The lights are the scene's as the keeper has
// them now (in the asynchronous loop the ray scene's belong to the shading thread): a keeper moves
// them with `lights[i].position`.
struct PunctualSpecularModel {
  std::vector<BrdfParams> materials;  // of Scene::materials, as shading evaluates them
  std::vector<PunctualLight> lights;  // the scene's punctual lights

  // The specular reflection towards `eye` of the lights in s.lights: shade_one's arithmetic for
  // those lights (ShadeResult::punctual_specular when eye is the shading view's and nothing
  // moved), without shadow rays.
  glm::vec3 specular(const PunctualSurface& s, const glm::vec3& eye) const;
};

struct ShadeBatch {
  std::vector<ShadeResult> results;
  std::vector<BlockerTriple> triples;  // deduplicated per result
  uint64_t rays = 0;                   // rays traced for these results

  void clear() { results.clear(), triples.clear(), rays = 0; }
  std::span<const BlockerTriple> triples_of(const ShadeResult& r) const { return {triples.data() + r.triple_begin, r.triple_count}; }
};

class Shader {
 public:
  Shader(const RayScene& scene, const ShaderSettings& settings);

  // Shades requests in parallel (TBB, in the caller's arena) and appends to out.
  void shade(const View& view, std::span<const ShadeRequest> requests, ShadeBatch& out) const;
  void shade(const ViewFrame& frame, std::span<const ShadeRequest> requests, ShadeBatch& out) const;
  // One request on the calling thread; triples are appended; rays counts what it traced.
  ShadeResult shade_one(const ViewFrame& frame, const ShadeRequest& request, std::vector<BlockerTriple>& triples,
                        uint64_t& rays) const;

  // Whether a request's effort changes its result: some estimate of the primary hit is sampled
  // (area lights with samples, glossy rays, gi paths). Where none is, results report effort 1.
  bool effort_matters() const { return effort_matters_; }

  // This shader's punctual specular model, with the ray scene's lights where they are now (call it
  // on the thread that owns the ray scene); no materials when the shader has no specular lobes.
  PunctualSpecularModel punctual_specular_model() const;

  const ShaderSettings& settings() const { return settings_; }
  const RayScene& ray_scene() const { return scene_; }
  uint64_t rays_traced() const { return rays_traced_.load(std::memory_order_relaxed); }  // since construction
  void add_rays(uint64_t n) const { rays_traced_.fetch_add(n, std::memory_order_relaxed); }
  // Wall-clock time spent inside shade() since construction (summed over calls, which may
  // overlap when several threads call it); rays_traced() / shading_seconds() is the
  // shader's ray rate while it works.
  double shading_seconds() const { return double(shading_ns_.load(std::memory_order_relaxed)) * 1e-9; }

 private:
  struct Surface;
  struct Tracer;
  const RayScene& scene_;
  ShaderSettings settings_;
  bool effort_matters_ = false;
  mutable std::atomic<uint64_t> rays_traced_{0};
  mutable std::atomic<uint64_t> shading_ns_{0};
};

}  // namespace epi

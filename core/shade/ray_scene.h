// Embree 3 geometry for a Scene: one Embree scene per Mesh, one instance per Object, so an
// object moves by updating its instance transform and recommitting the top level.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include <embree3/rtcore.h>

#include "scene/scene.h"
#include "shade/view.h"

namespace epi {

struct RayHit {
  bool hit = false;
  float t = 0.0f;
  uint32_t object = kNone;
  uint32_t triangle = kNone;
  float u = 0.0f, v = 0.0f;  // barycentric weights of triangle vertices 1 and 2
};

class RayScene {
 public:
  // Keeps a reference to scene, which must outlive this. Throws std::runtime_error with a
  // one-line message (naming Scene::source) for invalid indices or an Embree failure.
  explicit RayScene(const Scene& scene);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Moves an object and recommits; its area light, if any, follows. Must not run while
  // other threads trace (AsyncShader::run_between_batches does that safely).
  void set_object_transform(uint32_t object, const glm::mat4& object_to_world);
  // Moves a point or spot light to a world-space position (its direction, cone and intensity
  // stay). Throws std::out_of_range for a bad index and std::invalid_argument for a directional
  // light. Same threading rule as set_object_transform.
  void set_punctual_light_position(uint32_t light, const glm::vec3& position);

  const Scene& scene() const { return scene_; }
  const glm::mat4& object_to_world(uint32_t object) const { return transforms_[object]; }
  const glm::mat3& normal_to_world(uint32_t object) const { return normal_matrices_[object]; }
  // Punctual lights as currently placed (Scene::punctual_lights order); the shader lights with these.
  const std::vector<PunctualLight>& punctual_lights() const { return punctual_lights_; }
  // World-space area lights as currently placed (Scene::area_lights order), and the CDF
  // over them by power.
  const std::vector<AreaLight>& area_lights() const { return area_lights_; }
  const std::vector<float>& area_light_cdf() const { return area_light_cdf_; }
  // The area light made from an object, or kNone; and which of its triangles a mesh triangle is
  // (kNone if not emissive). The map exists when the light lists its mesh's emissive triangles
  // in mesh order (io/gltf and build_area_light do); unmapped lights are only light-sampled.
  uint32_t area_light_of_object(uint32_t object) const { return area_light_of_object_[object]; }
  bool area_light_mapped(size_t light) const { return !light_triangle_maps_[light].empty(); }
  uint32_t light_triangle(size_t light, uint32_t mesh_triangle) const { return light_triangle_maps_[light][mesh_triangle]; }

  // Nearest hit in (tnear, tfar), and whether anything lies there. Thread-safe.
  RayHit intersect(const Ray& ray) const;
  bool occluded(const Ray& ray) const;
  // occluded() for up to 16 rays traced together as a packet (rays from one point); the same
  // answers but where a surface lies within rounding of a ray's tfar. (Not with Embree's
  // coherent flag: with it, rtcOccluded16 of Embree 3.13.5 never returned for some packets.)
  void occluded16(const Ray* rays, size_t count, bool* blocked) const;
  // Up to 16 rays at once (rtcIntersect16): faster for coherent rays such as camera rays.
  void intersect16(const Ray* rays, size_t count, RayHit* hits) const;

  RTCScene handle() const { return top_; }
  size_t embree_bytes() const { return size_t(std::max<int64_t>(embree_bytes_.load(), 0)); }
  std::vector<MemoryItem> memory() const;

 private:
  void build();
  void release();
  void update_area_light_cdf();

  const Scene& scene_;
  RTCDevice device_ = nullptr;
  RTCScene top_ = nullptr;
  std::vector<RTCScene> mesh_scenes_;
  std::vector<RTCGeometry> instances_;  // per object; null for empty meshes
  std::vector<glm::mat4> transforms_;
  std::vector<glm::mat3> normal_matrices_;
  std::vector<PunctualLight> punctual_lights_;
  std::vector<AreaLight> area_lights_;
  std::vector<uint32_t> area_light_of_object_;  // index into area_lights_, or kNone
  std::vector<std::vector<uint32_t>> light_triangle_maps_;  // per area light: mesh triangle -> light triangle
  std::vector<float> area_light_cdf_;
  std::atomic<int64_t> embree_bytes_{0};
};

// Sets flush-to-zero and denormals-are-zero for this thread while alive (Embree wants them).
class FlushDenormals {
 public:
  FlushDenormals();
  ~FlushDenormals();
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
  unsigned int saved_;
};

}  // namespace epi

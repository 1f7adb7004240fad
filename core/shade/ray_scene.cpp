#include "shade/ray_scene.h"

#include <algorithm>
#include <cmath>

#include "shade/view.h"

#include <xmmintrin.h>

#include <stdexcept>
#include <string>

#include <glm/gtc/matrix_inverse.hpp>

#include "shade/brdf.h"
#include "shade/lights.h"

namespace epi {

namespace {

std::string scene_label(const Scene& scene) { return scene.source.empty() ? "scene" : scene.source; }

bool monitor_memory(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<int64_t>*>(user)->fetch_add(int64_t(bytes), std::memory_order_relaxed);
  return true;
}

void check_device(RTCDevice device, const Scene& scene, const std::string& what) {
  RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(scene_label(scene) + ": Embree failed to " + what + " (error " + std::to_string(int(error)) + ")");
}

}  // namespace

FlushDenormals::FlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }  // FTZ | DAZ
FlushDenormals::~FlushDenormals() { _mm_setcsr(saved_); }

RayScene::RayScene(const Scene& scene) : scene_(scene) {
  const std::string label = scene_label(scene);
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k)
        if (mesh.triangles[t][k] >= mesh.positions.size())
          throw std::runtime_error(label + ": mesh '" + mesh.name + "' triangle " + std::to_string(t) +
                                   " has a vertex index out of range");
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
      throw std::runtime_error(label + ": mesh '" + mesh.name + "' has " + std::to_string(mesh.normals.size()) +
                               " normals for " + std::to_string(mesh.positions.size()) + " positions");
    for (const MaterialRange& r : mesh.materials)
      if (r.material >= scene.materials.size())
        throw std::runtime_error(label + ": mesh '" + mesh.name + "' uses material " + std::to_string(r.material) +
                                 " of " + std::to_string(scene.materials.size()));
  }
  for (size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].mesh >= scene.meshes.size())
      throw std::runtime_error(label + ": object '" + scene.objects[o].name + "' refers to mesh " +
                               std::to_string(scene.objects[o].mesh) + " of " + std::to_string(scene.meshes.size()));
  const Bounds bounds = scene.world_bounds();
  for (int k = 0; k < 3 && !bounds.empty(); ++k)
    if (!(std::max(std::abs(bounds.min[k]), std::abs(bounds.max[k])) <= kMaxRayCoordinate))
      throw std::runtime_error(label + ": the scene reaches " +
                               std::to_string(std::max(std::abs(bounds.min[k]), std::abs(bounds.max[k]))) +
                               " from the origin, beyond the ray tracer's range (1e18)");
  for (const AreaLight& light : scene.area_lights) {
    if (light.object >= scene.objects.size())
      throw std::runtime_error(label + ": area light refers to object " + std::to_string(light.object) + " of " +
                               std::to_string(scene.objects.size()));
    const size_t triangles = light.triangle_materials.size();
    if (light.triangle_vertices.size() != 3 * triangles || light.triangle_cdf.size() != triangles)
      throw std::runtime_error(label + ": area light of object '" + scene.objects[light.object].name +
                               "' has inconsistent triangle, material and CDF counts");
    for (uint32_t material : light.triangle_materials)
      if (material >= scene.materials.size())
        throw std::runtime_error(label + ": area light of object '" + scene.objects[light.object].name +
                                 "' uses material " + std::to_string(material) + " of " + std::to_string(scene.materials.size()));
  }

  try {
    build();
  } catch (...) {
    release();
    throw;
  }
}

void RayScene::build() {
  const Scene& scene = scene_;
  device_ = rtcNewDevice("verbose=0");
  if (!device_) throw std::runtime_error(scene_label(scene) + ": cannot create an Embree device");
  rtcSetDeviceMemoryMonitorFunction(device_, monitor_memory, &embree_bytes_);

  // One Embree scene per mesh, built once.
  mesh_scenes_.assign(scene.meshes.size(), nullptr);
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (mesh.triangles.empty()) continue;
    RTCScene mesh_scene = rtcNewScene(device_);
    rtcSetSceneBuildQuality(mesh_scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* positions = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                  3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(uint32_t), mesh.triangles.size()));
    check_device(device_, scene, "allocate mesh buffers");
    for (size_t i = 0; i < mesh.positions.size(); ++i)
      for (int k = 0; k < 3; ++k) positions[3 * i + k] = mesh.positions[i][k];
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) indices[3 * i + k] = mesh.triangles[i][k];
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(mesh_scene, geometry, 0);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(mesh_scene);
    check_device(device_, scene, "build mesh '" + mesh.name + "'");
    mesh_scenes_[m] = mesh_scene;
  }

  // The top level: one instance per object, geometry ID = object index.
  top_ = rtcNewScene(device_);
  rtcSetSceneFlags(top_, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(top_, RTC_BUILD_QUALITY_LOW);
  instances_.assign(scene.objects.size(), nullptr);
  transforms_.resize(scene.objects.size());
  normal_matrices_.resize(scene.objects.size());
  for (uint32_t o = 0; o < scene.objects.size(); ++o) {
    transforms_[o] = scene.objects[o].object_to_world;
    normal_matrices_[o] = glm::inverseTranspose(glm::mat3(transforms_[o]));
    RTCScene mesh_scene = mesh_scenes_[scene.objects[o].mesh];
    if (!mesh_scene) continue;
    RTCGeometry instance = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, mesh_scene);
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &transforms_[o][0][0]);
    rtcCommitGeometry(instance);
    rtcAttachGeometryByID(top_, instance, o);
    instances_[o] = instance;
  }
  rtcCommitScene(top_);
  check_device(device_, scene, "build the top-level scene");

  punctual_lights_ = scene.punctual_lights;
  area_lights_ = scene.area_lights;
  area_light_of_object_.assign(scene.objects.size(), kNone);
  for (uint32_t i = 0; i < area_lights_.size(); ++i) area_light_of_object_[area_lights_[i].object] = i;
  light_triangle_maps_.resize(area_lights_.size());
  for (size_t i = 0; i < area_lights_.size(); ++i) {
    // Mesh triangle -> light triangle (the light lists the emissive triangles in mesh order).
    const AreaLight& light = area_lights_[i];
    const Mesh& mesh = scene.meshes[scene.objects[light.object].mesh];
    std::vector<uint32_t> map(mesh.triangles.size(), kNone);
    uint32_t next = 0;
    bool consistent = true;
    for (uint32_t t = 0; t < mesh.triangles.size() && consistent; ++t) {
      uint32_t material = mesh.material_of(t);
      if (!scene.materials[material].emissive()) continue;
      consistent = next < light.triangle_materials.size() && light.triangle_materials[next] == material;
      map[t] = next++;
    }
    if (consistent && next == light.triangle_materials.size()) light_triangle_maps_[i] = std::move(map);
  }
  update_area_light_cdf();
}

RayScene::~RayScene() { release(); }

void RayScene::release() {
  for (RTCGeometry instance : instances_)
    if (instance) rtcReleaseGeometry(instance);
  if (top_) rtcReleaseScene(top_);
  for (RTCScene s : mesh_scenes_)
    if (s) rtcReleaseScene(s);
  if (device_) rtcReleaseDevice(device_);
  instances_.clear();
  mesh_scenes_.clear();
  top_ = nullptr;
  device_ = nullptr;
}

void RayScene::set_object_transform(uint32_t object, const glm::mat4& object_to_world) {
  if (object >= transforms_.size())
    throw std::out_of_range(scene_label(scene_) + ": no object " + std::to_string(object) + " to move");
  glm::mat4 delta = object_to_world * glm::inverse(transforms_[object]);
  transforms_[object] = object_to_world;
  normal_matrices_[object] = glm::inverseTranspose(glm::mat3(object_to_world));
  if (instances_[object]) {
    rtcSetGeometryTransform(instances_[object], 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &transforms_[object][0][0]);
    rtcCommitGeometry(instances_[object]);
    rtcCommitScene(top_);
    check_device(device_, scene_, "move object '" + scene_.objects[object].name + "'");
  }
  uint32_t light_index = area_light_of_object_[object];
  if (light_index != kNone) {
    AreaLight moved = build_area_light(scene_, object, object_to_world);
    for (auto& loop : area_lights_[light_index].outlines)
      for (glm::vec3& p : loop) p = glm::vec3(delta * glm::vec4(p, 1.0f));
    moved.outlines = std::move(area_lights_[light_index].outlines);
    area_lights_[light_index] = std::move(moved);
    update_area_light_cdf();
  }
}

void RayScene::set_punctual_light_position(uint32_t light, const glm::vec3& position) {
  if (light >= punctual_lights_.size())
    throw std::out_of_range(scene_label(scene_) + ": no punctual light " + std::to_string(light) + " to move");
  if (punctual_lights_[light].type == LightType::directional)
    throw std::invalid_argument(scene_label(scene_) + ": light '" + punctual_lights_[light].name +
                                "' is directional and has no position to move");
  punctual_lights_[light].position = position;
}

void RayScene::update_area_light_cdf() {
  area_light_cdf_.clear();
  double total = 0.0;
  for (const AreaLight& light : area_lights_) total += std::max(light.power, 0.0f);
  double sum = 0.0;
  for (const AreaLight& light : area_lights_) {
    sum += std::max(light.power, 0.0f);
    area_light_cdf_.push_back(total > 0.0 ? float(sum / total) : 0.0f);
  }
  if (total > 0.0) area_light_cdf_.back() = 1.0f;
}

RayHit RayScene::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x, rh.ray.org_y = ray.origin.y, rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.direction.x, rh.ray.dir_y = ray.direction.y, rh.ray.dir_z = ray.direction.z;
  rh.ray.tnear = ray.tnear;
  rh.ray.tfar = ray.tfar;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(top_, &context, &rh);
  RayHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.hit = true;
  hit.t = rh.ray.tfar;
  hit.object = rh.hit.instID[0];
  hit.triangle = rh.hit.primID;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  return hit;
}

void RayScene::intersect16(const Ray* rays, size_t count, RayHit* hits) const {
  count = std::min<size_t>(count, 16);
  if (count == 0) return;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  for (size_t i = 0; i < 16; ++i) {
    const Ray& ray = rays[std::min(i, count - 1)];
    valid[i] = i < count ? -1 : 0;
    rh.ray.org_x[i] = ray.origin.x, rh.ray.org_y[i] = ray.origin.y, rh.ray.org_z[i] = ray.origin.z;
    rh.ray.dir_x[i] = ray.direction.x, rh.ray.dir_y[i] = ray.direction.y, rh.ray.dir_z[i] = ray.direction.z;
    rh.ray.tnear[i] = ray.tnear;
    rh.ray.tfar[i] = ray.tfar;
    rh.ray.time[i] = 0.0f;
    rh.ray.mask[i] = 0xffffffffu;
    rh.ray.id[i] = unsigned(i);
    rh.ray.flags[i] = 0;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  rtcIntersect16(valid, top_, &context, &rh);
  for (size_t i = 0; i < count; ++i) {
    RayHit& hit = hits[i];
    hit = RayHit{};
    if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
    hit.hit = true;
    hit.t = rh.ray.tfar[i];
    hit.object = rh.hit.instID[0][i];
    hit.triangle = rh.hit.primID[i];
    hit.u = rh.hit.u[i];
    hit.v = rh.hit.v[i];
  }
}

bool RayScene::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  r.org_x = ray.origin.x, r.org_y = ray.origin.y, r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x, r.dir_y = ray.direction.y, r.dir_z = ray.direction.z;
  r.tnear = ray.tnear;
  r.tfar = ray.tfar;
  r.time = 0.0f;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(top_, &context, &r);
  return r.tfar < 0.0f;
}

void RayScene::occluded16(const Ray* rays, size_t count, bool* blocked) const {
  count = std::min<size_t>(count, 16);
  if (count == 0) return;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) RTCRay16 r;
  alignas(64) int valid[16];
  for (size_t i = 0; i < 16; ++i) {
    const Ray& ray = rays[std::min(i, count - 1)];
    valid[i] = i < count ? -1 : 0;
    r.org_x[i] = ray.origin.x, r.org_y[i] = ray.origin.y, r.org_z[i] = ray.origin.z;
    r.dir_x[i] = ray.direction.x, r.dir_y[i] = ray.direction.y, r.dir_z[i] = ray.direction.z;
    r.tnear[i] = ray.tnear;
    r.tfar[i] = ray.tfar;
    r.time[i] = 0.0f;
    r.mask[i] = 0xffffffffu;
    r.id[i] = unsigned(i);
    r.flags[i] = 0;
  }
  rtcOccluded16(valid, top_, &context, &r);
  for (size_t i = 0; i < count; ++i) blocked[i] = r.tfar[i] < 0.0f;
}

std::vector<MemoryItem> RayScene::memory() const {
  size_t light_bytes = 0;
  for (const AreaLight& light : area_lights_) light_bytes += light.memory_bytes();
  return {{"embree (BVH + buffers)", embree_bytes()},
          {"object transforms", transforms_.capacity() * (sizeof(glm::mat4) + sizeof(glm::mat3))},
          {"area lights (placed copy)", light_bytes}};
}

}  // namespace epi

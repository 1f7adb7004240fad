// Area lights from emissive objects, and the numbering of all lights.
#pragma once

#include "scene/scene.h"

namespace epi {

// Lights are numbered in one list: punctual lights first, then area lights.
inline uint32_t area_light_number(const Scene& scene, size_t area_index) {
  return uint32_t(scene.punctual_lights.size() + area_index);
}

// The area light of an object placed by object_to_world: its emissive triangles in world space
// (in mesh order, as io/gltf builds them), per-triangle material, power CDF, area and power.
// Outlines are left empty (the loader finds them).
AreaLight build_area_light(const Scene& scene, uint32_t object, const glm::mat4& object_to_world);

}  // namespace epi

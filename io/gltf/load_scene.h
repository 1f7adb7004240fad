// Loading a glTF 2.0 scene (.gltf with external or data: buffers, or .glb) into the scene model.
// Everything is validated; bad input throws SceneLoadError. Conventions: docs/scene-format.md.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "image/resource_limit.h"
#include "scene/scene.h"

namespace epi {

struct LoadOptions {
  int subdiv_level_override = -1;  // -1: as the file says; else the level of every mesh that asks for subdivision
  uint64_t memory_limit = kDefaultMemoryLimit;  // bytes; subdivision estimated above it is refused before it runs
};

// The estimate behind the subdivision limit, per refined triangle: the mesh as loaded (~430 bytes
// measured with `epi info` on levels 3-5 of a 256-quad cage, OpenSubdiv's refiner included) plus
// its Embree BVH and edge-finder data when rendered. docs/reliability.md.
inline constexpr double kBytesPerRefinedTriangle = 600.0;

// what() is "<file>: <problem>", on one line.
struct SceneLoadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Scene load_scene(const std::filesystem::path& file, const LoadOptions& options = {});

}  // namespace epi

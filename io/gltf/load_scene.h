// Loading a glTF 2.0 scene (.gltf with external or data: buffers, or .glb) into the scene model.
// Everything is validated; bad input throws SceneLoadError. Conventions: docs/scene-format.md.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "scene/scene.h"

namespace epi {

struct LoadOptions {
  int subdiv_level_override = -1;  // -1: as the file says; else the level of every mesh that asks for subdivision
};

// what() is "<file>: <problem>", on one line.
struct SceneLoadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Scene load_scene(const std::filesystem::path& file, const LoadOptions& options = {});

}  // namespace epi

// The validation half of the shared render options (no CLI11 here: render_flags.cpp parses).
#include "render_options.h"

#include <stdexcept>

#include "scene/scene.h"

namespace epi::cli {

namespace {

ShaderKind shader_kind(const std::string& name) {
  if (name == "direct") return ShaderKind::direct;
  if (name == "glossy") return ShaderKind::glossy;
  if (name == "gi") return ShaderKind::gi;
  throw std::invalid_argument("unknown shader '" + name + "'");
}

}  // namespace

ShaderSettings shader_settings(const RenderOptions& options) {
  ShaderSettings settings = options.shading;
  settings.kind = shader_kind(options.shader);
  settings.seed = options.seed;
  const struct {
    const char* flag;
    int value, low, high;
  } counts[] = {{"--area-light-samples", settings.area_light_samples, 1, 4096},
                {"--glossy-samples", settings.glossy_samples, 0, 4096},
                {"--glossy-light-samples", settings.glossy_light_samples, 0, 4096},
                {"--gi-paths", settings.gi_paths, 0, 4096},
                {"--gi-light-samples", settings.gi_light_samples, 0, 4096},
                {"--gi-max-bounces", settings.gi_max_bounces, 0, 64}};
  for (const auto& c : counts)
    if (c.value < c.low || c.value > c.high)
      throw std::invalid_argument(std::string(c.flag) + " " + std::to_string(c.value) + " is not in [" +
                                  std::to_string(c.low) + ", " + std::to_string(c.high) + "]");
  return settings;
}

void check_sample_budget(const RenderOptions& options) {
  if (!(options.sample_budget > 0.0 && options.sample_budget <= 1.0))
    throw std::invalid_argument("--sample-budget " + std::to_string(options.sample_budget) + " is not in (0, 1]");
}

Camera apply_camera_override(const Scene& scene, const CameraOverride& override_) {
  Camera camera = scene.cameras.empty() ? Camera{} : scene.cameras.front();
  if (override_.eye) camera.eye = *override_.eye;
  if (override_.target) camera.target = *override_.target;
  if (override_.up) camera.up = *override_.up;
  if (override_.fov_degrees) camera.yfov_degrees = *override_.fov_degrees;
  const std::string problem = camera_problem(camera);
  if (!problem.empty())
    throw std::invalid_argument(scene.source + ": camera '" + camera.name + "'" +
                                (override_.any() ? " with --eye/--target/--up/--fov" : "") + ": " + problem);
  return camera;
}

}  // namespace epi::cli

// The options `epi render` and `epi-viewer` share: one struct, one parser (render_flags.cpp, the
// only CLI11 file besides the programs' mains) and one validation, so both programs accept the
// same flags with the same ranges and fail on bad input with the same messages.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "image/resource_limit.h"
#include "render/renderer.h"
#include "shade/shader.h"

namespace CLI {
class App;
class Validator;
}
namespace epi {
struct Scene;
struct Camera;
}  // namespace epi

namespace epi::cli {

struct CameraOverride {
  std::optional<glm::vec3> eye, target, up;
  std::optional<float> fov_degrees;
  bool any() const { return eye || target || up || fov_degrees; }
};

// The scene's default camera with the command line's --eye/--target/--up/--fov applied.
Camera apply_camera_override(const Scene& scene, const CameraOverride& override_);

struct RenderOptions {
  std::string scene;
  std::string mode = "epi";  // epi | rendercache (the frame loop) | raytrace | reference
  int width = 512, height = 512;
  int spp = 16;
  std::string shader = "direct";  // direct | glossy | gi
  ShaderSettings shading;         // sample counts from the command line; kind and seed from the two fields above/below
  uint64_t seed = 1;
  int threads = 0;  // 0: all cores
  std::string output = "out.png";
  std::string stats;  // JSON file, empty: none
  float exposure = 0.0f;  // stops, for 8-bit outputs (io/image tone map)
  bool quiet = false;
  int subdiv_level = -1;
  uint64_t memory_limit = kDefaultMemoryLimit;  // --memory-limit, bytes (docs/reliability.md)
  CameraOverride camera;
  // The frame loop (modes epi and rendercache):
  int frames = 60;
  bool sync = false;           // shade exactly the budget each frame (deterministic)
  double sample_budget = 0.02; // fraction of the pixels requested per frame
  std::string camera_path;     // file of camera keys per frame; empty: the scene's path, else still
  std::string frames_out;      // printf-style pattern for every frame's image, e.g. out/f%04d.png
  // The camera path on the loop's clock (docs/render.md, "The path on the clock"): path frames per
  // second of the loop's own time; 0: one path frame per rendered frame.
  double path_rate = 0.0;
  std::vector<int> frames_at;  // path frames --frames-out writes (empty: all); with path_rate, drawn exactly at them
  std::string save_epi;        // mode epi: the last frame's EPI snapshot (io/snapshot), empty: none
  bool trace_ahead = true;  // FrameSettings::trace_ahead (render.md, "Requests traced ahead")
  double rest_sample_budget = render::FrameSettings{}.rest_sample_budget;  // (render.md, "Idle shading at rest")
  double motion_sample_budget = render::FrameSettings{}.motion_sample_budget;  // (render.md, "Idle shading in motion")
  bool sparse_blend = true;        // epi mode: sparse regions smoothed (render.md, "Sparse regions")
  int sparse_effort = 1;           // epi mode: most effort of a request in a sparse region (render.md; 1: off)
  bool punctual_highlights = true; // epi mode: punctual lights' highlights recomputed per frame (render.md, "Punctual highlights")
  bool soft_shadow_edges = false;  // epi mode: the paper's umbral and penumbral edges (render.md, "Soft-shadow edges")
  // epi mode: how far a lone nearer point hides what lies behind it (PointCacheSettings; render.md,
  // "Sparse near surfaces"); 2, the dense radius, turns the sparse rule off. Unset: the renderer's.
  std::optional<int> sparse_occlusion_radius;
  std::optional<int> new_occluder_radius;
  // Predictive sampling (FrameSettings::predict_share, predict_frames, predict_stride,
  // predict_splat; render.md, "Sampling"). Unset: the renderer's.
  std::optional<float> predict_share;
  std::optional<float> predict_frames;
  std::optional<int> predict_stride;
  std::optional<int> predict_splat;
  std::string reference;       // image to compare the written frame with (all modes); empty: none
  bool speedup = true;         // epi, rendercache: time a 1-spp ray trace of the last view
};

// The shader settings a render asks for (kind, seed and sample counts); throws
// std::invalid_argument for a count out of range.
ShaderSettings shader_settings(const RenderOptions& options);
// Throws std::invalid_argument unless the sample budget is in (0, 1].
void check_sample_budget(const RenderOptions& options);

// Adds the scene argument and the flags both programs take (mode, size, shader and its sample
// counts, seed, threads, exposure, subdivision, camera, frame-loop budget, --sync, --camera-path)
// to `app`, writing into `options`. with_frame_loop: the build has core/render (the modes epi
// and rendercache and their flags).
void add_render_options(CLI::App& app, RenderOptions& options, bool with_frame_loop);
// The camera flags (--eye, --target, --up, --fov) and --size alone (epi edges).
void add_camera_options(CLI::App& app, CameraOverride& camera);
void add_size_option(CLI::App& app, int& width, int& height);
// --memory-limit GIB (info, edges and reconstruct take it too), and the check that a real-valued
// flag is finite (CLI::Range lets NaN through: every comparison with it is false).
void add_memory_limit_option(CLI::App& app, uint64_t& limit_bytes);
extern const CLI::Validator kFinite;

}  // namespace epi::cli

// The `epi` subcommands. cli/main.cpp (CLI11, the only file that includes it) parses the
// command line into these structs and calls run_*; each run_* lives in its own file and
// returns the process exit code. Errors are thrown as exceptions whose what() is one line
// naming the file and the problem; main prints "epi: <what>" and exits 1. A command line that
// does not parse (unknown flag, bad value, no subcommand) prints the problem and the usage and
// exits 2.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "shade/shader.h"

namespace epi {
struct Scene;
struct Camera;
}  // namespace epi

namespace epi::cli {

struct CameraOverride {
  std::optional<glm::vec3> eye, target, up;
  std::optional<float> fov_degrees;
};

// The scene's default camera with the command line's --eye/--target/--up/--fov applied.
Camera apply_camera_override(const Scene& scene, const CameraOverride& override_);

struct InfoOptions {
  std::string scene;
  int subdiv_level = -1;  // -1: as the scene says
};
int run_info(const InfoOptions& options);

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
  CameraOverride camera;
  // The frame loop (modes epi and rendercache):
  int frames = 60;
  bool sync = false;           // shade exactly the budget each frame (deterministic)
  double sample_budget = 0.02; // fraction of the pixels requested per frame
  std::string camera_path;     // file of camera keys per frame; empty: the scene's path, else still
  std::string frames_out;      // printf-style pattern for every frame's image, e.g. out/f%04d.png
  std::string save_epi;        // mode epi: the last frame's EPI snapshot (io/snapshot), empty: none
  bool soft_shadow_edges = false;  // epi mode: the paper's umbral and penumbral edges (render.md, "Soft-shadow edges")
  std::string reference;       // image to compare the written frame with (all modes); empty: none
  bool speedup = true;         // epi, rendercache: time a 1-spp ray trace of the last view
};
int run_render(const RenderOptions& options);
// The shader settings a render asks for (kind, seed and sample counts).
ShaderSettings shader_settings(const RenderOptions& options);
// The frame loop behind `render --mode epi|rendercache` (cli/frames.cpp).
int run_render_frames(const RenderOptions& options);

// `epi compare IMAGE REFERENCE`: the quality metrics of io/image/image_compare.h.
struct CompareOptions {
  std::string image, reference;
  std::string json;        // FILE, empty: none
  std::string diff;        // difference image to write, empty: none
  float diff_scale = 4.0f;
  float exposure = 0.0f;   // stops, for linear images on their way to display space
};
int run_compare(const CompareOptions& options);

// The 2D harness of core/epi (issue 3).
struct ReconstructOptions {
  std::string pattern;  // PATTERN.json
  double density = 0.1;
  std::string filter = "epi";  // epi | rendercache
  uint64_t seed = 1;
  bool antialias = true;
  bool complex_filter = true;
  std::string output;
  std::string stats;
  int threads = 0;
  bool quiet = false;
};
int run_reconstruct(const ReconstructOptions& options);

// The edge finder on its own (issue 4).
struct EdgesOptions {
  std::string scene;
  CameraOverride camera;
  int width = 512, height = 512;  // for the SVG projection
  std::string output;             // OUT.json
  std::string svg;
  std::string stats;
  int subdiv_level = -1;
  int threads = 0;
};
int run_edges(const EdgesOptions& options);

}  // namespace epi::cli

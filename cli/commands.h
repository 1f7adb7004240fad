// The `epi` subcommands. cli/main.cpp (CLI11; with render_flags.cpp, which adds the render
// flags shared with epi-viewer, the only files that include it) parses the command line into
// these structs and calls run_*; each run_* lives in its own file and
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

#include "render_options.h"

namespace epi {
struct Scene;
struct Camera;
}  // namespace epi

namespace epi::cli {

struct InfoOptions {
  std::string scene;
  int subdiv_level = -1;  // -1: as the scene says
  uint64_t memory_limit = kDefaultMemoryLimit;  // --memory-limit, bytes
};
int run_info(const InfoOptions& options);

int run_render(const RenderOptions& options);
// The frame loop behind `render --mode epi|rendercache` (cli/frames.cpp).
int run_render_frames(const RenderOptions& options);
// The camera of the last frame the frame loop would show (--frames of the path: --camera-path,
// else a still camera from --eye/--target/..., else the scene's own path; cli/frames.cpp):
// the view `render --mode reference|raytrace` renders, so that it is the reference of the
// same command in epi mode.
Camera last_frame_camera(const RenderOptions& options, const Scene& scene);

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
  uint64_t memory_limit = kDefaultMemoryLimit;  // --memory-limit, bytes
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
  uint64_t memory_limit = kDefaultMemoryLimit;  // --memory-limit, bytes
};
int run_edges(const EdgesOptions& options);

}  // namespace epi::cli

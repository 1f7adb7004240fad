// The `epi` command line: parsing only (CLI11 is slow to compile; it stays in this file).
// Each subcommand's work is in its own file, behind cli/commands.h.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>

#include "commands.h"

namespace {

using namespace epi::cli;

constexpr int kUsageExitCode = 2;  // a command line that does not parse; 1: the work failed

// Parses "x,y,z" into a vector of three finite floats.
bool parse_vec3(const std::string& text, glm::vec3& out) {
  std::stringstream in(text);
  std::string part;
  float v[3];
  for (int i = 0; i < 3; ++i) {
    if (!std::getline(in, part, ',')) return false;
    try {
      size_t used = 0;
      v[i] = std::stof(part, &used);
      if (used != part.size() || !std::isfinite(v[i])) return false;
    } catch (const std::exception&) {
      return false;
    }
  }
  if (std::getline(in, part)) return false;
  out = {v[0], v[1], v[2]};
  return true;
}

void add_vec3_option(CLI::App& app, const std::string& name, std::optional<glm::vec3>& target, const std::string& help) {
  app.add_option_function<std::string>(
         name,
         [&target, name](const std::string& text) {
           glm::vec3 v;
           if (!parse_vec3(text, v)) throw CLI::ValidationError(name, "expected three numbers x,y,z, got '" + text + "'");
           target = v;
         },
         help)
      ->type_name("X,Y,Z");
}

void add_camera_options(CLI::App& app, CameraOverride& camera) {
  add_vec3_option(app, "--eye", camera.eye, "Camera position (overrides the scene's default camera)");
  add_vec3_option(app, "--target", camera.target, "Point the camera looks at");
  add_vec3_option(app, "--up", camera.up, "Camera up vector");
  app.add_option_function<float>(
         "--fov", [&camera](float v) { camera.fov_degrees = v; }, "Vertical field of view in degrees")
      ->check(CLI::Range(0.01f, 179.0f));
}

void add_size_option(CLI::App& app, int& width, int& height) {
  app.add_option_function<std::string>(
         "--size",
         [&width, &height](const std::string& text) {
           int w = 0, h = 0;
           char x = 0, extra = 0;
           if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 ||
               h < 1 || w > 16384 || h > 16384)
             throw CLI::ValidationError("--size", "expected WxH with 1..16384, got '" + text + "'");
           width = w;
           height = h;
         },
         "Image size, e.g. 512x512")
      ->type_name("WxH");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"epi: interactive edge-and-point rendering of scenes with expensive lighting"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "epi 0.1");

  InfoOptions info;
  CLI::App* info_cmd = app.add_subcommand("info", "Describe a scene: objects, triangles, edges, lights, cameras, memory");
  info_cmd->add_option("scene", info.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
  info_cmd->add_option("--subdiv-level", info.subdiv_level, "Override the subdivision level of every subdivided mesh")
      ->check(CLI::Range(0, 8));

  RenderOptions render;
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Render a scene to an image file and print a timing summary (default: --mode epi, the edge-and-point renderer)");
  render_cmd->add_option("scene", render.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
#ifdef EPI_WITH_FRAMES
  render_cmd
      ->add_option("--mode", render.mode,
                   "epi (the default): the edge-and-point renderer, run over --frames frames of the camera path; "
                   "rendercache: the same without edges; raytrace: 1 sample per pixel; reference: converged, --spp "
                   "samples per pixel")
      ->check(CLI::IsMember({"epi", "rendercache", "raytrace", "reference"}))
      ->capture_default_str();
  render_cmd->add_option("--frames", render.frames, "Frames to run (epi, rendercache); the image is the last frame")->check(CLI::Range(1, 1000000))->capture_default_str();
  render_cmd->add_flag("--sync", render.sync,
                       "Shade exactly the sample budget inside every frame: the same bytes for the same seed. Default: "
                       "asynchronous, as interactively (the shader runs beside the frame loop; timing-dependent)");
  render_cmd->add_option("--sample-budget", render.sample_budget, "Fraction of the pixels shaded per frame")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  render_cmd->add_option("--camera-path", render.camera_path, "Camera keys per frame (docs/camera-path.md)");
  render_cmd->add_option("--frames-out", render.frames_out, "Write every frame, e.g. frames/f%04d.png");
  render_cmd->add_option("--save-epi", render.save_epi, "Write the last frame's EPI snapshot (mode epi), for epi-visualizer");
  render_cmd->add_flag("!--no-speedup", render.speedup,
                       "Skip the 1-spp ray trace of the last view that the speed-up over ray tracing is measured with");
#else
  render.mode = "reference";  // built without the frame loop
  render_cmd->add_option("--mode", render.mode, "reference: converged, --spp samples per pixel; raytrace: 1 sample per pixel")
      ->check(CLI::IsMember({"reference", "raytrace"}))
      ->capture_default_str();
#endif
  add_size_option(*render_cmd, render.width, render.height);
  render_cmd->add_option("--spp", render.spp, "Samples per pixel (reference mode)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  render_cmd->add_option("--shader", render.shader, "direct: lights and soft shadows; glossy: + glossy reflection; gi: + path-traced indirect")
      ->check(CLI::IsMember({"direct", "glossy", "gi"}))
      ->capture_default_str();
  render_cmd->add_option("--seed", render.seed, "Random seed (results do not depend on --threads)")->capture_default_str();
  render_cmd->add_option("--threads", render.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 1024));
  render_cmd->add_option("-o,--output", render.output, "Output image; format from the extension (.exr linear, .png sRGB)")
      ->capture_default_str();
  render_cmd->add_option("--stats", render.stats, "Write timings, rays traced and Mrays/s, and counts as JSON");
  render_cmd->add_option("--reference", render.reference,
                         "Print the written image's error against this reference image (as epi compare), also into --stats");
  render_cmd->add_option("--exposure", render.exposure,
                         "Exposure in stops for 8-bit outputs (.png): linear * 2^stops, then a highlight shoulder above "
                         "0.8 that keeps hue, then sRGB. EXR is written linear, untouched")
      ->check(CLI::Range(-32.0f, 32.0f))
      ->capture_default_str();
  render_cmd->add_option("--area-light-samples", render.shading.area_light_samples, "Shadow rays to area lights per hit")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  render_cmd->add_option("--glossy-samples", render.shading.glossy_samples, "Glossy reflection rays per hit (glossy shader)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  render_cmd
      ->add_option("--glossy-light-samples", render.shading.glossy_light_samples,
                   "Area-light shadow rays at each reflected hit (glossy shader)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  render_cmd->add_option("--gi-paths", render.shading.gi_paths, "Indirect paths per hit (gi shader)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  render_cmd->add_option("--gi-light-samples", render.shading.gi_light_samples, "Area-light shadow rays per path vertex (gi shader)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  render_cmd->add_option("--gi-max-bounces", render.shading.gi_max_bounces, "Longest indirect path, in bounces (gi shader)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  render_cmd->add_flag("--soft-shadow-edges", render.soft_shadow_edges,
                       "epi mode: also cut interpolation at area lights' umbral and penumbral edges, as the paper does "
                       "(off by default: it costs quality where a penumbra is a few pixels wide; docs/render.md)");
  render_cmd->add_flag("--quiet", render.quiet, "No progress bar, no repair report");
  render_cmd->add_option("--subdiv-level", render.subdiv_level, "Override the subdivision level")->check(CLI::Range(0, 8));
  add_camera_options(*render_cmd, render.camera);

  CompareOptions compare;
  CLI::App* compare_cmd = app.add_subcommand(
      "compare", "Compare an image with a reference: display-space RMSE, relative MSE (linear), pixels off by > 0.1 and > 0.2");
  compare_cmd->add_option("image", compare.image, "Image file (.exr linear, .png display-referred)")->required();
  compare_cmd->add_option("reference", compare.reference, "Reference image of the same size")->required();
  compare_cmd->add_option("--json", compare.json, "Write the metrics as JSON");
  compare_cmd->add_option("--diff", compare.diff, "Write the display difference, per channel, times --diff-scale, as an image");
  compare_cmd->add_option("--diff-scale", compare.diff_scale, "Factor on the difference image")
      ->check(CLI::Range(0.001f, 1000.0f))
      ->capture_default_str();
  compare_cmd->add_option("--exposure", compare.exposure, "Exposure in stops taking linear images to display space, as for PNG output")
      ->check(CLI::Range(-32.0f, 32.0f))
      ->capture_default_str();

#ifdef EPI_WITH_RECONSTRUCT
  ReconstructOptions reconstruct;
  CLI::App* reconstruct_cmd =
      app.add_subcommand("reconstruct", "2D harness: sample a polygon pattern sparsely and reconstruct it with the EPI filters");
  reconstruct_cmd->add_option("pattern", reconstruct.pattern, "PATTERN.json (polygons in pixel units)")->required();
  reconstruct_cmd->add_option("--density", reconstruct.density, "Fraction of pixels that get one sample")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  reconstruct_cmd->add_option("--filter", reconstruct.filter, "epi: edge-respecting; rendercache: the render cache's")
      ->check(CLI::IsMember({"epi", "rendercache"}))
      ->capture_default_str();
  reconstruct_cmd->add_option("--seed", reconstruct.seed, "Sampling seed")->capture_default_str();
  reconstruct_cmd->add_flag("!--no-aa", reconstruct.antialias, "Turn anti-aliasing off");
  reconstruct_cmd->add_flag("!--no-complex", reconstruct.complex_filter, "Turn the complex-pixel filter off");
  reconstruct_cmd->add_option("-o,--output", reconstruct.output, "Output image (.exr keeps linear values)")->required();
  reconstruct_cmd->add_option("--stats", reconstruct.stats, "Write timings and pixel classes as JSON");
  reconstruct_cmd->add_option("--threads", reconstruct.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 1024));
  reconstruct_cmd->add_flag("--quiet", reconstruct.quiet, "No progress output");
#endif

#ifdef EPI_WITH_EDGES
  EdgesOptions edges;
  CLI::App* edges_cmd = app.add_subcommand("edges", "Find the silhouette, sharp, border and shadow edges seen from a viewpoint");
  edges_cmd->add_option("scene", edges.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
  add_camera_options(*edges_cmd, edges.camera);
  add_size_option(*edges_cmd, edges.width, edges.height);
  edges_cmd->add_option("-o,--output", edges.output, "Edges as JSON (world space)")->required();
  edges_cmd->add_option("--svg", edges.svg, "Line drawing of the projected edges, coloured by kind");
  edges_cmd->add_option("--stats", edges.stats, "Counts by kind and timings as JSON");
  edges_cmd->add_option("--subdiv-level", edges.subdiv_level, "Override the subdivision level")->check(CLI::Range(0, 8));
  edges_cmd->add_option("--threads", edges.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 1024));
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // A command line that does not parse: the problem, then the usage of the (sub)command
    // that was being read (app.help() descends into it), exit code 2.
    std::fprintf(stderr, "epi: %s\n\n%s", e.what(), app.help().c_str());
    return kUsageExitCode;
  }

  try {
    if (info_cmd->parsed()) return run_info(info);
    if (render_cmd->parsed()) return run_render(render);
    if (compare_cmd->parsed()) return run_compare(compare);
#ifdef EPI_WITH_RECONSTRUCT
    if (reconstruct_cmd->parsed()) return run_reconstruct(reconstruct);
#endif
#ifdef EPI_WITH_EDGES
    if (edges_cmd->parsed()) return run_edges(edges);
#endif
  } catch (const std::exception& e) {
    std::fprintf(stderr, "epi: %s\n", e.what());
    return 1;
  }
  return 1;
}

// The `epi` command line: parsing only (CLI11 is slow to compile; it stays in this file and in
// render_flags.cpp, the flags `epi render` shares with `epi-viewer`).
// Each subcommand's work is in its own file, behind cli/commands.h.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "commands.h"

namespace {

using namespace epi::cli;

constexpr int kUsageExitCode = 2;  // a command line that does not parse; 1: the work failed

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
  add_memory_limit_option(*info_cmd, info.memory_limit);

  RenderOptions render;
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Render a scene to an image file and print a timing summary (default: --mode epi, the edge-and-point renderer)");
#ifdef EPI_WITH_FRAMES
  add_render_options(*render_cmd, render, true);
  render_cmd->add_option("--frames", render.frames, "Frames to run (epi, rendercache); the image is the last frame, whose view reference and raytrace render")->check(CLI::Range(1, 1000000))->capture_default_str();
  render_cmd->add_option("--frames-out", render.frames_out, "Write every frame, e.g. frames/f%04d.png (with --frames-at: those path frames)");
  render_cmd->add_option("--path-rate", render.path_rate,
                         "Follow the camera path at this many path frames per second of the loop's own clock, as a "
                         "viewer shows motion, instead of one path frame per rendered frame: a slower loop shows "
                         "fewer, farther apart frames (docs/render.md, \"The path on the clock\"). Default 0: off")
      ->check(kFinite & CLI::Range(0.0, 1e6));
  render_cmd->add_option("--frames-at", render.frames_at,
                         "Path frames, e.g. 15,25,59, that --frames-out writes (default: all); with --path-rate each is "
                         "drawn exactly at its key by the first frame whose clock reaches it")
      ->delimiter(',')
      ->check(CLI::Range(0, 999999));
  render_cmd->add_option("--save-epi", render.save_epi, "Write the last frame's EPI snapshot (mode epi), for epi-visualizer");
  render_cmd->add_flag("!--no-speedup", render.speedup,
                       "Skip the 1-spp ray trace of the last view that the speed-up over ray tracing is measured with");
#else
  add_render_options(*render_cmd, render, false);
#endif
  render_cmd->add_option("-o,--output", render.output, "Output image; format from the extension (.exr linear, .png sRGB)")
      ->capture_default_str();
  render_cmd->add_option("--stats", render.stats, "Write timings, rays traced and Mrays/s, and counts as JSON");
  render_cmd->add_option("--reference", render.reference,
                         "Print the written image's error against this reference image (as epi compare), also into --stats");
  render_cmd->add_flag("--quiet", render.quiet, "No progress bar, no repair report");

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
      ->check(kFinite & CLI::Range(-32.0f, 32.0f))
      ->capture_default_str();

#ifdef EPI_WITH_RECONSTRUCT
  ReconstructOptions reconstruct;
  CLI::App* reconstruct_cmd =
      app.add_subcommand("reconstruct", "2D harness: sample a polygon pattern sparsely and reconstruct it with the EPI filters");
  reconstruct_cmd->add_option("pattern", reconstruct.pattern, "PATTERN.json (polygons in pixel units)")->required();
  reconstruct_cmd->add_option("--density", reconstruct.density, "Fraction of pixels that get one sample")
      ->check(kFinite & CLI::Range(0.0, 1.0))
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
  add_memory_limit_option(*reconstruct_cmd, reconstruct.memory_limit);
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
  add_memory_limit_option(*edges_cmd, edges.memory_limit);
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

// `epi-viewer SCENE`: parsing only (CLI11 is slow to compile; the flags shared with `epi render`
// come from cli/render_flags.cpp). The window is in app.cpp.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "app.h"

int main(int argc, char** argv) {
  using epi::viewer::ViewerOptions;
  CLI::App app{"epi-viewer: move the camera, objects and lights through a scene and watch the edge-and-point "
               "renderer keep up (keys: H in the window, docs/viewer.md)"};
  app.set_version_flag("--version", "epi-viewer 0.1");
  ViewerOptions options;
  epi::cli::add_render_options(app, options.render, true);
  app.add_option("--script", options.script, "Play a script of input commands and exit when it ends (docs/viewer.md)");
  app.add_option("--frames", options.frames,
                 "Run N frames of the renderer with no input, save --screenshot, exit (with --script: the renderer stops after "
                 "N frames, the script runs to its end)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--screenshot", options.screenshot, "Save the rendered image on exit (.png tone-mapped, .exr linear)");
  app.add_option("--benchmark", options.benchmark, "Run N window frames orbiting the camera, print frame-time statistics, exit")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--record", options.record, "Camera path file that K (record) writes (docs/camera-path.md)");
  app.add_option("--path-rate", options.render.path_rate,
                 "Play the --camera-path at this many path frames per second of wall time, as a user would move, "
                 "instead of one path frame per rendered frame (docs/viewer.md, \"Paths on the clock\"). Default 0: off")
      ->check(epi::cli::kFinite & CLI::Range(0.0, 1e6))
      ->needs(app.get_option("--camera-path"));
  using epi::cli::kFinite;
  app.add_option("--ui-fps", options.ui_fps, "Window frame cap")->check(kFinite & CLI::Range(1.0, 1000.0))->capture_default_str();
  app.add_option("--max-fps", options.max_fps, "Frame-loop cap (0: as fast as it goes)")->check(kFinite & CLI::Range(0.0, 1000.0));
  app.add_option("--render-scale", options.render_scale,
                 "Render F times the window's size in each direction and scale the frames up to the window (bilinear): 0.5 "
                 "renders a quarter of the pixels, about three times the frames a second at 1920x1080 (docs/viewer.md, "
                 "\"Render scale\"). Screenshots are the rendered size")
      ->check(kFinite & CLI::Range(0.1, 1.0))
      ->capture_default_str();
  app.add_flag("--test-hold-shader", options.hold_shader, "Tests: the shader never returns a sample until exit")
      ->group("");  // hidden

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::fprintf(stderr, "epi-viewer: %s\n\n%s", e.what(), app.help().c_str());
    return 2;
  }
  try {
    return epi::viewer::run_viewer(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "epi-viewer: %s\n", e.what());
    return 1;
  }
}

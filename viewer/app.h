// epi-viewer: the window (GLFW, OpenGL texture upload, Dear ImGui) around a render::Session.
#pragma once

#include <string>

#include "render_options.h"

namespace epi::viewer {

struct ViewerOptions {
  cli::RenderOptions render;  // the flags shared with `epi render`
  std::string script;         // --script FILE
  int frames = 0;             // --frames N: run N frames of the renderer with no input, then exit
  std::string screenshot;     // --screenshot FILE: the rendered image at exit
  int benchmark = 0;          // --benchmark N: N window frames orbiting the camera, then statistics
  std::string record;         // --record FILE: the camera path recorded with K goes here
  double ui_fps = 60.0;       // window frame cap (vsync caps too, where the display has it)
  double max_fps = 0.0;       // frame-loop cap (0: as fast as it goes)
  double render_scale = 1.0;  // --render-scale F: the renderer's size as a share of the window's framebuffer
  bool hold_shader = false;   // tests: the shader blocks until exit (the window must not stall)
};

// Validates everything (exit code 1 and one line on failure, before any window), opens the window
// and runs until the window closes, the script ends, or --frames/--benchmark are done.
int run_viewer(const ViewerOptions& options);

}  // namespace epi::viewer

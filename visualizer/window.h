// The interactive window: the step drawings (draw.h) as an OpenGL texture, with ImGui controls
// (step, play/pause at a speed, jump to a stage, click a pixel, density, seed, presets).
#pragma once

#include <cstdint>
#include <string>

#include "model.h"

namespace epi::vis {

struct WindowOptions {
  std::string source;
  double density = 0.25;
  uint64_t seed = 1;
  int x = 0, y = 0;
  std::string screenshot;  // non-empty: save the window after the first frames and exit
  std::string record;      // non-empty: save the window as it closes, and print where it stood (tests)
  int step = 0;            // 1-based start step, 0: the first
};

// Returns the process exit code; throws std::runtime_error when no window can be opened.
int run_window(Model model, const WindowOptions& options);

}  // namespace epi::vis

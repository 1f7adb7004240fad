// epi-visualizer: steps a class through what the edge-and-point image does to one pixel
// (docs/visualizer.md). Headless with --export DIR; otherwise an interactive window.
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "export.h"
#include "model.h"
#include "presets.h"
#include "steps.h"
#include "window.h"

namespace {

// "X,Y" -> pixel; throws with the reason.
std::pair<int, int> parse_pixel(const std::string& text) {
  int x = 0, y = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%d,%d%c", &x, &y, &extra) != 2)
    throw std::invalid_argument("--pixel '" + text + "': expected X,Y (two integers)");
  return {x, y};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace epi::vis;
  CLI::App app("epi-visualizer: the edge-and-point image, stage by stage, for one pixel");
  std::string source = "checkerboard", pixel, export_dir, screenshot, record;
  double density = 0.25, seconds = 1.5;
  uint64_t seed = 1;
  bool list = false;
  int step = 0;
  app.add_option("source", source, "A preset name, a PATTERN.json (epi reconstruct's format) or an EPI snapshot (epi render --save-epi)")
      ->capture_default_str();
  app.add_option("--pixel", pixel, "The pixel to follow, X,Y (default: the preset's, else the edge pixel nearest the image centre)");
  app.add_option("--density", density, "Fraction of pixels that get one sample (patterns)")->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--seed", seed, "Sampling seed (patterns)")->capture_default_str();
  app.add_option("--export", export_dir, "Write every step as PNG and SVG, trace.json and animation.gif into this new folder; no window");
  app.add_option("--seconds-per-step", seconds, "Animation pace (export)")->check(CLI::Range(0.1, 60.0))->capture_default_str();
  app.add_flag("--list-presets", list, "List the presets and exit");
  app.add_option("--screenshot", screenshot, "Window: after drawing, save the window as PNG and exit (tests)");
  app.add_option("--record", record, "Window: save the window as PNG when it closes and print the pixel and step (tests)");
  app.add_option("--step", step, "Window: start at this step (1-based)")->check(CLI::Range(1, 100000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {  // --help prints and exits 0; a bad command line exits 2, as `epi` does
    return app.exit(e) == 0 ? 0 : 2;
  }

  try {
    if (list) {
      for (const Preset& p : presets()) std::printf("%-13s %s\n", p.name.c_str(), p.description.c_str());
      return 0;
    }
    Model model(load_source(source, density, seed));
    int x = model.width() / 2, y = model.height() / 2;
    if (const Preset* p = find_preset(source)) {
      x = p->pixel_x, y = p->pixel_y;
    } else {  // the simple (else complex) pixel nearest the centre: something to see
      long best = -1;
      for (int kind : {2, 1})
        if (best < 0)
          for (int py = 0; py < model.height(); ++py)
            for (int px = 0; px < model.width(); ++px) {
              const int type = model.type_at(px, py);
              if ((kind == 2) != (type >= 2) || type == 0) continue;
              const long d = long(px - model.width() / 2) * (px - model.width() / 2) + long(py - model.height() / 2) * (py - model.height() / 2);
              if (best < 0 || d < best) best = d, x = px, y = py;
            }
    }
    if (!pixel.empty()) {
      std::tie(x, y) = parse_pixel(pixel);
      if (x < 0 || y < 0 || x >= model.width() || y >= model.height())
        throw std::invalid_argument("--pixel " + pixel + " is outside the " + std::to_string(model.width()) + "x" +
                                    std::to_string(model.height()) + " image");
    }
    if (!export_dir.empty()) {
      const epi::PixelTrace trace = model.tracer().trace(x, y);
      const std::vector<Step> steps = build_steps(model, trace);
      export_steps(model, trace, steps, export_dir, seconds);
      std::printf("%s: pixel (%d, %d), %zu steps -> %s (step_NNN.png/.svg, trace.json, animation.gif)\n", source.c_str(), x, y,
                  steps.size(), export_dir.c_str());
      return 0;
    }
    WindowOptions options;
    options.source = source, options.density = density, options.seed = seed, options.x = x, options.y = y;
    options.screenshot = screenshot, options.record = record, options.step = step;
    return run_window(std::move(model), options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "epi-visualizer: %s\n", e.what());
    return 1;
  }
}

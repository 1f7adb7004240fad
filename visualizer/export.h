// Headless export: one numbered PNG and SVG per step, trace.json listing every step (stage,
// section, caption, values), and animation.gif of the whole sequence. Needs no display.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "epi/trace.h"
#include "model.h"
#include "steps.h"

namespace epi::vis {

// The step's picture as kCanvasWidth x kCanvasHeight RGB bytes (row-major, no padding).
std::vector<uint8_t> render_rgb(const Model& model, const PixelTrace& trace, const std::vector<Step>& steps, int index);

// trace.json's content.
nlohmann::ordered_json trace_json(const Model& model, const PixelTrace& trace, const std::vector<Step>& steps);

// Writes everything into `dir`, which must not exist or be empty (created if missing). Files are
// written into a temporary sibling folder first and moved in at the end. Throws
// std::runtime_error("<dir>: <problem>").
void export_steps(const Model& model, const PixelTrace& trace, const std::vector<Step>& steps, const std::string& dir,
                  double seconds_per_step = 1.5);

// Writes an RGB8 image (width x height) as PNG (libpng).
void write_png(const std::string& file, const std::vector<uint8_t>& rgb, int width, int height);

}  // namespace epi::vis

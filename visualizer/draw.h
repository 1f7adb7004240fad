// Draws one step with Cairo: the window of pixels around the traced pixel on the left, the
// stage, caption, values and colour swatches on the right. The same function draws the PNG and
// SVG exports and the interactive window's image (docs/visualizer.md).
#pragma once

#include <cairo.h>

#include "epi/trace.h"
#include "model.h"
#include "steps.h"

namespace epi::vis {

constexpr int kCanvasWidth = 1280, kCanvasHeight = 800;

// Draws into a kCanvasWidth x kCanvasHeight surface. `index` counts from 0.
void draw_step(cairo_t* cr, const Model& model, const PixelTrace& trace, const Step& step, int index, int count);

// Where the main area maps image pixels (for the window's clicks): canvas point of pixel
// coordinate (px, py), and back.
struct Viewport {
  double x0, y0, cell;  // canvas position of image point (ox, oy), canvas px per image px
  double ox, oy;
  int px0, py0, px1, py1;  // the pixels shown, inclusive
  double to_canvas_x(double px) const { return x0 + (px - ox) * cell; }
  double to_canvas_y(double py) const { return y0 + (py - oy) * cell; }
};
Viewport viewport(const Model& model, const PixelTrace& trace, const View& view);

}  // namespace epi::vis

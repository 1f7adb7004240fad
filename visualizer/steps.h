// The teaching steps for one traced pixel: eight stages, each a sequence of steps with a
// one-sentence caption, the paper's section, the values shown, and what to draw (View).
// Steps are plain data: drawing one (draw.h) depends on nothing but the model and the step.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "epi/trace.h"
#include "model.h"

namespace epi::vis {

struct Rgba {
  double r = 0, g = 0, b = 0, a = 1;
};

// Everything below is in image pixel coordinates (pixel (x, y) covers [x, x+1) x [y, y+1)).
struct CellMark {
  double x, y, w = 1, h = 1;  // a rectangle (a pixel, or a sub-pixel)
  Rgba fill{0, 0, 0, 0};
  Rgba outline{0, 0, 0, 0};
  double outline_width = 0;  // canvas px
  std::string label;         // centred text
  bool hatch = false;        // cross-hatched (complex, outside the image)
};
struct Arrow {
  double x0, y0, x1, y1;
  Rgba color;
};
struct Shape {
  std::vector<std::array<double, 2>> points;
  bool closed = true;
  Rgba fill{0, 0, 0, 0};
  Rgba stroke{0, 0, 0, 0};
  double width = 2;  // canvas px
  bool dashed = false;
};
struct Text {
  double x, y;  // centre, image pixel coordinates
  std::string text;
  double size = 14;  // canvas px
  Rgba color{0.1, 0.1, 0.1, 1};
};
struct Swatch {
  std::string label;
  Rgb rgb;  // linear
};

struct View {
  int radius = 4;            // the (2r+1)^2 window around the traced pixel
  bool whole_image = false;  // the whole image instead of the window
  bool polygons = true;      // pattern: the exact scene, faint (snapshot: the EPI result, faint)
  double base_alpha = 0.4;   // how faint
  bool segments = true;      // the edge segments
  bool samples = true;       // sample dots at their 4x4 region centres
  bool sample_regions = false;  // the 4x4 region grid inside the traced pixel
  bool ambiguity = true;     // edge-ambiguous samples crossed out (from classification on)
  int crossings = 0;         // 0 none, 1 pixel sides, 2 pixel sides and centre lines
  bool reconstructed_edges = false;  // simple pixels' 10-bit edges
  bool classes = false;      // pixels filled by class
  bool subpixel_grid = false;
  std::vector<CellMark> marks;
  std::vector<Shape> shapes;
  std::vector<Arrow> arrows;
  std::vector<Text> texts;
  std::vector<Swatch> swatches;
};

struct Step {
  int stage = 1;        // 1..8
  std::string section;  // the paper's section, e.g. "5.2 Reachability map"
  std::string caption;  // one sentence
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  View view;
};

constexpr int kStageCount = 8;
const char* stage_name(int stage);  // "Input", "Edge rasterization", ...

std::vector<Step> build_steps(const Model& model, const PixelTrace& trace);

// The polygon of region 0 (A) or 1 (B) of a unit cell cut by the edge from boundary piece p_low
// to p_high (n pieces per side), in cell coordinates.
std::vector<std::array<double, 2>> region_polygon(int p_low, int p_high, int n, int region);

}  // namespace epi::vis

// The 2D harness: a PATTERN.json of coloured polygons, its edges, seeded point sampling and
// the exact (supersampled) image the reconstructions are measured against.
//   {"width":W,"height":H,"background":[r,g,b],"polygons":[{"color":[r,g,b],"points":[[x,y],...]},...]}
// Pixel units, y down, later polygons on top, linear colours in [0,1]; even-odd fill.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "epi/epi_pixel.h"
#include "epi/rasterize.h"
#include "image/image.h"

namespace epi {

// what(): "<file>: <problem>", one line.
struct PatternError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Polygon {
  std::array<float, 3> color{};
  std::vector<std::array<double, 2>> points;
};

struct Pattern {
  int width = 0, height = 0;
  std::array<float, 3> background{};
  std::vector<Polygon> polygons;
};

constexpr int kMaxPatternSize = 16384;

Pattern load_pattern(const std::string& file);
// `name` prefixes error messages.
Pattern parse_pattern(const std::string& json_text, const std::string& name);

// Every polygon boundary segment.
std::vector<Segment> pattern_edges(const Pattern& pattern);

// Colour of the topmost polygon containing (x, y), or the background.
std::array<float, 3> pattern_color(const Pattern& pattern, double x, double y);

// Every pixel independently gets a sample with probability `density` at a uniform position
// inside it (seeded, deterministic). Returns the number of samples.
int64_t sample_pattern(const Pattern& pattern, double density, uint64_t seed, EpiImage& epi);

// Exact pixel coverage: an n x n stratified supersampling of every pixel that any edge
// touches (crossings or endpoints inside), the colour at the centre elsewhere.
RgbImage exact_image(const Pattern& pattern, int n = 16);

// Pixels that an edge touches (crossing on any side, or an endpoint inside), row-major.
std::vector<uint8_t> edge_pixels(const Pattern& pattern);

}  // namespace epi

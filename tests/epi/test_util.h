// Helpers shared by the core/epi tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "epi/classify.h"
#include "epi/epi_pixel.h"
#include "epi/geometry.h"
#include "epi/pattern.h"
#include "epi/rasterize.h"
#include "epi/reconstruct.h"

namespace epi::test {

inline std::string pattern_path(const std::string& name) {
  return std::string(EPI_SOURCE_DIR) + "/tests/epi/patterns/" + name;
}

// An EPI built from a pattern: masks (with centre lines when `complex`), samples.
struct Built {
  Pattern pattern;
  BoundaryMasks masks;
  EpiImage epi;
};
inline Built build(const Pattern& pattern, double density, uint64_t seed, bool centre_lines = true) {
  Built b{pattern, BoundaryMasks(pattern.width, pattern.height, centre_lines), EpiImage(pattern.width, pattern.height)};
  const std::vector<Segment> edges = pattern_edges(pattern);
  rasterize_edges(b.masks, edges);
  sample_pattern(pattern, density, seed, b.epi);
  return b;
}

inline CellKind kind_of(const BoundaryMasks& masks, int x, int y) {
  uint8_t sides[4];
  masks.pixel_sides(x, y, sides);
  return geom::classify_cell(sides, 8).kind;
}

// Mean absolute error (over channels) on the pixels where select[i] != 0.
inline double mean_error(const RgbImage& a, const RgbImage& b, const std::vector<uint8_t>& select) {
  double sum = 0;
  int64_t n = 0;
  for (size_t i = 0; i < select.size(); ++i) {
    if (!select[i]) continue;
    for (int c = 0; c < 3; ++c) sum += std::abs(double(a.pixels[i * 3 + c]) - double(b.pixels[i * 3 + c]));
    ++n;
  }
  return n ? sum / double(3 * n) : 0.0;
}

// A random pattern: `count` random polygons (3 to 6 vertices) in a w x h image.
inline Pattern random_pattern(int w, int h, int count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Pattern p;
  p.width = w, p.height = h;
  p.background = {float(u(rng)), float(u(rng)), float(u(rng))};
  for (int i = 0; i < count; ++i) {
    Polygon poly;
    poly.color = {float(u(rng)), float(u(rng)), float(u(rng))};
    const double cx = u(rng) * w, cy = u(rng) * h, r = 1.0 + u(rng) * 0.3 * std::max(w, h);
    const int n = 3 + int(u(rng) * 4);
    for (int k = 0; k < n; ++k) {
      const double a = 6.283185307179586 * (k + 0.8 * u(rng)) / n;
      poly.points.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
    }
    p.polygons.push_back(poly);
  }
  return p;
}

// A fine checker of 0.3-pixel squares 0.34 pixels apart in a w x h image: nearly every pixel
// complex (and many sub-pixels of the complex filter too).
inline Pattern fine_checker(int w, int h) {
  Pattern p;
  p.width = w, p.height = h;
  p.background = {0.9f, 0.1f, 0.2f};
  for (int j = 0; j < h * 3; ++j)
    for (int i = 0; i < w * 3; ++i)
      if ((i + j) % 2 == 0) {
        const double x = i * 0.34 + 0.05, y = j * 0.34 + 0.05;
        p.polygons.push_back({{0.1f, 0.8f, 0.3f}, {{x, y}, {x + 0.3, y}, {x + 0.3, y + 0.3}, {x, y + 0.3}}});
      }
  return p;
}

}  // namespace epi::test

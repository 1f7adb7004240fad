// A linear-light RGB float image, row-major, y down: the currency between the renderer
// stages and image I/O. Pixel (x, y) covers [x, x+1) x [y, y+1).
#pragma once

#include <cstddef>
#include <vector>

namespace epi {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> pixels;  // 3 floats per pixel

  RgbImage() = default;
  RgbImage(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h) * 3, 0.0f) {}
  float* at(int x, int y) { return &pixels[(size_t(y) * size_t(width) + size_t(x)) * 3]; }
  const float* at(int x, int y) const { return &pixels[(size_t(y) * size_t(width) + size_t(x)) * 3]; }
};

}  // namespace epi

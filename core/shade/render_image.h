// Whole-image rendering with the shader: `reference` (many stratified samples per pixel) and
// `raytrace` (one sample per pixel, at the pixel centre: the paper's baseline).
#pragma once

#include <cstdint>
#include <functional>

#include "image/image.h"
#include "shade/shader.h"

namespace epi {

struct RenderStats {
  uint64_t rays = 0;
  uint64_t samples = 0;
  double seconds = 0.0;
  double mrays_per_second() const { return seconds > 0.0 ? double(rays) / seconds * 1e-6 : 0.0; }
};

// Averages spp samples per pixel (stratified on a sqrt(spp) grid, jittered from the shader's
// seed; spp == 1 samples the pixel centre). Parallel over 16x16 tiles, deterministic.
// progress (optional) receives the fraction done, from one thread at a time.
RgbImage render_image(const Shader& shader, const View& view, int spp,
                      const std::function<void(double)>& progress = {}, RenderStats* stats = nullptr);

}  // namespace epi

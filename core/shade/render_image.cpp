#include "shade/render_image.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "shade/sampling.h"

namespace epi {

namespace {
constexpr int kTile = 16;
constexpr uint64_t kStreamPixel = 4;
}  // namespace

RgbImage render_image(const Shader& shader, const View& view, int spp, const std::function<void(double)>& progress,
                      RenderStats* stats) {
  if (spp < 1) throw std::invalid_argument("render: samples per pixel " + std::to_string(spp) + " must be at least 1");
  const ViewFrame frame(view);
  const auto start = std::chrono::steady_clock::now();
  RgbImage image(view.width, view.height);
  const int tiles_x = (view.width + kTile - 1) / kTile, tiles_y = (view.height + kTile - 1) / kTile;
  const int tile_count = tiles_x * tiles_y;
  const int grid = int(std::sqrt(double(spp)));
  std::atomic<uint64_t> rays{0};
  std::atomic<int> tiles_done{0};
  std::mutex progress_mutex;
  int last_percent = -1;

  tbb::parallel_for(0, tile_count, [&](int tile) {
    FlushDenormals flush;
    std::vector<BlockerTriple> triples;
    uint64_t tile_rays = 0;
    const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
    for (int y = y0; y < std::min(y0 + kTile, view.height); ++y)
      for (int x = x0; x < std::min(x0 + kTile, view.width); ++x) {
        glm::vec3 sum(0.0f);
        const uint64_t pixel_key = hash_combine(shader.settings().seed, uint64_t(y) * uint64_t(view.width) + uint64_t(x));
        for (int s = 0; s < spp; ++s) {
          ShadeRequest request{uint32_t(s), float(x) + 0.5f, float(y) + 0.5f};
          if (spp > 1) {
            Rng rng(pixel_key, kStreamPixel, uint64_t(s));
            float a = rng.uniform(), b = rng.uniform();
            bool on_grid = s < grid * grid;
            request.x = float(x) + (on_grid ? (float(s % grid) + a) / float(grid) : a);
            request.y = float(y) + (on_grid ? (float(s / grid) + b) / float(grid) : b);
          }
          triples.clear();
          sum += shader.shade_one(frame, request, triples, tile_rays).color;
        }
        sum /= float(spp);
        float* out = image.at(x, y);
        out[0] = sum.x, out[1] = sum.y, out[2] = sum.z;
      }
    rays.fetch_add(tile_rays, std::memory_order_relaxed);
    tiles_done.fetch_add(1);
    if (progress) {
      std::lock_guard lock(progress_mutex);
      int done = tiles_done.load();  // read under the lock: reports never go backwards
      int percent = int(100.0 * done / tile_count);
      if (percent != last_percent) {
        last_percent = percent;
        progress(double(done) / tile_count);
      }
    }
  });
  shader.add_rays(rays.load());
  if (stats) {
    stats->rays = rays.load();
    stats->samples = uint64_t(view.width) * uint64_t(view.height) * uint64_t(spp);
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return image;
}

}  // namespace epi

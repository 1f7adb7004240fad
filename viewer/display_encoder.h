// Linear frames to RGBA8 for epi-viewer's window (on the frame thread). No GL: the display
// benchmark (bench/viewer) and the viewer's unit tests use it without a window.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "image/image.h"
#include "image_io.h"

namespace epi::viewer {

// Linear RGB -> RGBA8 for display: io/image's tone map, then sRGB through a table (65537 entries:
// at most one level from write_image's exact encoding, and that rarely).
class DisplayEncoder {
 public:
  DisplayEncoder() {
    for (size_t i = 0; i < table_.size(); ++i) {
      const float v = float(i) / float(table_.size() - 1);
      const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
      table_[i] = uint8_t(std::lround(std::clamp(s, 0.0f, 1.0f) * 255.0f));
    }
  }
  void set_exposure(float stops) { exposure_.store(stops); }
  float exposure() const { return exposure_.load(); }

  // One display pixel from its tone-mapped channels (each in [0, 1]).
  uint32_t pixel(const float* display) const {
    constexpr float top = float(kTableSize - 1);
    // (int32, not size_t: a float to 64-bit unsigned conversion is a branchy sequence on x86-64)
    auto level = [&](float v) { return uint32_t(table_[uint32_t(int32_t(v * top + 0.5f))]); };
    return level(display[0]) | level(display[1]) << 8 | level(display[2]) << 16 | 0xff000000u;
  }

  void encode(const RgbImage& image, uint32_t* rgba) const {
    const size_t pixels = size_t(image.width) * size_t(image.height);
    const float stops = exposure_.load();
    // Tone-mapped a run of pixels at a time (the exposure's factor once a run, not once a pixel).
    constexpr size_t kRun = 1024;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 4 * kRun), [&](const tbb::blocked_range<size_t>& r) {
      float display[3 * kRun];
      for (size_t i = r.begin(); i < r.end(); i += kRun) {
        const size_t n = std::min(kRun, r.end() - i);
        tone_map_pixels(&image.pixels[3 * i], n, stops, display);
        for (size_t k = 0; k < n; ++k) rgba[i + k] = pixel(display + 3 * k);
      }
    });
  }

 private:
  static constexpr size_t kTableSize = 65537;
  std::array<uint8_t, kTableSize> table_;
  std::atomic<float> exposure_{0.0f};
};

}  // namespace epi::viewer

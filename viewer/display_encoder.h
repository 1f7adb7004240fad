// Linear frames to RGBA8 for epi-viewer's window (on the frame thread). No GL: the display
// benchmark (bench/viewer) and the viewer's unit tests use it without a window.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace epi::viewer {

// Entries of the sRGB table: display values in [0, 1] in steps of 1/65536.
inline constexpr size_t kDisplayLevels = 65537;

// The sRGB level of a tone-mapped channel v in [0, 1]: the table entry nearest v (the index an
// int32 conversion: a float to 64-bit unsigned one is a branchy sequence on x86-64).
inline uint32_t display_level(const uint32_t* levels, float v) {
  return levels[uint32_t(int32_t(v * float(kDisplayLevels - 1) + 0.5f))];
}

// RGBA8 of `pixels` linear RGB pixels: io/image's tone_map at `exposure_stops`, then the sRGB
// level of each channel from `levels` (kDisplayLevels entries), alpha 255. Highway, dispatched
// to the best target; every target gives the bits of tone_map and the table a pixel at a time.
void encode_display_pixels(const float* linear, size_t pixels, float exposure_stops, const uint32_t* levels, uint32_t* rgba);

// Linear RGB -> RGBA8 for display: io/image's tone map, then sRGB through a table (65537 entries:
// at most one level from write_image's exact encoding, and that rarely).
class DisplayEncoder {
 public:
  DisplayEncoder();
  void set_exposure(float stops) { exposure_.store(stops); }
  float exposure() const { return exposure_.load(); }

  // One display pixel from its tone-mapped channels (each in [0, 1]).
  uint32_t pixel(const float* display) const {
    const uint32_t* l = levels_.data();
    return display_level(l, display[0]) | display_level(l, display[1]) << 8 | display_level(l, display[2]) << 16 | 0xff000000u;
  }

  // The whole image, in parallel runs (oneTBB).
  void encode(const RgbImage& image, uint32_t* rgba) const;

 private:
  std::vector<uint32_t> levels_;  // kDisplayLevels sRGB levels, 0-255
  std::atomic<float> exposure_{0.0f};
};

}  // namespace epi::viewer

// The edge-and-point image (EPI): 10 bytes per pixel, stored as three planes (SoA).
// The whole bit layout lives here; docs/epi.md explains it with pictures.
//
//   edge plane  (uint16)  bits 0-9   edge code (see geometry.h)
//                         bits 10-13 sample region: rx + 4*ry on the pixel's 4x4 interior grid
//                         bit  14    the pixel holds a sample
//                         bit  15    the sample is usable (not edge-ambiguous)
//   color plane (uint32)  bits 0-23  sample colour r, g, b, one byte each (encode_epi_color8: sRGB to 1, ratios above)
//                         bits 24-31 sample age (frames)
//   cache plane (uint32)  bits 0-23  primary-to-primary reachability to the 24 neighbours of the 5x5
//                         bits 24-27 pixel type (empty, complex, simple side pair + primary side)
//                         bits 28-31 spare
// The paper's 36 bits of "other Render Cache data" are: age (8) + reachability (24) + type (4).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace epi {

// The packed form of one pixel; the planes hold exactly these bytes, split by field.
#pragma pack(push, 1)
struct EpiPixel {
  uint16_t edge;
  uint32_t color;
  uint32_t cache;
};
#pragma pack(pop)
static_assert(sizeof(EpiPixel) == 10, "an EPI pixel is 10 bytes, as in the paper");

namespace bits {
constexpr uint16_t kCodeMask = 0x3ff;
constexpr int kRegionShift = 10;
constexpr uint16_t kHasSample = 1u << 14;
constexpr uint16_t kUsable = 1u << 15;
constexpr uint32_t kReachMask = 0xffffff;
constexpr int kTypeShift = 24;
constexpr int kAgeShift = 24;
}  // namespace bits

inline int edge_code(uint16_t edge) { return edge & bits::kCodeMask; }
inline int sample_region(uint16_t edge) { return (edge >> bits::kRegionShift) & 15; }
inline bool has_sample(uint16_t edge) { return edge & bits::kHasSample; }
inline bool usable_sample(uint16_t edge) { return edge & bits::kUsable; }
inline int pixel_type(uint32_t cache) { return int(cache >> bits::kTypeShift) & 15; }
inline uint32_t reach_mask(uint32_t cache) { return cache & bits::kReachMask; }
inline int sample_age(uint32_t color) { return int(color >> bits::kAgeShift); }

// 8-bit sRGB <-> linear light, over [0, 1]: the display's encoding (viewer, visualizer).
inline uint8_t encode_srgb8(float linear) {
  float v = linear <= 0.0f ? 0.0f : (linear >= 1.0f ? 1.0f : linear);
  v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(v * 255.0f));
}
inline const std::array<float, 256>& srgb8_to_linear() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double v = i / 255.0;
      t[size_t(i)] = float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table;
}

// The EPI's colour code, one byte per channel (docs/epi.md, "Colour"): codes 0..kEpiUnitCode are
// sRGB steps over [0, 1]; the codes above are equal ratio steps from 1 to kEpiColourMax, so a light
// seen directly (the Cornell box's lamp is 17, 12, 4) keeps its hue instead of clamping to white.
// Everything decodes through the one table epi_color8_to_linear() (the row kernels are handed it).
constexpr int kEpiUnitCode = 223;
constexpr float kEpiColourMax = 64.0f;
inline uint8_t encode_epi_color8(float linear) {
  if (!(linear > 0.0f)) return 0;  // negative and NaN
  if (linear <= 1.0f) {
    const float v = linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
    return uint8_t(std::lround(v * float(kEpiUnitCode)));
  }
  if (linear >= kEpiColourMax) return 255;  // and +inf
  const float steps = std::log(linear) / std::log(kEpiColourMax) * float(255 - kEpiUnitCode);
  return uint8_t(kEpiUnitCode + std::lround(steps));
}
inline const std::array<float, 256>& epi_color8_to_linear() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i <= kEpiUnitCode; ++i) {
      const double v = double(i) / kEpiUnitCode;
      t[size_t(i)] = float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
    }
    for (int i = kEpiUnitCode + 1; i < 256; ++i)
      t[size_t(i)] = float(std::pow(double(kEpiColourMax), double(i - kEpiUnitCode) / double(255 - kEpiUnitCode)));
    return t;
  }();
  return table;
}
// A colour brighter than kEpiColourMax is scaled down to it whole (its hue stays), not per channel.
inline float epi_color_scale(float r, float g, float b) {
  const float m = std::max(r, std::max(g, b));
  return m > kEpiColourMax ? kEpiColourMax / m : 1.0f;
}
inline uint32_t encode_epi_color(const float rgb[3]) {
  const float k = epi_color_scale(rgb[0], rgb[1], rgb[2]);
  return uint32_t(encode_epi_color8(k * rgb[0])) | uint32_t(encode_epi_color8(k * rgb[1])) << 8 |
         uint32_t(encode_epi_color8(k * rgb[2])) << 16;
}
inline void decode_color(uint32_t color, float rgb[3]) {
  const auto& lut = epi_color8_to_linear();
  rgb[0] = lut[color & 255];
  rgb[1] = lut[(color >> 8) & 255];
  rgb[2] = lut[(color >> 16) & 255];
}

// The image: three planes, row-major, y down.
struct EpiImage {
  int width = 0, height = 0;
  std::vector<uint16_t> edge;
  std::vector<uint32_t> color;
  std::vector<uint32_t> cache;

  EpiImage() = default;
  EpiImage(int w, int h)
      : width(w), height(h), edge(size_t(w) * size_t(h), 0), color(size_t(w) * size_t(h), 0),
        cache(size_t(w) * size_t(h), 0) {}
  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }

  // A point sample at (x + fx, y + fy), fx, fy in [0, 1); colour in linear light.
  void set_sample(int x, int y, double fx, double fy, const float rgb[3], int age = 0) {
    const int rx = std::min(3, std::max(0, int(fx * 4.0)));
    const int ry = std::min(3, std::max(0, int(fy * 4.0)));
    const size_t i = index(x, y);
    edge[i] = uint16_t((edge[i] & bits::kCodeMask) | ((rx + 4 * ry) << bits::kRegionShift) | bits::kHasSample);
    color[i] = encode_epi_color(rgb) | uint32_t(std::min(255, std::max(0, age))) << bits::kAgeShift;
  }
  void clear_sample(int x, int y) { edge[index(x, y)] &= bits::kCodeMask; }
};

}  // namespace epi

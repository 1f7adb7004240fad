// Image files through OpenImageIO. The format follows the file extension:
// .exr (and .hdr) keep linear float RGB, untouched; .png, .jpg, .tif, .ppm, .bmp get 8-bit sRGB
// after the display tone map below (docs/scene-format.md, "Image output").
#pragma once

#include <cstddef>
#include <filesystem>
#include <stdexcept>

#include "image/image.h"

namespace epi {

// what(): "<file>: <problem>", one line.
struct ImageIOError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The display tone map of the 8-bit formats, per pixel, on linear RGB:
//  1. exposure: multiply by 2^exposure_stops;
//  2. highlight shoulder on the largest channel m: identity up to kShoulderKnee (0.8), above it
//     m' = k + (1 - k) * x / (1 + x) with x = (m - k) / (1 - k), which is continuous with slope 1
//     at the knee and tends to 1; the three channels are scaled by m'/m, so hue and saturation
//     stay (a plain clamp turns bright colours white or shifts their hue);
//  3. negative and non-finite channels become 0.
// The result is in [0, 1]; sRGB encoding follows.
constexpr float kShoulderKnee = 0.8f;
void tone_map(const float* linear, float exposure_stops, float* display);
// tone_map of `pixels` consecutive RGB pixels, the same bits (the exposure's factor found once).
void tone_map_pixels(const float* linear, size_t pixels, float exposure_stops, float* display);
// Its inverse at exposure 0: linear RGB whose tone map is `display` (in [0, 1]); a largest channel
// of 1 maps to a large finite value. Writing such an image to an 8-bit file gives back the display
// bytes (the viewer's window screenshots).
void inverse_tone_map(const float* display, float* linear);

// sRGB transfer functions on [0, 1].
float linear_to_srgb(float v);
float srgb_to_linear(float v);

struct ImageWriteOptions {
  float exposure = 0.0f;  // stops, for the 8-bit formats (linear formats are written untouched)
};

// True for extensions that keep linear floats.
bool is_linear_format(const std::filesystem::path& file);

// Throws ImageIOError if `file` has no supported extension or its folder does not exist.
// Call before long work, so a bad -o fails at once.
void check_output_path(const std::filesystem::path& file);

// Writes atomically: a temporary file beside `file`, renamed into place only when complete.
// The bytes depend only on the pixels (no timestamp), so equal images give equal files.
void write_image(const std::filesystem::path& file, const RgbImage& image, const ImageWriteOptions& options = {});

// Reads any format OpenImageIO knows into linear RGB (8-bit formats are decoded from sRGB).
RgbImage read_image(const std::filesystem::path& file);

}  // namespace epi

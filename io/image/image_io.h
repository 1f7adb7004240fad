// Image files through OpenImageIO. The format follows the file extension:
// .exr (and .hdr) keep linear float RGB; .png, .jpg, .tif, .ppm, .bmp get 8-bit sRGB
// after a plain clamp to [0, 1] (a documented, invertible-below-1 tone map).
#pragma once

#include <filesystem>
#include <stdexcept>

#include "image/image.h"

namespace epi {

// what(): "<file>: <problem>", one line.
struct ImageIOError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// True for extensions that keep linear floats.
bool is_linear_format(const std::filesystem::path& file);

// Throws ImageIOError if `file` has no supported extension or its folder does not exist.
// Call before long work, so a bad -o fails at once.
void check_output_path(const std::filesystem::path& file);

// Writes atomically: a temporary file beside `file`, renamed into place only when complete.
// The bytes depend only on the pixels (no timestamp), so equal images give equal files.
void write_image(const std::filesystem::path& file, const RgbImage& image);

// Reads any format OpenImageIO knows into linear RGB (8-bit formats are decoded from sRGB).
RgbImage read_image(const std::filesystem::path& file);

}  // namespace epi

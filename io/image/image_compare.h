// Image quality metrics of an image against a reference: the one place they are computed
// (`epi compare`, `epi render --reference`, tests). Definitions in docs/scene-format.md,
// "Comparing images".
#pragma once

#include <filesystem>
#include <stdexcept>

#include "image/image.h"

namespace epi {

// How an image's values are to be read. Linear images (renders, EXR files) reach display space
// through the PNG output's tone map (tone_map, at the given exposure) and the sRGB encoding;
// display-referred images (8-bit files such as PNG) are display space as stored.
enum class ImageEncoding { linear, display };
ImageEncoding encoding_of_file(const std::filesystem::path& file);  // from the extension (io/image)

struct ImageDifference {
  int width = 0, height = 0;
  double display_rmse = 0.0;  // RMS over all pixels and channels of display values in [0, 1]
  double relative_mse = 0.0;  // mean over pixels and channels of (x - r)^2 / (r^2 + 0.01), linear values
  double over_0_1 = 0.0;      // fraction of pixels with some display channel off by more than 0.1
  double over_0_2 = 0.0;      // ... by more than 0.2
  double max_display_error = 0.0;  // the largest display difference of any channel
};

// Throws std::invalid_argument if the sizes differ or an image is empty.
ImageDifference compare_images(const RgbImage& image, ImageEncoding image_encoding, const RgbImage& reference,
                               ImageEncoding reference_encoding, float exposure_stops = 0.0f);

// The display difference as an image to look at: per channel |display(image) - display(reference)|
// times `scale`, clamped to 1, returned as linear values that a PNG (at exposure 0) shows as those
// display values. Throws as compare_images.
RgbImage difference_image(const RgbImage& image, ImageEncoding image_encoding, const RgbImage& reference,
                          ImageEncoding reference_encoding, float exposure_stops = 0.0f, float scale = 1.0f);

}  // namespace epi

// Display-space error through OpenImageIO's ImageBufAlgo::compare (RMS error and the counts of
// pixels over the two thresholds); the relative MSE in linear space, which it does not give, here.
#include "image_compare.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "image_io.h"

namespace epi {
namespace {

std::vector<float> display_values(const RgbImage& image, ImageEncoding encoding, float exposure) {
  std::vector<float> display(image.pixels.size());
  for (size_t i = 0; i < display.size(); i += 3) {
    if (encoding == ImageEncoding::display) {
      for (int c = 0; c < 3; ++c) {  // NaN as 0 and infinities clamped, as the tone map treats them
        const float v = image.pixels[i + c];
        display[i + c] = linear_to_srgb(std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f));
      }
    } else {
      float mapped[3];
      tone_map(&image.pixels[i], exposure, mapped);
      for (int c = 0; c < 3; ++c) display[i + c] = linear_to_srgb(mapped[c]);
    }
  }
  return display;
}

void check_sizes(const RgbImage& image, const RgbImage& reference) {
  if (image.width <= 0 || image.height <= 0) throw std::invalid_argument("empty image");
  if (image.width != reference.width || image.height != reference.height)
    throw std::invalid_argument("size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " differs from the reference's " + std::to_string(reference.width) + "x" +
                                std::to_string(reference.height));
}

}  // namespace

ImageEncoding encoding_of_file(const std::filesystem::path& file) {
  return is_linear_format(file) ? ImageEncoding::linear : ImageEncoding::display;
}

ImageDifference compare_images(const RgbImage& image, ImageEncoding image_encoding, const RgbImage& reference,
                               ImageEncoding reference_encoding, float exposure_stops) {
  check_sizes(image, reference);
  ImageDifference d;
  d.width = image.width, d.height = image.height;

  std::vector<float> a = display_values(image, image_encoding, exposure_stops);
  std::vector<float> b = display_values(reference, reference_encoding, exposure_stops);
  const OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT);
  const OIIO::ImageBuf buffer_a(spec, a.data()), buffer_b(spec, b.data());
  // A pixel counts once if any channel is over the threshold ("fail" 0.2, "warn" 0.1).
  const OIIO::ImageBufAlgo::CompareResults r = OIIO::ImageBufAlgo::compare(buffer_a, buffer_b, 0.2f, 0.1f);
  // (r.error is set whenever a pixel is over the fail threshold: a result here, not an error.)
  const double pixels = double(image.width) * double(image.height);
  d.display_rmse = r.rms_error;
  d.max_display_error = r.maxerror;
  d.over_0_1 = double(r.nwarn) / pixels;
  d.over_0_2 = double(r.nfail) / pixels;

  // Relative MSE on linear values (non-finite values count as 0, as the tone map treats them).
  double sum = 0.0;
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    const double x = std::isfinite(image.pixels[i]) ? image.pixels[i] : 0.0;
    const double y = std::isfinite(reference.pixels[i]) ? reference.pixels[i] : 0.0;
    sum += (x - y) * (x - y) / (y * y + 0.01);
  }
  d.relative_mse = sum / double(image.pixels.size());
  return d;
}

RgbImage difference_image(const RgbImage& image, ImageEncoding image_encoding, const RgbImage& reference,
                          ImageEncoding reference_encoding, float exposure_stops, float scale) {
  check_sizes(image, reference);
  const std::vector<float> a = display_values(image, image_encoding, exposure_stops);
  const std::vector<float> b = display_values(reference, reference_encoding, exposure_stops);
  RgbImage out(image.width, image.height);
  // Display values d below the tone map's knee (linear 0.8) come back from a PNG exactly (to 8 bits);
  // above it, the shoulder compresses them a little.
  for (size_t i = 0; i < a.size(); ++i) out.pixels[i] = srgb_to_linear(std::min(1.0f, std::fabs(a[i] - b[i]) * scale));
  return out;
}

}  // namespace epi

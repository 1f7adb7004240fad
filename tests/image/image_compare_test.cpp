// compare_images against a scalar reference of its documented definitions (docs/scene-format.md,
// "Comparing images"), on random images with highlights, negative and non-finite values.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "image_compare.h"
#include "image_io.h"

namespace epi {
namespace {

struct Expected {
  double rmse = 0, relative_mse = 0, over_0_1 = 0, over_0_2 = 0, max = 0;
};

// The definitions, one pixel at a time, without OpenImageIO.
Expected reference_metrics(const RgbImage& a, ImageEncoding ea, const RgbImage& b, ImageEncoding eb, float exposure) {
  auto display = [&](const RgbImage& image, ImageEncoding e, size_t p, float out[3]) {
    if (e == ImageEncoding::display) {
      for (int c = 0; c < 3; ++c) {
        const float v = image.pixels[3 * p + c];
        out[c] = std::isnan(v) ? 0.0f : v <= 0.0f ? 0.0f : v >= 1.0f ? 1.0f : linear_to_srgb(v);
      }
      return;
    }
    tone_map(&image.pixels[3 * p], exposure, out);
    for (int c = 0; c < 3; ++c) out[c] = linear_to_srgb(out[c]);
  };
  Expected x;
  const size_t pixels = size_t(a.width) * a.height;
  for (size_t p = 0; p < pixels; ++p) {
    float da[3], db[3];
    display(a, ea, p, da), display(b, eb, p, db);
    double largest = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = std::fabs(double(da[c]) - double(db[c]));
      x.rmse += d * d, largest = std::max(largest, d);
      const double u = std::isfinite(a.pixels[3 * p + c]) ? a.pixels[3 * p + c] : 0.0;
      const double r = std::isfinite(b.pixels[3 * p + c]) ? b.pixels[3 * p + c] : 0.0;
      x.relative_mse += (u - r) * (u - r) / (r * r + 0.01);
    }
    x.over_0_1 += largest > 0.1, x.over_0_2 += largest > 0.2, x.max = std::max(x.max, largest);
  }
  x.rmse = std::sqrt(x.rmse / (3.0 * pixels)), x.relative_mse /= 3.0 * pixels;
  x.over_0_1 /= pixels, x.over_0_2 /= pixels;
  return x;
}

TEST(CompareImages, MatchesTheDefinitionsOnRandomImages) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> value(0.0f, 1.5f), noise(-0.3f, 0.3f);
  for (int trial = 0; trial < 20; ++trial) {
    const int w = 1 + int(rng() % 40), h = 1 + int(rng() % 30);
    RgbImage a(w, h), b(w, h);
    for (size_t i = 0; i < a.pixels.size(); ++i) {
      b.pixels[i] = value(rng);
      a.pixels[i] = std::max(0.0f, b.pixels[i] + (rng() % 4 == 0 ? noise(rng) : 0.0f));
    }
    if (trial % 5 == 0) {  // non-finite and negative values, an HDR highlight
      a.pixels[0] = std::numeric_limits<float>::quiet_NaN(), b.pixels[1] = std::numeric_limits<float>::infinity();
      a.pixels[2 % a.pixels.size()] = -1.0f, b.pixels[0] = 40.0f;
    }
    const ImageEncoding ea = trial % 3 == 0 ? ImageEncoding::display : ImageEncoding::linear;
    const ImageEncoding eb = trial % 2 == 0 ? ImageEncoding::display : ImageEncoding::linear;
    const float exposure = trial % 4 == 1 ? 1.5f : 0.0f;
    const ImageDifference d = compare_images(a, ea, b, eb, exposure);
    const Expected x = reference_metrics(a, ea, b, eb, exposure);
    EXPECT_EQ(d.width, w);
    EXPECT_NEAR(d.display_rmse, x.rmse, 1e-6) << trial;
    EXPECT_NEAR(d.relative_mse, x.relative_mse, 1e-9 * (1 + x.relative_mse)) << trial;
    EXPECT_DOUBLE_EQ(d.over_0_1, x.over_0_1) << trial;
    EXPECT_DOUBLE_EQ(d.over_0_2, x.over_0_2) << trial;
    EXPECT_NEAR(d.max_display_error, x.max, 1e-6) << trial;
    EXPECT_GT(x.over_0_1, 0.0) << trial;  // the noise makes some pixels count
  }
}

TEST(CompareImages, IdenticalIsZeroAndSizesMustMatch) {
  RgbImage a(8, 4);
  for (size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = float(i % 7) * 0.3f;
  const ImageDifference d = compare_images(a, ImageEncoding::linear, a, ImageEncoding::linear);
  EXPECT_EQ(d.display_rmse, 0.0);
  EXPECT_EQ(d.relative_mse, 0.0);
  EXPECT_EQ(d.over_0_1, 0.0);
  EXPECT_THROW(compare_images(a, ImageEncoding::linear, RgbImage(4, 8), ImageEncoding::linear), std::invalid_argument);
  EXPECT_THROW(compare_images(RgbImage(), ImageEncoding::linear, RgbImage(), ImageEncoding::linear), std::invalid_argument);
}

}  // namespace
}  // namespace epi

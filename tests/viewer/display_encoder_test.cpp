// viewer/display_encoder.h: the frame thread's RGBA8 equals io/image's per-pixel tone map followed
// by the encoder's sRGB table, pixel for pixel, on every Highway target, whatever the image's size
// against the vectors and the parallel runs, at any exposure, for the values a frame can hold
// (negative, NaN, infinite, huge, exactly on the shoulder's knee).
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "display_encoder.h"
#include "image_io.h"

namespace epi::viewer {
namespace {

std::vector<uint32_t> per_pixel(const DisplayEncoder& encoder, const RgbImage& image) {
  std::vector<uint32_t> out(size_t(image.width) * size_t(image.height));
  for (size_t i = 0; i < out.size(); ++i) {
    float d[3];
    tone_map(&image.pixels[3 * i], encoder.exposure(), d);
    out[i] = encoder.pixel(d);
  }
  return out;
}

TEST(DisplayEncoder, EveryTargetEqualsThePerPixelToneMap) {
  const float specials[] = {0.0f, -0.0f, -1.0f, kShoulderKnee, std::nextafter(kShoulderKnee, 2.0f), 1.0f, 1e30f,
                            std::numeric_limits<float>::max(), std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::denorm_min()};
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    DisplayEncoder encoder;
    // Widths around the vectors (1-40 pixels), a parallel run less one, one and more, a ragged
    // image; specials in a fifth of the channels, or none (whole vectors below the knee).
    std::vector<std::pair<int, int>> sizes = {{4095, 1}, {4096, 1}, {4097, 1}, {301, 67}};
    for (int w = 1; w <= 40; ++w) sizes.push_back({w, 1});
    for (const auto& [w, h] : sizes)
      for (const float special_share : {0.2f, 0.0f}) {
        RgbImage image;
        image.width = w, image.height = h;
        image.pixels.resize(size_t(w) * size_t(h) * 3);
        for (size_t i = 0; i < image.pixels.size(); ++i)
          image.pixels[i] = u(rng) < special_share ? specials[i % std::size(specials)] : 0.9f * u(rng) * u(rng);
        for (const float stops : {0.0f, -2.5f, 1.0f, 7.0f}) {
          encoder.set_exposure(stops);
          std::vector<uint32_t> rgba(size_t(w) * size_t(h), 0u);
          encoder.encode(image, rgba.data());
          const std::vector<uint32_t> expected = per_pixel(encoder, image);
          for (size_t i = 0; i < rgba.size(); ++i)
            ASSERT_EQ(rgba[i], expected[i]) << hwy::TargetName(target) << ", " << w << "x" << h << ", " << stops
                                            << " stops, pixel " << i << " (" << image.pixels[3 * i] << ", "
                                            << image.pixels[3 * i + 1] << ", " << image.pixels[3 * i + 2] << ")";
        }
      }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The table's ends and a mid-grey, against the exact sRGB encoding.
TEST(DisplayEncoder, BlackWhiteAndGreyEncodeAsSrgb) {
  const DisplayEncoder encoder;
  const float black[3] = {0.0f, 0.0f, 0.0f}, white[3] = {1.0f, 1.0f, 1.0f}, grey[3] = {0.22f, 0.22f, 0.22f};
  EXPECT_EQ(encoder.pixel(black), 0xff000000u);
  EXPECT_EQ(encoder.pixel(white), 0xffffffffu);
  EXPECT_EQ(encoder.pixel(grey), 0xff818181u);  // sRGB(0.22) = 0.5064: 129
}

}  // namespace
}  // namespace epi::viewer

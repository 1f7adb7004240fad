// An 8192x8192 edge-and-point image reconstructed (the 2D pipeline: rasterized edges, sparse
// samples, every filter): ~2.4 GB, ~5 s in Release and ~21 s under ASan+UBSan (both stages run it),
// so it is its own program, labelled `large` (`ctest -LE large` skips it; docs/reliability.md).
// The frame loop itself at this size needs ~10 GB (160 bytes a pixel) and is refused by the CLI's
// memory estimate under the default limit; the smaller frame-loop sizes are in edges_on_pixels_test.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "epi/reconstruct.h"

namespace epi {
namespace {

constexpr int kSize = 8192;
constexpr double kVertical = 4096.5;  // through the centres of column 4096 (complex pixels)
constexpr int kHorizontal = 6000;     // exactly on the border between rows 5999 and 6000

const float kRed[3] = {0.8f, 0.05f, 0.05f}, kBlue[3] = {0.05f, 0.1f, 0.8f}, kGreen[3] = {0.1f, 0.7f, 0.1f};

const float* region(double x, double y) { return y > kHorizontal ? kGreen : x < kVertical ? kRed : kBlue; }

TEST(LargeImage, An8192SquareEpiReconstructsWithEdgesWhereTheyMustBe) {
  EpiImage epi(kSize, kSize);
  BoundaryMasks masks(kSize, kSize, true);
  const std::vector<Segment> segments = {{kVertical, 0.0, kVertical, double(kHorizontal)},
                                         {0.0, double(kHorizontal), double(kSize), double(kHorizontal)}};
  rasterize_edges(masks, segments);
  // One sample in 4 pixels, at the centres of odd columns and rows (both sides of the vertical edge
  // have a sample one pixel from it).
  for (int y = 1; y < kSize; y += 2)
    for (int x = 1; x < kSize; x += 2) epi.set_sample(x, y, 0.5, 0.5, region(x + 0.5, y + 0.5));
  const auto t0 = std::chrono::steady_clock::now();
  Reconstruction out;
  {
    Reconstructor reconstructor;
    ReconstructSettings settings;  // epi filter, anti-aliasing and the complex filter on
    reconstructor.tiled(epi, masks, settings, Schedule{}, out);
  }
  std::printf("reconstruction %.0f ms\n", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  ASSERT_EQ(out.image.width, kSize);
  ASSERT_EQ(out.image.height, kSize);
  // Every pixel: finite, in range; whole pixels of a region have its colour; the pixels the
  // vertical edge halves mix its two sides half and half; no pixel reached no sample.
  size_t bad = 0, crossed = 0;
  std::string first;
  auto fail = [&](int x, int y, const char* why) {
    if (bad++ < 8) {
      const float* p = out.image.at(x, y);
      first += std::string(why) + " at (" + std::to_string(x) + ", " + std::to_string(y) + "): " + std::to_string(p[0]) +
               " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    }
  };
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const float* p = out.image.at(x, y);
      if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) {
        fail(x, y, "not finite");
        continue;
      }
      if (out.priority[size_t(y) * kSize + size_t(x)] >= 16.0f) fail(x, y, "no sample reached");
      if (x == 4096 && y < kHorizontal) {  // halved by the vertical edge
        ++crossed;
        for (int c = 0; c < 3; ++c)
          if (std::abs(p[c] - 0.5f * (kRed[c] + kBlue[c])) > 0.1f) fail(x, y, "crossed pixel not half and half");
        continue;
      }
      const float* want = region(x + 0.5, y + 0.5);
      // Beside the horizontal edge on the row border: 1/16 of the colour step (the masks' 1/8-pixel
      // precision, docs/reliability.md "Extremes"); elsewhere sRGB8 storage only.
      // Twice that at the T-junction where the vertical edge ends on the horizontal one.
      const bool beside = y == kHorizontal - 1 || y == kHorizontal, junction = beside && x >= 4095 && x <= 4097;
      const float tolerance = junction ? 2.0f * 0.75f / 16.0f + 0.02f : beside ? 0.75f / 16.0f + 0.02f : 0.02f;
      for (int c = 0; c < 3; ++c)
        if (std::abs(p[c] - want[c]) > tolerance) {
          fail(x, y, "wrong colour");
          break;
        }
    }
  EXPECT_EQ(bad, 0u) << first;
  EXPECT_EQ(crossed, size_t(kHorizontal));
}

}  // namespace
}  // namespace epi

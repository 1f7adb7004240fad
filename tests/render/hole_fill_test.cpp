// Hole filling (docs/render.md, "Holes"): holes take their own region's colours, never the other
// side of an edge, and a hole no filled pixel reaches stays as it is.
#include <gtest/gtest.h>

#include "render/hole_fill.h"

namespace epi::render {
namespace {

// 24x12: red on the left, blue on the right, a geometric edge along column 12; a hole 6 wide and
// 6 high straddles the edge (columns 9..14, rows 3..8).
TEST(HoleFill, HolesTakeTheirOwnRegionsColourAndNeverCrossAnEdge) {
  const int w = 24, h = 12;
  RgbImage image(w, h);
  std::vector<uint8_t> holes(size_t(w * h), 0), barrier(size_t(w * h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y * w + x);
      if (x == 12) barrier[i] = 1;
      const bool hole = x >= 9 && x <= 14 && y >= 3 && y <= 8;
      holes[i] = hole;
      if (hole) continue;  // black, as the filters leave it
      image.pixels[i * 3 + (x < 12 ? 0 : 2)] = 1.0f;  // the edge column itself is blue
    }
  const size_t filled = fill_holes(image, holes, barrier);
  EXPECT_EQ(filled, 36u);
  for (int y = 3; y <= 8; ++y)
    for (int x = 9; x <= 14; ++x) {
      const float* p = &image.pixels[size_t(y * w + x) * 3];
      if (x != 12) {
        EXPECT_EQ(p[x < 12 ? 0 : 2], 1.0f) << x << "," << y;
        EXPECT_EQ(p[x < 12 ? 2 : 0], 0.0f) << x << "," << y;
      }
      if (x == 12) {
        EXPECT_GT(p[0] + p[2], 0.99f) << y;  // on the edge: a mix of its neighbours, not black
      }
    }
}

// A whole hole image has nothing to fill from; a hole ring filled from outside blurs inwards.
TEST(HoleFill, NothingToFillFromLeavesTheHoleAndRingsBlendOutwards) {
  const int w = 9, h = 9;
  RgbImage image(w, h);
  std::vector<uint8_t> all(size_t(w * h), 1), none(size_t(w * h), 0);
  EXPECT_EQ(fill_holes(image, all, none), 0u);
  for (float v : image.pixels) EXPECT_EQ(v, 0.0f);
  // Left column white, right column black (filled), everything between a hole: the fill lies
  // between the two, never outside [0, 1], and is brighter towards the left.
  std::vector<uint8_t> holes(size_t(w * h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      holes[size_t(y * w + x)] = x > 0 && x < w - 1;
      for (int c = 0; c < 3; ++c) image.pixels[size_t(y * w + x) * 3 + size_t(c)] = x == 0 ? 1.0f : 0.0f;
    }
  EXPECT_EQ(fill_holes(image, holes, none), size_t(h * (w - 2)));
  for (int y = 0; y < h; ++y)
    for (int x = 1; x < w - 1; ++x) {
      const float v = image.pixels[size_t(y * w + x) * 3], left = image.pixels[size_t(y * w + x - 1) * 3];
      EXPECT_GE(v, 0.0f);
      EXPECT_LE(v, 1.0f);
      EXPECT_LE(v, left + 1e-6f) << x << "," << y;
    }
  EXPECT_GT(image.pixels[size_t(4 * w + 1) * 3], 0.4f);
  EXPECT_LT(image.pixels[size_t(4 * w + 7) * 3], 0.6f);
}

}  // namespace
}  // namespace epi::render

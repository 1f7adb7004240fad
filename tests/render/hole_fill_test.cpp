// Hole filling (docs/render.md, "Holes"): holes take their own region's colours, never the other
// side of an edge, and a hole no filled pixel reaches stays as it is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <hwy/targets.h>
#include <tbb/global_control.h>

#include "epi/interpolate.h"
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

// A region of holes the barrier encloses (a ring of barrier pixels that are filled, as the
// pixels an edge crosses are) has no source of its own: it takes the ring's colour, not black.
TEST(HoleFill, AnEnclosedRegionWithoutSourcesTakesTheColourAroundIt) {
  const int w = 11, h = 11;
  RgbImage image(w, h);
  std::vector<uint8_t> holes(size_t(w * h), 0), barrier(size_t(w * h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y * w + x);
      const int ring = std::max(std::abs(x - 5), std::abs(y - 5));
      barrier[i] = ring == 3;
      holes[i] = ring < 3;
      for (int c = 0; c < 3; ++c) image.pixels[i * 3 + size_t(c)] = ring == 3 ? 0.5f : ring > 3 ? 0.9f : 0.0f;
    }
  EXPECT_EQ(fill_holes(image, holes, barrier), 25u);
  for (int y = 3; y <= 7; ++y)
    for (int x = 3; x <= 7; ++x) EXPECT_FLOAT_EQ(image.pixels[size_t(y * w + x) * 3], 0.5f) << x << "," << y;
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

// The definition, written as whole-image sweeps: each sweep fills every hole off a barrier that
// touches a filled pixel off a barrier, from those pixels only (mean, neighbours in row order);
// then the holes on barriers from any filled neighbour; then sweeps over the holes left (regions
// the barriers enclose without a source) from any filled neighbour. Returns the count filled.
size_t fill_holes_by_sweeps(RgbImage& image, const std::vector<uint8_t>& holes, const std::vector<uint8_t>& barrier) {
  const int w = image.width, h = image.height;
  std::vector<uint8_t> filled(holes.size());
  for (size_t i = 0; i < holes.size(); ++i) filled[i] = !holes[i];
  auto mean_of = [&](int x, int y, bool any, float out[3]) {
    float sum[3] = {0, 0, 0};
    int count = 0;
    for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
      for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) {
        const size_t q = size_t(qy) * size_t(w) + size_t(qx);
        if (!filled[q] || (!any && barrier[q])) continue;
        for (int c = 0; c < 3; ++c) sum[c] += image.pixels[q * 3 + size_t(c)];
        ++count;
      }
    for (int c = 0; c < 3; ++c) out[c] = count ? sum[c] / float(count) : 0.0f;
    return count > 0;
  };
  size_t total = 0;
  for (;;) {
    std::vector<std::pair<size_t, std::array<float, 3>>> sweep;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        std::array<float, 3> c;
        if (!filled[i] && !barrier[i] && mean_of(x, y, false, c.data())) sweep.push_back({i, c});
      }
    if (sweep.empty()) break;
    for (const auto& [i, c] : sweep) {
      for (int k = 0; k < 3; ++k) image.pixels[i * 3 + size_t(k)] = c[size_t(k)];
      filled[i] = 1;
    }
    total += sweep.size();
  }
  std::vector<std::pair<size_t, std::array<float, 3>>> last;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      std::array<float, 3> c;
      if (!filled[i] && barrier[i] && mean_of(x, y, true, c.data())) last.push_back({i, c});
    }
  for (const auto& [i, c] : last) {
    for (int k = 0; k < 3; ++k) image.pixels[i * 3 + size_t(k)] = c[size_t(k)];
    filled[i] = 1;
  }
  total += last.size();
  for (;;) {
    std::vector<std::pair<size_t, std::array<float, 3>>> sweep;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        std::array<float, 3> c;
        if (!filled[i] && mean_of(x, y, true, c.data())) sweep.push_back({i, c});
      }
    if (sweep.empty()) break;
    for (const auto& [i, c] : sweep) {
      for (int k = 0; k < 3; ++k) image.pixels[i * 3 + size_t(k)] = c[size_t(k)];
      filled[i] = 1;
    }
    total += sweep.size();
  }
  return total;
}

// Random images with random blobs of holes and random barrier lines, sizes from 1x1 to 130x97,
// the scratch reused (and oneTBB held to one and four threads, for a parallel fill to come): the
// same bits and count as the definition.
TEST(HoleFill, EqualsTheDefinitionOnRandomImages) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  HoleFillScratch scratch;
  int filled_total = 0;
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{1, 40}, std::pair{40, 1}, std::pair{37, 23}, std::pair{130, 97},
                              std::pair{64, 70}}) {
    RgbImage image(w, h);
    for (float& v : image.pixels) v = u(rng);
    std::vector<uint8_t> holes(size_t(w) * size_t(h), 0), barrier(holes.size(), 0);
    for (int blob = 0; blob < 6; ++blob) {  // rectangles of holes, some covering most of the image
      const int x0 = int(u(rng) * float(w)), y0 = int(u(rng) * float(h));
      const int x1 = std::min(w, x0 + 1 + int(u(rng) * float(w) * 0.6f)), y1 = std::min(h, y0 + 1 + int(u(rng) * float(h) * 0.6f));
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) holes[size_t(y) * size_t(w) + size_t(x)] = 1;
    }
    for (size_t i = 0; i < holes.size(); ++i) holes[i] |= u(rng) < 0.1f;
    const int column = int(u(rng) * float(w)), row = int(u(rng) * float(h));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) barrier[size_t(y) * size_t(w) + size_t(x)] = x == column || y == row || u(rng) < 0.03f;
    for (size_t i = 0; i < holes.size(); ++i)
      if (holes[i]) image.pixels[i * 3] = image.pixels[i * 3 + 1] = image.pixels[i * 3 + 2] = 0.0f;
    RgbImage expected = image;
    const size_t expected_count = fill_holes_by_sweeps(expected, holes, barrier);
    filled_total += int(expected_count);
    for (const int threads : {1, 4}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
      RgbImage got = image;
      EXPECT_EQ(fill_holes(got, holes, barrier, scratch), expected_count) << w << "x" << h;
      EXPECT_EQ(got.pixels, expected.pixels) << w << "x" << h << ", " << threads << " threads";
    }
  }
  EXPECT_GT(filled_total, 2000);
}

// The renderer's pass (list_holes, then fill_listed_holes) against the per-pixel definition of a
// hole and a barrier fed to fill_holes: random reconstructions where some top-priority pixels are
// black (holes) and some are not, and random edge flags of which only some bits are barriers;
// sizes around the pass's 16-row bands and 64-pixel chunks, one and two threads.
TEST(HoleFill, TheRenderersListingEqualsThePerPixelDefinition) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const uint8_t barrier_bits = 1 | 4;
  size_t holes_total = 0;
  for (const int threads : {1, 2})
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {1, 40}, {40, 1}, {63, 17}, {64, 16}, {65, 33}, {130, 97}}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
      const size_t n = size_t(w) * size_t(h);
      RgbImage image(w, h);
      std::vector<float> priority(n);
      std::vector<uint8_t> flags(n), holes(n), barrier(n);
      const float hole_share = u(rng) * 0.3f;
      for (size_t i = 0; i < n; ++i) {
        const bool top = u(rng) < hole_share;
        priority[i] = top ? (u(rng) < 0.5f ? kMaxPriority : kMaxPriority * 2.0f) : u(rng) * kMaxPriority * 0.999f;
        const bool black = top ? u(rng) < 0.8f : u(rng) < 0.1f;  // black below the top: no hole
        for (int c = 0; c < 3; ++c) image.pixels[i * 3 + size_t(c)] = black ? 0.0f : (u(rng) < 0.3f ? 0.0f : u(rng));
        if (!black && image.pixels[i * 3] == 0.0f && image.pixels[i * 3 + 1] == 0.0f && image.pixels[i * 3 + 2] == 0.0f)
          image.pixels[i * 3 + 1] = 0.5f;
        flags[i] = uint8_t(rng() & 7u);
        holes[i] = top && black;
        barrier[i] = (flags[i] & barrier_bits) != 0;
        holes_total += holes[i];
      }
      RgbImage expected = image, listed = image;
      const size_t filled = fill_holes(expected, holes, barrier);
      HoleFillScratch scratch;
      std::vector<uint8_t> barrier_out;
      for (int round = 0; round < 2; ++round) {  // the scratch reused, as the renderer does
        listed = image;
        list_holes(listed, priority, flags, barrier_bits, barrier_out, scratch);
        EXPECT_EQ(barrier_out, barrier) << w << "x" << h;
        std::vector<uint32_t> want;
        for (size_t i = 0; i < n; ++i)
          if (holes[i]) want.push_back(uint32_t(i));
        EXPECT_EQ(scratch.holes, want) << w << "x" << h;
        EXPECT_EQ(fill_listed_holes(listed, barrier_out, scratch), filled) << w << "x" << h;
        EXPECT_EQ(listed.pixels, expected.pixels) << w << "x" << h;
      }
    }
  EXPECT_GT(holes_total, 1000u);
}

}  // namespace
}  // namespace epi::render

// hole_mask on every target compiled and supported here against is_hole, pixel by pixel: every
// count from 0 to 64 (vector remainders), priorities just below, at and above the top, NaN and
// infinities, colours of +0, -0, denormals, NaN and ordinary values in each channel.
namespace epi::render {
namespace {
TEST(HoleFill, TheHoleMaskGivesIsHolesBitsOnEveryTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float priorities[] = {kMaxPriority, std::nextafter(kMaxPriority, 0.0f), std::nextafter(kMaxPriority, 100.0f), 0.0f,
                              nan, inf, -inf, 3.0f};
  const float colours[] = {0.0f, -0.0f, std::numeric_limits<float>::denorm_min(), nan, 0.5f, inf};
  int holes = 0;
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937 rng(17);
    for (int round = 0; round < 40; ++round)
      for (size_t count = 0; count <= 64; ++count) {
        std::vector<float> top(count), rgb(3 * count);
        for (float& p : top) p = priorities[rng() % 8];
        // Mostly black, so that every channel decides some pixels.
        for (float& c : rgb) c = rng() % 4 == 0 ? colours[rng() % 6] : (rng() % 2 ? 0.0f : -0.0f);
        const uint64_t got = hole_mask(top.data(), rgb.data(), count);
        for (size_t k = 0; k < 64; ++k) {
          const bool want = k < count && is_hole(top[k], &rgb[3 * k]);
          ASSERT_EQ(bool((got >> k) & 1), want) << hwy::TargetName(target) << ", count " << count << ", pixel " << k;
          holes += want;
        }
      }
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GT(holes, 1000);
}
}  // namespace
}  // namespace epi::render

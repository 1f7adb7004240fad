// The sparse-region blend (docs/render.md, "Sparse regions"): the edge-stopping filter against its
// definition written as sums over each line's barrier-free runs, colour never crossing a barrier,
// dense regions left exactly as the EPI made them, and noisy sparse samples of a flat surface made
// closer to it than the EPI's patch per sample.
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "render/sparse_blend.h"

namespace epi::render {
namespace {

constexpr size_t C = kSparseBlendChannels;

// The filter by its definition, in double: per iteration, rows then columns, each pixel the sum of
// a^|d| x over the barrier-free run of its line that holds it (barrier pixels keep zeros).
std::vector<double> filter_by_definition(const EpiImage& epi, const std::vector<uint8_t>& barrier,
                                         const SparseBlendSettings& settings) {
  const int w = epi.width, h = epi.height;
  std::vector<double> s(C * size_t(w) * size_t(h), 0.0);
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    if (barrier[i]) continue;
    s[C * i + 4] = 1.0;
    if (has_sample(epi.edge[i])) {
      float rgb[3];
      decode_color(epi.color[i], rgb);
      s[C * i] = rgb[0], s[C * i + 1] = rgb[1], s[C * i + 2] = rgb[2], s[C * i + 3] = 1.0;
    }
  }
  const int n = settings.iterations;
  for (int k = 0; k < n; ++k) {
    const double sigma_k = settings.sigma * std::sqrt(3.0) * std::exp2(n - k - 1) / std::sqrt(std::exp2(2.0 * n) - 1.0);
    const double a = std::exp(-std::sqrt(2.0) / sigma_k);
    for (const bool rows : {true, false}) {
      const std::vector<double> in = s;
      const int lines = rows ? h : w, length = rows ? w : h;
      for (int line = 0; line < lines; ++line) {
        auto at = [&](int p) { return rows ? size_t(line) * size_t(w) + size_t(p) : size_t(p) * size_t(w) + size_t(line); };
        for (int p = 0; p < length; ++p) {
          if (barrier[at(p)]) continue;
          int lo = p, hi = p;
          while (lo > 0 && !barrier[at(lo - 1)]) --lo;
          while (hi + 1 < length && !barrier[at(hi + 1)]) ++hi;
          for (size_t c = 0; c < C; ++c) {
            double sum = 0.0;
            for (int q = lo; q <= hi; ++q) sum += std::pow(a, std::abs(p - q)) * in[C * at(q) + c];
            s[C * at(p) + c] = sum;
          }
        }
      }
    }
  }
  return s;
}

struct RandomEpi {
  EpiImage epi;
  std::vector<uint8_t> barrier;
};

RandomEpi random_epi(int w, int h, double sample_share, double barrier_share, std::mt19937& rng) {
  RandomEpi r{EpiImage(w, h), std::vector<uint8_t>(size_t(w) * size_t(h), 0)};
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Edge codes and ages as the EPI holds them: bits the filter must not read as colour.
      r.epi.edge[r.epi.index(x, y)] = uint16_t(rng() & bits::kCodeMask);
      if (u(rng) < sample_share) {
        const float rgb[3] = {float(u(rng)), float(u(rng)), float(2.0 * u(rng))};
        r.epi.set_sample(x, y, u(rng), u(rng), rgb, int(rng() % 256));
      }
      r.barrier[r.epi.index(x, y)] = u(rng) < barrier_share;
    }
  // An edge as the rasterizer marks one: a line of barrier pixels across the image.
  if (w > 4 && h > 4)
    for (int y = 0; y < h; ++y) r.barrier[r.epi.index(std::min(w - 1, w / 3 + y / 3), y)] = 1;
  return r;
}

TEST(SparseBlend, TheFilterEqualsItsDefinitionOnRandomImages) {
  std::mt19937 rng(21);
  int compared = 0;
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{1, 17}, std::pair{23, 1}, std::pair{37, 23}, std::pair{64, 40}})
    for (const double share : {0.02, 0.3, 1.0})
      for (const double barriers : {0.0, 0.05, 1.0})
        for (const int iterations : {1, 2, 3}) {
          const RandomEpi r = random_epi(w, h, share, barriers, rng);
          SparseBlendSettings settings;
          settings.iterations = iterations;
          settings.sigma = iterations == 3 ? 5.0f : 2.0f;
          std::vector<float> got;
          filter_samples(r.epi, r.barrier, settings, got);
          const std::vector<double> want = filter_by_definition(r.epi, r.barrier, settings);
          const size_t n = size_t(w) * size_t(h);
          ASSERT_GE(got.size(), C * n);
          for (size_t i = 0; i < n; ++i)
            for (size_t c = 0; c < C; ++c) {
              const double expected = want[C * i + c];
              ASSERT_NEAR(got[c * n + i], expected, 1e-4 * (1.0 + std::abs(expected)))
                  << w << "x" << h << ", share " << share << ", barriers " << barriers << ", pixel " << i << ", plane " << c;
              compared += expected != 0.0;
            }
        }
  EXPECT_GT(compared, 10000);
  EpiImage epi(4, 4);
  std::vector<float> sums;
  EXPECT_THROW(filter_samples(epi, std::vector<uint8_t>(3), SparseBlendSettings{}, sums), std::invalid_argument);
  SparseBlendSettings zero;
  zero.sigma = 0.0f;
  EXPECT_THROW(filter_samples(epi, std::vector<uint8_t>(16), zero, sums), std::invalid_argument);
}

// The Highway kernels on every target compiled and supported here against the scalar filter and
// blend: the same bits and count, for widths around the strip of 16 and the row groups of 8, at
// every sampling density and barrier share, over one to three iterations.
TEST(SparseBlend, EveryTargetGivesTheReferenceBits) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  int blended = 0;
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937 rng(33);
    for (const auto& [w, h] : {std::pair{1, 1}, std::pair{1, 17}, std::pair{15, 3}, std::pair{16, 9}, std::pair{17, 8},
                               std::pair{31, 33}, std::pair{33, 7}, std::pair{64, 40}, std::pair{70, 23}})
      for (const double share : {0.02, 0.15, 1.0})
        for (const double barriers : {0.0, 0.05, 1.0})
          for (const int iterations : {1, 2, 3}) {
            const RandomEpi r = random_epi(w, h, share, barriers, rng);
            SparseBlendSettings settings;
            settings.iterations = iterations;
            RgbImage image(w, h);
            std::uniform_real_distribution<float> u(0.0f, 2.0f);
            for (float& v : image.pixels) v = u(rng);
            RgbImage want = image;
            std::vector<float> sums;
            const size_t want_count = sparse_blend_reference(want, r.epi, r.barrier, settings, sums);
            SparseBlendScratch scratch;
            const size_t count = sparse_blend(image, r.epi, r.barrier, settings, scratch);
            ASSERT_EQ(count, want_count) << hwy::TargetName(target) << " " << w << "x" << h;
            for (size_t i = 0; i < want.pixels.size(); ++i)
              ASSERT_EQ(std::bit_cast<uint32_t>(image.pixels[i]), std::bit_cast<uint32_t>(want.pixels[i]))
                  << hwy::TargetName(target) << ", " << w << "x" << h << ", share " << share << ", barriers " << barriers
                  << ", iterations " << iterations << ", value " << i;
            blended += count > 0;
          }
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GT(blended, 100);
}

// A red region and a blue one, sparsely sampled, split by a column of barrier pixels, the image
// black: after the blend no pixel on either side holds any of the other side's colour, every one
// holds some of its own, and the barrier column stays black.
TEST(SparseBlend, NoColourCrossesABarrier) {
  const int w = 40, h = 30, wall = 17;
  EpiImage epi(w, h);
  std::vector<uint8_t> barrier(size_t(w) * size_t(h), 0);
  const float red[3] = {1, 0, 0}, blue[3] = {0, 0, 1};
  for (int y = 1; y < h; y += 7)
    for (int x = 2; x < w; x += 7)
      if (x != wall) epi.set_sample(x, y, 0.5, 0.5, x < wall ? red : blue);
  for (int y = 0; y < h; ++y) barrier[epi.index(wall, y)] = 1;
  RgbImage image(w, h);
  SparseBlendScratch scratch;
  const size_t changed = sparse_blend(image, epi, barrier, SparseBlendSettings{}, scratch);
  EXPECT_EQ(changed, size_t(w - 1) * size_t(h));  // every pixel but the barrier's: all sparse
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* p = &image.pixels[3 * epi.index(x, y)];
      if (x == wall) EXPECT_TRUE(p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f) << x << "," << y;
      else if (x < wall) EXPECT_TRUE(p[2] == 0.0f && p[0] > 0.0f) << x << "," << y;
      else EXPECT_TRUE(p[0] == 0.0f && p[2] > 0.0f) << x << "," << y;
    }
}

// Where every pixel (or every other one) holds a sample, the image is left bit for bit as it was,
// also along the image's border and beside barriers (the density counts only the kernel's part
// inside the image and the pixel's region). An empty 8x8 corner makes the frame one with a sparse
// block, so the filter runs; only pixels within 6 of that corner may change.
TEST(SparseBlend, DenseRegionsStayAsTheEpiMadeThem) {
  std::mt19937 rng(5);
  for (const int step : {1, 2})
    for (const bool empty_corner : {false, true}) {
      const int w = 33, h = 21;
      EpiImage epi(w, h);
      std::vector<uint8_t> barrier(size_t(w) * size_t(h), 0);
      std::uniform_real_distribution<float> u(0.0f, 1.0f);
      auto in_corner = [&](int x, int y) { return empty_corner && x >= 24 && y >= 16; };
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const float rgb[3] = {u(rng), u(rng), u(rng)};
          if ((x + y) % step == 0 && !in_corner(x, y)) epi.set_sample(x, y, 0.5, 0.5, rgb);
          barrier[epi.index(x, y)] = x == 11 || (y == 7 && x > 20);
        }
      EXPECT_EQ(any_sparse_block(epi, SparseBlendSettings{}.dense), empty_corner);
      RgbImage image(w, h);
      for (float& v : image.pixels) v = u(rng);
      const RgbImage before = image;
      SparseBlendScratch scratch;
      const size_t changed = sparse_blend(image, epi, barrier, SparseBlendSettings{}, scratch);
      EXPECT_EQ(changed > 0, empty_corner) << step;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if (x < 24 - 6 || y < 16 - 6)
            for (int c = 0; c < 3; ++c)
              ASSERT_EQ(image.pixels[3 * epi.index(x, y) + size_t(c)], before.pixels[3 * epi.index(x, y) + size_t(c)])
                  << "step " << step << ", pixel " << x << "," << y;
    }
}

// A flat grey surface sampled every 7 pixels (as a moving camera leaves a magnified one, 2 % a
// frame) with noisy results, the EPI's patch per sample given as the image: the blend brings the
// image closer to the true grey (RMSE 0.110 -> 0.091 at the default scale of 2 pixels; a scale
// of 2 averages few samples 7 pixels apart, which is what the bundled paths preferred).
TEST(SparseBlend, NoisySparseSamplesOfAFlatSurfaceComeCloserToIt) {
  const int w = 70, h = 49, spacing = 7;
  const float grey = 0.4f;
  std::mt19937 rng(9);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  EpiImage epi(w, h);
  std::vector<float> sample(size_t(w) * size_t(h), 0.0f);
  for (int y = spacing / 2; y < h; y += spacing)
    for (int x = spacing / 2; x < w; x += spacing) {
      const float v = std::max(0.0f, grey + noise(rng));
      const float rgb[3] = {v, v, v};
      epi.set_sample(x, y, 0.5, 0.5, rgb);
      float decoded[3];
      decode_color(epi.color[epi.index(x, y)], decoded);
      sample[epi.index(x, y)] = decoded[0];
    }
  RgbImage image(w, h);  // each pixel the colour of its cell's sample: the EPI's mosaic
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = sample[epi.index(x / spacing * spacing + spacing / 2, y / spacing * spacing + spacing / 2)];
      for (int c = 0; c < 3; ++c) image.pixels[3 * epi.index(x, y) + size_t(c)] = v;
    }
  auto rmse = [&](const RgbImage& im) {
    double sum = 0.0;
    for (float v : im.pixels) sum += double(v - grey) * double(v - grey);
    return std::sqrt(sum / double(im.pixels.size()));
  };
  const double before = rmse(image);
  SparseBlendScratch scratch;
  sparse_blend(image, epi, std::vector<uint8_t>(size_t(w) * size_t(h), 0), SparseBlendSettings{}, scratch);
  EXPECT_LT(rmse(image) * 1.15, before) << "before " << before << ", after " << rmse(image);
}

}  // namespace
}  // namespace epi::render

// The point cache's window-minimum kernels (core/render/depth_windows.h) on every Highway target
// compiled and supported here, against plain loops over the same windows: the same bits, for
// widths around every vector length (1 to 70 pixels), every radius the cache accepts, rows with
// empty pixels (+inf) and with runs of equal depths; the occlusion test's lone masks over windows
// of every size up to 31x31.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "render/depth_windows.h"
#include "render/point_cache.h"

namespace epi::render {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Depths as the point cache holds them: positive, +inf where a pixel is empty, and often equal
// (a plane seen face-on).
std::vector<float> random_row(std::mt19937& rng, int w) {
  std::uniform_real_distribution<float> depth(0.01f, 1e4f), chance(0.0f, 1.0f);
  std::vector<float> row(static_cast<size_t>(w));
  for (float& d : row) {
    const float c = chance(rng);
    d = c < 0.3f ? kInf : c < 0.4f ? 7.0f : depth(rng);
  }
  return row;
}

void expect_same_bits(const std::vector<float>& got, const std::vector<float>& want, const char* what, int64_t target,
                      int w, int radius) {
  for (size_t x = 0; x < want.size(); ++x)
    ASSERT_EQ(std::bit_cast<uint32_t>(got[x]), std::bit_cast<uint32_t>(want[x]))
        << what << " on " << hwy::TargetName(target) << ", width " << w << ", radius " << radius << ", x " << x;
}

TEST(DepthWindows, EveryTargetGivesThePlainLoopsBits) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937 rng(11);
    for (int w = 1; w <= 70 && !HasFailure(); ++w) {
      const std::vector<float> above = random_row(rng, w), row = random_row(rng, w), below = random_row(rng, w);
      const size_t n = size_t(w);
      // row_window_min, every radius.
      for (int radius = 1; radius <= kMaxOcclusionRadius; ++radius) {
        std::vector<float> got(n), want(n);
        for (int x = 0; x < w; ++x) {
          want[size_t(x)] = kInf;
          for (int q = std::max(0, x - radius); q <= std::min(w - 1, x + radius); ++q) want[size_t(x)] = std::min(want[size_t(x)], row[size_t(q)]);
        }
        row_window_min(row.data(), got.data(), w, radius);
        expect_same_bits(got, want, "row_window_min", target, w, radius);
      }
      // rows_min over one to three rows.
      const float* rows[3] = {row.data(), above.data(), below.data()};
      for (int count = 1; count <= 3; ++count) {
        std::vector<float> got(n), want(n);
        for (size_t x = 0; x < n; ++x) {
          want[x] = rows[0][x];
          for (int k = 1; k < count; ++k) want[x] = std::min(want[x], rows[k][x]);
        }
        rows_min(rows, count, got.data(), w);
        expect_same_bits(got, want, "rows_min", target, w, count);
      }
      // lone_depths, with and without the rows above and below (the image's first and last rows).
      for (const bool top : {false, true})
        for (const bool bottom : {false, true}) {
          std::vector<float> least(n), alone(n), want_least(n), want_alone(n);
          for (int x = 0; x < w; ++x) {
            float m = kInf;
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const float* r = dy < 0 ? (top ? nullptr : above.data()) : dy > 0 ? (bottom ? nullptr : below.data()) : row.data();
                if ((dx == 0 && dy == 0) || !r || x + dx < 0 || x + dx >= w) continue;
                m = std::min(m, r[x + dx]);
              }
            want_least[size_t(x)] = m;
            want_alone[size_t(x)] = m > row[size_t(x)] ? row[size_t(x)] : kInf;
          }
          lone_depths(top ? nullptr : above.data(), row.data(), bottom ? nullptr : below.data(), least.data(), alone.data(), w);
          expect_same_bits(least, want_least, "lone_depths' least", target, w, 1);
          expect_same_bits(alone, want_alone, "lone_depths' alone", target, w, 1);
        }
    }
    // lone_window_masks: windows of 1-31 columns and 1-31 rows at random places of a padded image,
    // depths that tie with the products often (a scale of 1 and equal depths) and the tested depth
    // among them.
    const int w = 45, h = 40;
    std::vector<float> alone(size_t(w) * size_t(h) + kWindowPad), neighbour_min(alone.size());
    for (int y = 0; y < h; ++y) {
      const std::vector<float> a = random_row(rng, w), b = random_row(rng, w);
      std::copy(a.begin(), a.end(), alone.begin() + y * w), std::copy(b.begin(), b.end(), neighbour_min.begin() + y * w);
    }
    std::uniform_int_distribution<int> pick(0, 1 << 20);
    for (int round = 0; round < 2000 && !HasFailure(); ++round) {
      const int n = 1 + pick(rng) % 31, rows = 1 + pick(rng) % 31;
      const int x0 = pick(rng) % (w - n + 1), y0 = pick(rng) % (h - rows + 1);
      const float scale = round % 3 == 0 ? 1.0f : 1.02f;
      const float depth = round % 2 == 0 ? 7.0f : alone[size_t(pick(rng)) % alone.size()];
      uint32_t got[31], want[31];
      for (int r = 0; r < rows; ++r) {
        want[r] = 0;
        for (int k = 0; k < n; ++k) {
          const size_t q = size_t(y0 + r) * size_t(w) + size_t(x0 + k);
          want[r] |= uint32_t((alone[q] * scale < depth) & !(neighbour_min[q] * scale < depth)) << k;
        }
      }
      lone_window_masks(&alone[size_t(y0) * size_t(w) + size_t(x0)], &neighbour_min[size_t(y0) * size_t(w) + size_t(x0)],
                        size_t(w), rows, n, scale, depth, got);
      for (int r = 0; r < rows; ++r)
        ASSERT_EQ(got[r], want[r]) << "lone_window_masks on " << hwy::TargetName(target) << ": " << n << " columns, row " << r;
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace
}  // namespace epi::render

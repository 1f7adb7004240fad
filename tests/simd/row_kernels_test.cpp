// The anti-aliasing and fill row kernels of every compiled target, called directly on
// random rows, against their per-pixel oracles (antialias_pixel, fill_pixel) bit for bit. The
// frames of kernels_test.cpp hold few simple pixels and fewer unfound ones; here every pixel
// may be simple (or unfound), every edge code and neighbour occurs, rows above and below are
// missing in every combination and widths run across the vector and chunk sizes.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <hwy/targets.h>

#include "epi/antialias.h"
#include "epi/fill.h"
#include "epi/rows.h"
#include "epi/tables.h"
#include "simd/row_kernels.h"

namespace epi {
namespace {

constexpr int kWidths[] = {1, 2, 3, 15, 16, 17, 31, 32, 33, 63, 64, 65, 66, 127, 128, 129, 191, 200, 1000};

bool same_bits(const float* a, const float* b, size_t n) { return std::memcmp(a, b, n * sizeof(float)) == 0; }

class RowKernels : public testing::TestWithParam<int64_t> {
 protected:
  const simd::RowKernels& kernels() const { return simd::row_kernels(GetParam()); }
};

// Random colours with a random share of simple pixels (0 to all of them), random edge words
// (every code, the usable and sample bits set at random), rows above and below present or not.
TEST_P(RowKernels, AntialiasEqualsTheOracle) {
  const EpiTables& t = epi_tables();
  std::vector<uint32_t> table(1024);
  for (int k = 0; k < 1024; ++k) table[size_t(k)] = t.area_a[k] | uint32_t(t.secondary_neighbour[k]) << 16;
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<float> colour(0.0f, 1.0f);
  int64_t blended = 0;
  for (int w : kWidths)
    for (double simple_share : {0.0, 0.02, 0.3, 0.9, 1.0})
      for (int rows_present = 0; rows_present < 4; ++rows_present) {
        SCOPED_TRACE("width " + std::to_string(w) + ", simple " + std::to_string(simple_share) + ", rows " +
                     std::to_string(rows_present));
        // Three rows of colours in one allocation (the kernel gathers relative to the own row),
        // edge words and types of the three rows (the oracle reads row 1's).
        std::vector<float> rgb(size_t(9 * w));
        for (float& c : rgb) c = colour(rng);
        std::vector<uint16_t> edge(size_t(3 * w));
        std::vector<uint8_t> types(size_t(3 * w));
        std::bernoulli_distribution simple(simple_share);
        for (int i = 0; i < 3 * w; ++i) {
          edge[size_t(i)] = uint16_t(rng());
          types[size_t(i)] = uint8_t(simple(rng) ? 2 + rng() % 12 : (rng() % 2 ? 0 : rng() % 2 ? 1 : 14 + rng() % 2));
        }
        const float* rows[3] = {rows_present & 1 ? rgb.data() : nullptr, rgb.data() + 3 * w,
                                rows_present & 2 ? rgb.data() + 6 * w : nullptr};
        const EpiRows epi{edge.data(), types.data(), nullptr, w, 3};
        std::vector<float> expected(size_t(3 * w)), out(size_t(3 * w), -1.0f);
        for (int x = 0; x < w; ++x) {
          antialias_pixel(epi, x, 1, rows, &expected[size_t(3 * x)]);
          blended += !same_bits(&expected[size_t(3 * x)], rows[1] + 3 * x, 3);
        }
        kernels().antialias({w, {rows[0], rows[1], rows[2]}, types.data() + w, edge.data() + w, table.data(), out.data()});
        for (int x = 0; x < w; ++x)
          ASSERT_TRUE(same_bits(&expected[size_t(3 * x)], &out[size_t(3 * x)], 3))
              << "pixel " << x << " type " << int(types[size_t(w + x)]) << " code " << (edge[size_t(w + x)] & 0x3ff);
      }
  EXPECT_GT(blended, 5000);  // the blend itself was compared, not only pass-through pixels
}

// Padded rows (simd::FillRow): random colours and found flags (0 to all pixels unfound), random
// reach masks; rows outside the image missing in every combination (zero rows for the kernel);
// into a separate row and in place.
TEST_P(RowKernels, FillEqualsTheOracle) {
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<float> colour(0.0f, 1.0f);
  int64_t filled = 0;
  for (int w : kWidths)
    for (double unfound_share : {0.0, 0.05, 0.5, 1.0})
      for (int outside : {0, 1, 2, 3, 4, 5, 6}) {
        SCOPED_TRACE("width " + std::to_string(w) + ", unfound " + std::to_string(unfound_share) + ", outside " +
                     std::to_string(outside));
        const size_t plane = size_t(w) + 2 * simd::kPad + 64;
        std::vector<float> rgb(5 * 3 * plane, 0.0f), zeros(3 * plane, 0.0f);
        std::vector<uint8_t> found(5 * plane, 0);
        std::bernoulli_distribution unfound(unfound_share);
        for (int k = 0; k < 5; ++k)
          for (int x = 0; x < w; ++x) {
            const size_t i = size_t(k) * plane + simd::kPad + size_t(x);
            for (int c = 0; c < 3; ++c) rgb[3 * i + size_t(c)] = colour(rng);
            found[i] = !unfound(rng);
          }
        std::vector<uint32_t> reach(static_cast<size_t>(w));
        for (uint32_t& m : reach) m = uint32_t(rng()) & 0xffffffu;
        // outside 1-2: the top one or two rows missing, 3-4 the bottom, 5 both of each, 6 only the own row.
        auto missing = [&](int k) {
          return (outside == 1 && k == 0) || (outside == 2 && k < 2) || (outside == 3 && k == 4) ||
                 (outside == 4 && k > 2) || (outside == 5 && (k == 0 || k == 4)) || (outside == 6 && k != 2);
        };
        const float* oracle_rows[5];
        const uint8_t* oracle_found[5];
        simd::FillRow row{w, {}, {}, reach.data(), nullptr};
        for (int k = 0; k < 5; ++k) {
          const float* r = rgb.data() + 3 * (size_t(k) * plane + simd::kPad);
          const uint8_t* f = found.data() + size_t(k) * plane + simd::kPad;
          oracle_rows[k] = missing(k) ? nullptr : r, oracle_found[k] = missing(k) ? nullptr : f;
          row.rows[k] = missing(k) ? zeros.data() + 3 * simd::kPad : r;
          row.found[k] = missing(k) ? reinterpret_cast<const uint8_t*>(zeros.data() + 3 * simd::kPad) : f;
        }
        std::vector<float> expected(size_t(3 * w)), out(size_t(3 * w), -1.0f);
        row.out = out.data();
        for (int x = 0; x < w; ++x) {
          fill_pixel(x, w, reach[size_t(x)], oracle_rows, oracle_found, &expected[size_t(3 * x)]);
          filled += !same_bits(&expected[size_t(3 * x)], oracle_rows[2] + 3 * x, 3);
        }
        kernels().fill(row);
        for (int x = 0; x < w; ++x)
          ASSERT_TRUE(same_bits(&expected[size_t(3 * x)], &out[size_t(3 * x)], 3))
              << "pixel " << x << " found " << int(oracle_found[2][x]) << " reach " << reach[size_t(x)];
        // In place (the tiled schedule): the own row overwritten, the same colours.
        float* own = rgb.data() + 3 * (2 * plane + simd::kPad);
        row.out = own;
        kernels().fill(row);
        for (int x = 0; x < w; ++x)
          ASSERT_TRUE(same_bits(&expected[size_t(3 * x)], own + 3 * x, 3)) << "in place, pixel " << x;
      }
  EXPECT_GT(filled, 4000);
}

std::string target_name(const testing::TestParamInfo<int64_t>& info) { return hwy::TargetName(info.param); }
INSTANTIATE_TEST_SUITE_P(EveryTarget, RowKernels, testing::ValuesIn(simd::compiled_targets()), target_name);

}  // namespace
}  // namespace epi

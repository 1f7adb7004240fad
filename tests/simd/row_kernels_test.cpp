// The anti-aliasing, fill, fallback-mean and fallback 7x7 reachability row kernels of every
// compiled target, called directly on random rows, against their per-pixel oracles
// (antialias_pixel, fill_pixel, fallback_color, reach_window7) bit for bit. The frames of
// kernels_test.cpp hold few simple pixels and fewer unfound ones; here every pixel
// may be simple (or unfound), every edge code and neighbour occurs, rows above and below are
// missing in every combination and widths run across the vector and chunk sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <hwy/targets.h>

#include "epi/antialias.h"
#include "epi/epi_pixel.h"
#include "epi/fill.h"
#include "epi/geometry.h"
#include "epi/interpolate.h"
#include "epi/reachability.h"
#include "epi/reconstruct.h"
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

// The fallback's whole-window mean (simd::WindowMeanRow) against fallback_color, whose answer
// for an edge-free 7x7 inside the image it is: seven rows of edge-free pixels, samples from none
// to all of them and usable from none to all of those (black where the window holds no usable
// sample), random pixels taken, none with a usable sample in its 5x5 (as the fallback's pixels:
// they reached nothing there); the pixels not taken, and those beyond `end`, keep their colour.
TEST_P(RowKernels, WindowMeanEqualsTheFallback) {
  std::mt19937_64 rng(33);
  const auto& lut = epi_color8_to_linear();
  int64_t coloured = 0, black = 0;
  for (int w : kWidths)
    for (double sampled_share : {0.0, 0.02, 0.2, 1.0})
      for (double usable_share : {0.0, 0.5, 1.0})
        for (double take_share : {0.1, 1.0}) {
          SCOPED_TRACE("width " + std::to_string(w) + ", sampled " + std::to_string(sampled_share) + ", usable " +
                       std::to_string(usable_share) + ", taken " + std::to_string(take_share));
          constexpr int kRows = 7;
          const size_t plane = size_t(w) + 2 * simd::kPad + 64;
          std::vector<uint16_t> edge(size_t(kRows * w));
          std::vector<uint32_t> color(size_t(kRows * w));
          const std::vector<uint8_t> types(size_t(kRows * w), uint8_t(kTypeEmpty));
          std::vector<float> red(kRows * plane, -0.0f), green(kRows * plane, 0.0f), blue(kRows * plane, 0.0f);
          std::bernoulli_distribution sampled(sampled_share), usable(usable_share), taken(take_share);
          simd::WindowMeanRow row{};
          for (int k = 0; k < kRows; ++k) {
            for (int x = 0; x < w; ++x) {
              const size_t i = size_t(k * w + x), p = size_t(k) * plane + simd::kPad + size_t(x);
              const bool has = sampled(rng), use = has && usable(rng);
              edge[i] = uint16_t((rng() & 0x3fff) | (has ? bits::kHasSample : 0) | (use ? bits::kUsable : 0));
              color[i] = uint32_t(rng());
              red[p] = std::copysign(lut[color[i] & 255], use ? 1.0f : -1.0f);
              green[p] = lut[(color[i] >> 8) & 255], blue[p] = lut[(color[i] >> 16) & 255];
            }
            row.red[k] = red.data() + size_t(k) * plane, row.green[k] = green.data() + size_t(k) * plane;
            row.blue[k] = blue.data() + size_t(k) * plane;
          }
          // Taken: interior pixels at random, within [first, end); marks outside it are stray.
          std::vector<uint8_t> take(size_t(w), 1);
          const int first = std::min(w, 3 + int(rng() % 5)), end = std::max(first, w - 3 - int(rng() % 5));
          // The span may start left of the first pixel that can be taken (the row's first unfound pixel).
          const int span_first = int(rng() % 4);
          for (int x = 0; x < first; ++x) take[size_t(x)] = x >= 3 && x + 3 < w && taken(rng);  // within the span
          for (int x = first; x < end; ++x) take[size_t(x)] = taken(rng);
          // A taken pixel reached nothing in its 5x5 (the kernel's precondition): no usable sample there.
          for (int x = 3; x < end; ++x)
            if (take[size_t(x)])
              for (int k = 1; k < kRows - 1; ++k)
                for (int px = x - 2; px <= x + 2; ++px) {
                  const size_t i = size_t(k * w + px), p = size_t(k) * plane + simd::kPad + size_t(px);
                  edge[i] &= uint16_t(~bits::kUsable);
                  red[p] = -std::abs(red[p]);
                }
          std::vector<float> out(3 * size_t(w)), before;
          for (float& c : out) c = float(rng() % 1000) - 2000.0f;
          before = out;
          row.width = w, row.take = take.data(), row.first = std::min(span_first, first), row.end = end, row.rgb = out.data();
          kernels().window_mean(row);
          const EpiRows rows{edge.data(), types.data(), color.data(), w, kRows};
          for (int x = 0; x < w; ++x) {
            const float* got = &out[3 * size_t(x)];
            if (x < 3 || x >= end || !take[size_t(x)]) {
              ASSERT_TRUE(same_bits(got, &before[3 * size_t(x)], 3)) << "pixel " << x << " not taken but written";
              continue;
            }
            float want[3];
            fallback_color(rows, x, 3, want);
            ASSERT_TRUE(same_bits(got, want, 3)) << "pixel " << x << ": " << got[0] << " against " << want[0];
            (want[0] + want[1] + want[2] > 0 ? coloured : black) += 1;
          }
        }
  EXPECT_GT(coloured, 5000);
  EXPECT_GT(black, 1000);
}

// The reachable mean by masks (WindowMeanRow with masks, the pixels with an edge in their 7x7)
// and the scalar last resort after it (fallback_reaching_row with the kernel's found flags)
// against the scalar fallback from the same masks, bit for bit: random types (so the masks cut
// the windows), samples and usable ones from none to all, every row of a 7-row image (rows
// outside read as zero rows), random pixels taken, each with no usable sample it reaches in its
// 5x5 (the fallback's pixels).
TEST_P(RowKernels, MaskedWindowMeanEqualsTheScalarFallback) {
  std::mt19937_64 rng(34);
  const auto& lut = epi_color8_to_linear();
  int64_t found = 0, last_resort = 0;
  constexpr int kRows = 7;
  for (int w : kWidths)
    for (double sampled_share : {0.02, 0.2, 1.0})
      for (double usable_share : {0.0, 0.5, 1.0})
        for (double simple_share : {0.1, 0.5}) {
          SCOPED_TRACE("width " + std::to_string(w) + ", sampled " + std::to_string(sampled_share) + ", usable " +
                       std::to_string(usable_share) + ", simple " + std::to_string(simple_share));
          const size_t plane = size_t(w) + 2 * simd::kPad + 64;
          std::bernoulli_distribution sampled(sampled_share), usable(usable_share), simple(simple_share),
              complex(0.03), taken(0.5);
          std::vector<uint16_t> edge(size_t(kRows * w));
          std::vector<uint32_t> color(size_t(kRows * w));
          std::vector<uint8_t> types(size_t(kRows * w));
          for (size_t i = 0; i < types.size(); ++i) {
            const bool has = sampled(rng), use = has && usable(rng);
            edge[i] = uint16_t((rng() & 0x3fff) | (has ? bits::kHasSample : 0) | (use ? bits::kUsable : 0));
            color[i] = uint32_t(rng());
            types[i] = uint8_t(complex(rng) ? kTypeComplex : simple(rng) ? 2 + int(rng() % 12) : kTypeEmpty);
          }
          const TypeRows type_rows{types.data(), w, kRows};
          for (int y = 0; y < kRows; ++y) {
            FallbackScratch scratch;
            scratch.reaching.assign(size_t(w), 0), scratch.reach7.assign(size_t(w), 0);
            const int first = int(rng() % size_t(w)), end = first + 1 + int(rng() % size_t(w - first));
            scratch.span_first = first, scratch.span_end = end;
            // Taken pixels reach no usable sample in their 5x5: the reached ones there made unusable.
            std::vector<uint16_t> edge_y = edge;
            for (int x = first; x < end; ++x) {
              if (!taken(rng)) continue;
              const uint64_t mask = reach_window7(type_rows, x, y);
              scratch.reaching[size_t(x)] = 1, scratch.reach7[size_t(x)] = mask, ++scratch.reaching_count;
              for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx)
                  if ((mask >> window7_bit(dx, dy)) & 1) edge_y[size_t((y + dy) * w + x + dx)] &= uint16_t(~bits::kUsable);
            }
            std::vector<float> red(kRows * plane, -0.0f), green(kRows * plane, 0.0f), blue(kRows * plane, 0.0f);
            std::vector<float> zero_red(plane, -0.0f), zero(plane, 0.0f);
            for (int r = 0; r < kRows; ++r)
              for (int x = 0; x < w; ++x) {
                const size_t i = size_t(r * w + x), p = size_t(r) * plane + simd::kPad + size_t(x);
                red[p] = std::copysign(lut[color[i] & 255], edge_y[i] & bits::kUsable ? 1.0f : -1.0f);
                green[p] = lut[(color[i] >> 8) & 255], blue[p] = lut[(color[i] >> 16) & 255];
              }
            simd::WindowMeanRow row{};
            for (int k = 0; k < 7; ++k) {
              const int r = y - 3 + k;
              const bool inside = r >= 0 && r < kRows;
              row.red[k] = inside ? red.data() + size_t(r) * plane : zero_red.data();
              row.green[k] = inside ? green.data() + size_t(r) * plane : zero.data();
              row.blue[k] = inside ? blue.data() + size_t(r) * plane : zero.data();
            }
            std::vector<float> got(3 * size_t(w)), want;
            for (float& c : got) c = float(rng() % 1000) - 2000.0f;
            want = got;
            std::vector<uint8_t> found_flags(size_t(w), 7);
            row.width = w, row.take = scratch.reaching.data(), row.first = first, row.end = end, row.rgb = got.data();
            row.masks = scratch.reach7.data(), row.found = found_flags.data();
            kernels().window_mean(row);
            const EpiRows rows{edge_y.data(), types.data(), color.data(), w, kRows};
            for (int x = std::max(first, 3); x < end; ++x)
              if (scratch.reaching[size_t(x)]) {
                ASSERT_LE(found_flags[size_t(x)], 1) << "pixel " << x << ": found not written";
                (found_flags[size_t(x)] ? found : last_resort) += 1;
              }
            fallback_reaching_row(rows, y, got.data(), true, scratch, found_flags.data());
            fallback_reaching_row(rows, y, want.data(), true, scratch);
            for (int x = 0; x < w; ++x)
              ASSERT_TRUE(same_bits(&got[3 * size_t(x)], &want[3 * size_t(x)], 3))
                  << "pixel " << x << ", row " << y << ": " << got[3 * size_t(x)] << " against " << want[3 * size_t(x)];
          }
        }
  EXPECT_GT(found, 5000);
  EXPECT_GT(last_resort, 1000);
}

// The fallback's 7x7 reachability against reach_window7: random types (empty, complex and every
// simple type in random shares), images of 1 to 9 rows (the windows leave the image on every side),
// random pixels taken. The relation rows are computed as the reconstruction does, only over the
// columns the taken pixels' windows cover; the planes' other bytes hold garbage (0x0f: every
// region reaches every other), so a read beyond a taken pixel's window fails. Outside the image
// that garbage is never reached: the relations into it are computed, and blocked.
TEST_P(RowKernels, Reach7EqualsTheOracle) {
  std::mt19937_64 rng(77);
  constexpr int kPadBefore = 3;
  int64_t partial = 0, whole = 0, none = 0;
  for (int w : kWidths)
    for (int h : {1, 2, 4, 7, 9})
      for (double complex_share : {0.0, 0.05, 0.3, 1.0})
        for (double simple_share : {0.0, 0.3, 1.0}) {
          SCOPED_TRACE("width " + std::to_string(w) + ", height " + std::to_string(h) + ", complex " +
                       std::to_string(complex_share) + ", simple " + std::to_string(simple_share));
          std::bernoulli_distribution is_complex(complex_share), is_simple(simple_share), taken(0.3);
          std::vector<uint8_t> types(size_t(w * h));
          for (uint8_t& t : types)
            t = uint8_t(is_complex(rng) ? kTypeComplex : is_simple(rng) ? 2 + int(rng() % 12) : kTypeEmpty);
          const size_t padded = size_t(w) + 2 * simd::kPad + 64;
          std::vector<uint8_t> padded_types(padded * size_t(h), uint8_t(kTypeComplex)), outside(padded, uint8_t(kTypeComplex));
          for (int y = 0; y < h; ++y)
            std::memcpy(&padded_types[size_t(y) * padded + simd::kPad], &types[size_t(y * w)], size_t(w));
          auto type_row = [&](int r) { return r >= 0 && r < h ? &padded_types[size_t(r) * padded] : outside.data(); };
          const size_t plane = size_t(w) + kPadBefore + 69;
          const TypeRows oracle_types{types.data(), w, h};
          for (int y = 0; y < h; ++y) {
            const int first = int(rng() % size_t(w)), end = first + 1 + int(rng() % size_t(w - first));
            std::vector<uint8_t> take(size_t(w) + 64, 1);  // stray marks outside [first, end)
            for (int x = first; x < end; ++x) take[size_t(x)] = taken(rng);
            take[size_t(first)] = 1;
            std::vector<uint8_t> relations(28 * plane, 0x0f);
            const int x0 = std::max(0, first - 3), x1 = std::min(w, end + 3);
            simd::Reach7Row row{{}, plane, take.data(), first, end, nullptr};
            for (int k = 0; k < 7; ++k) {
              const int r = y - 3 + k;
              uint8_t* out = &relations[4 * size_t(k) * plane + kPadBefore];
              kernels().relations({x1 - x0, (k > 0 ? type_row(r - 1) : outside.data()) + x0, type_row(r) + x0,
                                   &relation_tables(), out + x0, plane});
              row.relations[k] = out;
            }
            constexpr uint64_t kUntouched = 0xdeadbeefdeadbeefull;
            std::vector<uint64_t> masks(size_t(w), kUntouched);
            row.masks = masks.data();
            kernels().reach7(row);
            for (int x = 0; x < w; ++x) {
              if (x < first || x >= end || !take[size_t(x)]) {
                ASSERT_EQ(masks[size_t(x)], kUntouched) << "pixel " << x << ", row " << y << " not taken but written";
                continue;
              }
              const uint64_t want = reach_window7(oracle_types, x, y);
              ASSERT_EQ(masks[size_t(x)], want) << "pixel " << x << ", row " << y;
              (want == kWindow7All ? whole : want == uint64_t(1) << 24 ? none : partial) += 1;
            }
          }
        }
  EXPECT_GT(partial, 5000);
  EXPECT_GT(whole, 100);
  EXPECT_GT(none, 1000);
}

std::string target_name(const testing::TestParamInfo<int64_t>& info) { return hwy::TargetName(info.param); }
INSTANTIATE_TEST_SUITE_P(EveryTarget, RowKernels, testing::ValuesIn(simd::compiled_targets()), target_name);

}  // namespace
}  // namespace epi

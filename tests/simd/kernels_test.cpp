// The Highway row kernels of every compiled target (AVX3, AVX2, SSE4, SSSE3, scalar: those
// this CPU runs) against the per-pixel oracle, bit for bit: image, priority, classified
// planes and counts, through the tiled and the staged schedules, over random patterns and
// the extremes (empty, one-pixel, one-row and one-column images, widths around the vector
// size, every pixel complex, edges along pixel borders, no and full sampling).
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

#include <hwy/targets.h>

#include "epi/reconstruct.h"
#include "simd/row_kernels.h"
#include "test_util.h"

namespace epi {
namespace {

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  // memcmp of an empty vector's data() (null) is undefined, even for 0 bytes.
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

class Kernels : public testing::TestWithParam<int64_t> {
 protected:
  // Tiled (several band sizes and thread counts) and staged with this target's kernels,
  // each equal to the oracle bit for bit.
  void expect_equal(const test::Built& b, const ReconstructSettings& s, const std::string& what) {
    SCOPED_TRACE(what);
    const EpiImage input = b.epi;
    const Reconstruction oracle = reconstruct_oracle(b.epi, b.masks, s);
    Reconstructor fast({false, GetParam()});
    ASSERT_EQ(std::string(fast.kernel_name()), hwy::TargetName(GetParam()));
    Reconstruction r;
    auto expect_same = [&](const char* schedule) {
      SCOPED_TRACE(schedule);
      ASSERT_TRUE(same_bits(oracle.image.pixels, r.image.pixels));
      ASSERT_TRUE(same_bits(oracle.priority, r.priority));
      ASSERT_EQ(oracle.edge, r.edge);
      ASSERT_EQ(oracle.cache, r.cache);
      ASSERT_EQ(oracle.counts.simple, r.counts.simple);
      ASSERT_EQ(oracle.counts.complex, r.counts.complex);
      ASSERT_EQ(oracle.counts.ambiguous, r.counts.ambiguous);
    };
    for (const Schedule& schedule : {Schedule{1, 1}, Schedule{5, 2}, Schedule{64, 2}}) {
      fast.tiled(b.epi, b.masks, s, schedule, r);
      expect_same("tiled");
    }
    ReconstructTimes times;
    fast.staged(b.epi, b.masks, s, r, times, {8, 2});
    expect_same("staged");
    fast.tiled(b.epi, b.masks, s, {7, 1, false}, r);
    expect_same("tiled, reachability without symmetry");
    fast.tiled(b.epi, b.masks, s, {6, 1, false, false}, r);
    expect_same("tiled, reachability without symmetry and relation rows recomputed");
    fast.staged(b.epi, b.masks, s, r, times, {8, 1, true, false});
    expect_same("staged, relation rows recomputed");
    ASSERT_EQ(input.edge, b.epi.edge);  // the input is never written
    ASSERT_EQ(input.color, b.epi.color);
  }

  void expect_equal_all_settings(const test::Built& b, const std::string& what) {
    for (const ReconstructSettings& s :
         {ReconstructSettings{}, ReconstructSettings{Filter::epi, false, false, false},
          ReconstructSettings{Filter::epi, true, false, true}, ReconstructSettings{Filter::rendercache, false, false}})
      expect_equal(b, s, what + (s.filter == Filter::rendercache ? " rendercache" : s.fill ? " epi" : " epi, interpolation only"));
  }
};

// Random patterns and ages, widths 1-70 (not multiples of the vector), densities 0-100 %.
TEST_P(Kernels, RandomPatternsEqualTheOracle) {
  std::mt19937_64 rng(77);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  for (int trial = 0; trial < 25; ++trial) {
    const int w = pick(1, 70), h = pick(1, 40);
    const uint64_t seed = rng();
    test::Built b = test::build(test::random_pattern(w, h, pick(1, 30), seed), pick(0, 100) / 100.0, seed, pick(0, 3) != 0);
    for (size_t i = 0; i < b.epi.color.size(); ++i)
      b.epi.color[i] = (b.epi.color[i] & 0xffffffu) | uint32_t(rng() % 256) << bits::kAgeShift;
    expect_equal_all_settings(b, "trial " + std::to_string(trial) + " " + std::to_string(w) + "x" + std::to_string(h));
  }
}

// Widths around every vector width: 4-16 float lanes, 16-64 byte lanes (reachability).
TEST_P(Kernels, ExtremeSizes) {
  for (auto [w, h] : {std::pair{0, 0}, {0, 5}, {5, 0}, {1, 1}, {1, 17}, {17, 1}, {2, 3}, {15, 4}, {16, 4}, {17, 4},
                      {31, 3}, {33, 3}, {63, 3}, {64, 2}, {65, 2}, {127, 3}, {128, 2}, {129, 3}})
    for (double d : {0.0, 0.5, 1.0}) {
      const test::Built b = test::build(test::random_pattern(std::max(w, 1), std::max(h, 1), 6, uint64_t(w * 100 + h)), d, 3);
      if (w == 0 || h == 0) {
        test::Built empty{b.pattern, BoundaryMasks(w, h, true), EpiImage(w, h)};
        expect_equal_all_settings(empty, "empty " + std::to_string(w) + "x" + std::to_string(h));
        continue;
      }
      expect_equal_all_settings(b, std::to_string(w) + "x" + std::to_string(h) + " density " + std::to_string(d));
    }
}

// A fine checker of 0.4-pixel squares: nearly every pixel complex.
TEST_P(Kernels, EveryPixelComplex) {
  const Pattern p = test::fine_checker(23, 9);
  for (double d : {0.3, 1.0}) {
    const test::Built b = test::build(p, d, 5);
    const Reconstruction r = reconstruct_oracle(b.epi, b.masks, {});
    ASSERT_GT(r.counts.complex, 23 * 9 * 8 / 10);
    expect_equal_all_settings(b, "complex, density " + std::to_string(d));
  }
}

// Edges exactly on pixel borders (axis-aligned squares on integer corners) and through corners.
TEST_P(Kernels, EdgesAlongPixelBorders) {
  Pattern p;
  p.width = 21, p.height = 13;
  p.background = {0.2f, 0.2f, 0.2f};
  p.polygons.push_back({{1, 1, 0}, {{3, 2}, {9, 2}, {9, 8}, {3, 8}}});
  p.polygons.push_back({{0, 1, 1}, {{12, 0}, {20, 8}, {12, 8}}});
  p.polygons.push_back({{1, 0, 1}, {{0, 10}, {21, 10}, {21, 11}, {0, 11}}});
  for (double d : {0.1, 0.6, 1.0}) expect_equal_all_settings(test::build(p, d, 6), "borders, density " + std::to_string(d));
}

// Sharp wedges (thin triangles 3-12 pixels long): their tips lie inside pixels whose two
// crossings alone would make them simple; the centre lines make many of them complex
// (docs/epi.md, "Corners"), in the kernel as in the oracle.
TEST_P(Kernels, CornersInsidePixelsEqualTheOracle) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Pattern p;
  p.width = 67, p.height = 29;
  p.background = {0.1f, 0.1f, 0.1f};
  for (int i = 0; i < 40; ++i) {
    const double tx = 2 + u(rng) * 63, ty = 2 + u(rng) * 25, a = 6.283185307179586 * u(rng), len = 3 + 9 * u(rng);
    const double spread = 0.3 + 0.6 * u(rng);  // the tip's angle, radians
    p.polygons.push_back({{float(u(rng)), float(u(rng)), 17.0f * float(u(rng))},
                          {{tx, ty},
                           {tx + len * std::cos(a - spread / 2), ty + len * std::sin(a - spread / 2)},
                           {tx + len * std::cos(a + spread / 2), ty + len * std::sin(a + spread / 2)}}});
  }
  for (double d : {0.2, 0.7}) {
    const test::Built b = test::build(p, d, 8);
    int corners = 0;
    for (int y = 0; y < p.height; ++y)
      for (int x = 0; x < p.width; ++x)
        corners += test::kind_of(b.masks, x, y) == CellKind::simple && classify_pixel(b.masks, x, y, 0).kind == CellKind::complex;
    ASSERT_GT(corners, 10);
    expect_equal_all_settings(b, "corners, density " + std::to_string(d));
  }
}

std::string target_name(const testing::TestParamInfo<int64_t>& info) { return hwy::TargetName(info.param); }
INSTANTIATE_TEST_SUITE_P(EveryTarget, Kernels, testing::ValuesIn(simd::compiled_targets()), target_name);

// The tests above must really cover the vector widths: on x86-64 at least SSE4 and the
// scalar fallback are compiled and run everywhere.
TEST(KernelTargets, VectorAndScalarTargetsAreCompiled) {
  const std::vector<int64_t> targets = simd::compiled_targets();
  std::string names;
  for (int64_t t : targets) names += std::string(hwy::TargetName(t)) + " ";
  std::printf("compiled and supported targets: %s\n", names.c_str());
#if HWY_ARCH_X86
  bool sse4 = false, fallback = false;
  for (int64_t t : targets) sse4 = sse4 || t == HWY_SSE4, fallback = fallback || t == HWY_SCALAR || t == HWY_EMU128;
  EXPECT_TRUE(sse4) << names;
  EXPECT_TRUE(fallback) << names;
#endif
  EXPECT_THROW(simd::row_kernels(HWY_AVX3_DL), std::invalid_argument);       // not compiled
  EXPECT_THROW(simd::row_kernels(HWY_SSE4 | HWY_AVX2), std::invalid_argument);  // not one target
  EXPECT_EQ(simd::row_kernels(0).target, targets.front());
}

}  // namespace
}  // namespace epi

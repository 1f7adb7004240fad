// The trace (core/epi/trace.h) against the reconstruction: at every pixel of several patterns,
// densities and settings, the traced final colour, priority, reach mask, type and edge code are
// the ones reconstruct_oracle (and reconstruct_tiled) produce, bit for bit; and the recorded
// reachability steps recompose into the reach mask.
#include <bit>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "epi/interpolate.h"
#include "epi/reachability.h"
#include "epi/tables.h"
#include "epi/trace.h"
#include "test_util.h"

namespace epi {
namespace {

bool same(const float* a, const Rgb& b) { return std::memcmp(a, b.data(), 3 * sizeof(float)) == 0; }

void check_every_pixel(const test::Built& built, const ReconstructSettings& settings, const std::string& what) {
  EpiImage oracle_epi = built.epi, tiled_epi = built.epi;
  const Reconstruction oracle = reconstruct_oracle(oracle_epi, built.masks, settings);
  const Reconstruction tiled = reconstruct_tiled(tiled_epi, built.masks, settings, Schedule{7, 2});
  ReconstructSettings rc = settings;
  rc.filter = Filter::rendercache;
  EpiImage rc_epi = built.epi;
  const Reconstruction rendercache = reconstruct_oracle(rc_epi, built.masks, rc);
  const Tracer tracer(built.epi, built.masks, settings);
  int classes[3] = {}, complex_filtered = 0, antialiased = 0;
  for (int y = 0; y < built.epi.height; ++y)
    for (int x = 0; x < built.epi.width; ++x) {
      const PixelTrace t = tracer.trace(x, y);
      const size_t i = oracle_epi.index(x, y);
      SCOPED_TRACE(what + " pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")");
      ASSERT_TRUE(same(oracle.image.at(x, y), t.result));
      ASSERT_TRUE(same(tiled.image.at(x, y), t.result));
      ASSERT_EQ(std::bit_cast<uint32_t>(oracle.priority[i]), std::bit_cast<uint32_t>(t.priority));
      // Classification and reachability against the untraced functions (classify_pixel on the
      // input word, reach_full on the tracer's classified EPI).
      const PixelClass c = classify_pixel(built.masks, x, y, built.epi.edge[i]);
      ASSERT_EQ(reach_full(tracer.classified(), x, y), t.reach);
      ASSERT_EQ(int(c.type), t.type);
      ASSERT_EQ(edge_code(c.edge), t.code);
      ASSERT_EQ(usable_sample(c.edge), t.usable);
      ASSERT_TRUE(same(rendercache.image.at(x, y), t.rendercache));
      // The recorded steps recompose into the mask: 24 steps, or none on the all-empty fast path.
      if (t.reach_fast_path) {
        ASSERT_EQ(t.reach, 0xffffffu);
      } else {
        ASSERT_EQ(t.reach_steps.size(), 24u);
        uint32_t mask = 0;
        for (const ReachStep& s : t.reach_steps) {
          uint8_t combined = 0;
          for (int k = 0; k < s.preds; ++k) combined |= s.path[k];
          ASSERT_EQ(combined, s.mask);
          if (s.mask & kReachPP) mask |= 1u << reach_bit(s.dx, s.dy);
        }
        ASSERT_EQ(mask, t.reach);
      }
      // Interpolation's listed samples add up to the weight the priority is made of.
      if (!t.fallback && !t.usable && !t.complex_estimate) {
        ASSERT_EQ(std::bit_cast<uint32_t>(weight_priority(t.total_weight)), std::bit_cast<uint32_t>(t.priority));
      }
      ++classes[int(t.kind)];
      complex_filtered += t.output == PixelTrace::Output::complex_filter;
      antialiased += t.output == PixelTrace::Output::antialiased;
    }
  // The patterns exercise every branch the trace records.
  EXPECT_GT(classes[0], 0) << what;
  EXPECT_GT(classes[1], 0) << what;
  EXPECT_GT(classes[2], 0) << what;
  if (settings.complex_filter) {
    EXPECT_GT(complex_filtered, 0) << what;
  }
  if (settings.antialias) {
    EXPECT_GT(antialiased, 0) << what;
  }
}

TEST(Trace, FinalValuesEqualTheReconstructionAtEveryPixel) {
  for (const char* name : {"wedges.json", "slivers.json", "checker.json", "discs.json"}) {
    const Pattern pattern = load_pattern(test::pattern_path(name));
    for (double density : {0.1, 0.6}) {
      const test::Built built = test::build(pattern, density, 7);
      check_every_pixel(built, {}, std::string(name) + " density " + std::to_string(density));
    }
  }
}

TEST(Trace, FollowsTheSettingsAndRandomPatterns) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const test::Built built = test::build(test::random_pattern(40, 32, 6, seed), 0.15, seed);
    ReconstructSettings s;
    s.fill = seed != 2;
    s.antialias = seed != 3;
    check_every_pixel(built, s, "random " + std::to_string(seed));
  }
  const test::Built built = test::build(load_pattern(test::pattern_path("checker.json")), 0.3, 2);
  ReconstructSettings no_complex;
  no_complex.complex_filter = false;
  check_every_pixel(built, no_complex, "checker without the complex filter");
}

TEST(Trace, FallbackAndFillAreRecorded) {
  // At 3 % density many pixels reach no sample: the fallback runs and fill replaces its colour.
  const test::Built built = test::build(load_pattern(test::pattern_path("checker.json")), 0.03, 11);
  const Tracer tracer(built.epi, built.masks, {});
  int fallback = 0, filled = 0;
  for (int y = 0; y < built.epi.height; ++y)
    for (int x = 0; x < built.epi.width; ++x) {
      const PixelTrace t = tracer.trace(x, y);
      if (!t.fallback) continue;
      ++fallback;
      EXPECT_EQ(t.priority, kMaxPriority);
      EXPECT_TRUE(t.fill_ran);
      if (!t.fill_contributions.empty()) ++filled;
    }
  EXPECT_GT(fallback, 0);
  EXPECT_GT(filled, 0);
}

TEST(Trace, RejectsPixelsOutsideAndTheRenderCacheFilter) {
  const test::Built built = test::build(load_pattern(test::pattern_path("wedges.json")), 0.2, 1);
  const Tracer tracer(built.epi, built.masks, {});
  EXPECT_THROW(tracer.trace(-1, 0), std::out_of_range);
  EXPECT_THROW(tracer.trace(0, built.epi.height), std::out_of_range);
  ReconstructSettings rc;
  rc.filter = Filter::rendercache;
  EXPECT_THROW(Tracer(built.epi, built.masks, rc), std::invalid_argument);
}

}  // namespace
}  // namespace epi

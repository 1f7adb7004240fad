// Reachability properties, and the tiled parallel reconstructor against the oracle, bit for bit.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <cstring>
#include <random>

#include "epi/interpolate.h"
#include "epi/reachability.h"
#include "epi/reconstruct.h"
#include "epi/rows.h"
#include "epi/tables.h"
#include "test_util.h"

namespace epi {
namespace {

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(Reachability, EmptyImageReachesTheWholeNeighbourhood) {
  EpiImage epi(9, 9);
  BoundaryMasks masks(9, 9, false);
  classify_rows(epi, masks, 0, 9);
  EXPECT_EQ(reach_full(epi, 4, 4), 0xffffffu);
  // Corner pixel: only the offsets inside the image.
  const uint32_t corner = reach_full(epi, 0, 0);
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx)
      if (dx || dy) {
        EXPECT_EQ((corner >> reach_bit(dx, dy)) & 1, uint32_t(dx >= 0 && dy >= 0)) << dx << "," << dy;
      }
}

TEST(Reachability, ComplexPixelsBlockPropagation) {
  EpiImage epi(9, 9);
  BoundaryMasks masks(9, 9, false);
  // Make pixel (5,4) complex: three crossings on its top side.
  masks.top[masks.index(5, 4)] = 0b10101;
  classify_rows(epi, masks, 0, 9);
  ASSERT_EQ(pixel_type(epi.cache[epi.index(5, 4)]), kTypeComplex);
  const uint32_t m = reach_full(epi, 4, 4);
  EXPECT_FALSE((m >> reach_bit(1, 0)) & 1);
  EXPECT_FALSE((m >> reach_bit(2, 0)) & 1);  // only reachable through (5,4)
  EXPECT_TRUE((m >> reach_bit(2, 1)) & 1);   // around it
  EXPECT_TRUE((m >> reach_bit(1, 1)) & 1);
}

TEST(Reachability, AStraightEdgeSeparatesItsSides) {
  for (double x_edge : {4.3, 4.5, 4.9}) {
    EpiImage epi(9, 9);
    BoundaryMasks masks(9, 9, false);
    const Segment s{x_edge - 0.2, -5.0, x_edge + 0.2, 15.0};
    rasterize_edges(masks, std::span<const Segment>(&s, 1));
    classify_rows(epi, masks, 0, 9);
    for (int y = 2; y < 7; ++y)
      for (int x = 0; x < 9; ++x) {
        const uint32_t m = reach_full(epi, x, y);
        for (int dx = -2; dx <= 2; ++dx)
          for (int dy = -2; dy <= 2; ++dy) {
            if (!(dx || dy) || x + dx < 0 || x + dx > 8) continue;
            // Empty pixels on opposite sides never reach each other.
            if (x == 4 || x + dx == 4) continue;
            EXPECT_EQ((m >> reach_bit(dx, dy)) & 1, uint32_t((x < 4) == (x + dx < 4))) << x << "," << y;
          }
      }
  }
}

TEST(Reachability, IsSymmetricOnRandomPatterns) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::Built b = test::build(test::random_pattern(40, 30, 12, seed), 0.5, seed);
    classify_rows(b.epi, b.masks, 0, 30);
    std::vector<uint32_t> masks(40 * 30);
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x) masks[size_t(y * 40 + x)] = reach_full(b.epi, x, y);
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            if (!(dx || dy) || !b.epi.inside(x + dx, y + dy)) continue;
            ASSERT_EQ((masks[size_t(y * 40 + x)] >> reach_bit(dx, dy)) & 1,
                      (masks[size_t((y + dy) * 40 + x + dx)] >> reach_bit(-dx, -dy)) & 1);
          }
  }
}

// Reachability by brute force: every monotone staircase path from the centre to each offset
// of the (2R+1)^2 window, each composed step by step as explicit relations over {P, S}, the
// paths OR-ed. Bit (dy + R) * (2R + 1) + (dx + R), the centre left out.
uint64_t brute_reach_window(const EpiImage& epi, int x, int y, int radius) {
  const EpiTables& t = epi_tables();
  auto type = [&](int px, int py) {
    return epi.inside(px, py) ? pixel_type(epi.cache[epi.index(px, py)]) : kTypeComplex;
  };
  auto step = [&](int ax, int ay, int bx, int by) {  // relation a -> b as bool[2][2]
    const int dir = bx > ax ? kRight : by > ay ? kDown : bx < ax ? kLeft : kUp;
    const int m = t.neighbour[dir][(type(ax, ay) << 4) | type(bx, by)];
    std::array<std::array<bool, 2>, 2> r{};
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) r[i][j] = (m >> (2 * i + j)) & 1;
    return r;
  };
  uint64_t result = 0;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      if (!(dx || dy)) continue;
      const int nx = std::abs(dx), ny = std::abs(dy), sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
      bool reach_pp = false;
      // A path: a sequence of nx + ny steps, a bit per step (1 = along x).
      for (int moves = 0; moves < (1 << (nx + ny)); ++moves) {
        if (std::popcount(unsigned(moves)) != nx) continue;
        std::array<bool, 2> from_p{true, false};  // regions of the current pixel reachable from P
        int cx = x, cy = y;
        for (int k = 0; k < nx + ny; ++k) {
          const int px = cx + ((moves >> k) & 1 ? sx : 0), py = cy + ((moves >> k) & 1 ? 0 : sy);
          const auto r = step(cx, cy, px, py);
          from_p = {(from_p[0] && r[0][0]) || (from_p[1] && r[1][0]), (from_p[0] && r[0][1]) || (from_p[1] && r[1][1])};
          cx = px, cy = py;
        }
        reach_pp = reach_pp || from_p[0];
      }
      if (reach_pp) result |= uint64_t(1) << ((dy + radius) * (2 * radius + 1) + dx + radius);
    }
  return result;
}

uint32_t brute_reach(const EpiImage& epi, int x, int y) {
  const uint64_t window = brute_reach_window(epi, x, y, 2);
  uint32_t result = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx)
      if ((dx || dy) && ((window >> ((dy + 2) * 5 + dx + 2)) & 1)) result |= 1u << reach_bit(dx, dy);
  return result;
}

std::vector<uint8_t> types_of(const EpiImage& epi) {
  std::vector<uint8_t> types(epi.cache.size());
  for (size_t i = 0; i < types.size(); ++i) types[i] = uint8_t(pixel_type(epi.cache[i]));
  return types;
}

// The 7x7 fallback's reachability: brute force over all monotone paths up to 3 away, and its
// inner 5x5 equal to the filter's own mask.
TEST(Reachability, Window7MatchesBruteForcePathEnumeration) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::Built b = test::build(test::random_pattern(30, 22, 16, seed), 0.5, seed);
    classify_rows(b.epi, b.masks, 0, 22);
    const std::vector<uint8_t> types = types_of(b.epi);
    const TypeRows plane{types.data(), 30, 22};
    for (int y = 0; y < 22; ++y)
      for (int x = 0; x < 30; ++x) {
        const uint64_t got = reach_window7(plane, x, y);
        ASSERT_EQ(got, brute_reach_window(b.epi, x, y, 3) | (uint64_t(1) << window7_bit(0, 0))) << x << "," << y;
        const uint32_t full = reach_full(b.epi, x, y);
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx)
            if (dx || dy) {
              ASSERT_EQ((got >> window7_bit(dx, dy)) & 1, (full >> reach_bit(dx, dy)) & 1);
            }
      }
  }
  // The fast path: an empty image reaches the whole window, minus what lies outside it.
  EpiImage epi(9, 9);
  BoundaryMasks masks(9, 9, false);
  classify_rows(epi, masks, 0, 9);
  const std::vector<uint8_t> types = types_of(epi);
  EXPECT_EQ(reach_window7({types.data(), 9, 9}, 4, 4), kWindow7All);
  EXPECT_EQ(reach_window7({types.data(), 9, 9}, 0, 4), brute_reach_window(epi, 0, 4, 3) | (uint64_t(1) << 24));
}

// The interpolation's fallback around one lone sample in an edge-free image: the sample's colour
// out to 3 pixels in each direction (the 7x7 reach, corners included), black beyond (inside the
// hole), with the sample anywhere, image borders included.
TEST(Fallback, OneSampleColoursItsSevenBySevenAndTheHoleBeyondIsBlack) {
  const int w = 11, h = 9;
  const float rgb[3] = {0.25f, 0.5f, 0.75f};
  for (const auto& [sx, sy] : {std::pair{5, 4}, std::pair{0, 0}, std::pair{10, 8}, std::pair{3, 0}}) {
    EpiImage epi(w, h);
    epi.set_sample(sx, sy, 0.5, 0.5, rgb);
    BoundaryMasks masks(w, h, false);
    classify_rows(epi, masks, 0, h);
    const std::vector<uint8_t> types = types_of(epi);
    const EpiRows rows = whole_image_rows(epi, types.data());
    float expected[3];
    decode_color(epi.color[epi.index(sx, sy)], expected);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float got[3] = {-1, -1, -1};
        fallback_color(rows, x, y, got);
        const bool near = std::abs(x - sx) <= 3 && std::abs(y - sy) <= 3;
        for (int c = 0; c < 3; ++c)
          ASSERT_FLOAT_EQ(got[c], near ? expected[c] : 0.0f) << "sample " << sx << "," << sy << " pixel " << x << "," << y;
      }
  }
}

// fallback_color without its hole shortcut (the oracle of the shortcut): the reachable samples
// of the 7x7, then at an edge the 5x5's and the 7x7's samples, else black.
void straightforward_fallback(const EpiRows& rows, int x, int y, float rgb[3]) {
  const uint64_t reach = reach_window7(rows.type_rows(), x, y);
  const auto& lut = epi_color8_to_linear();
  float sum[3] = {0, 0, 0}, total = 0;
  for (int dy = std::max(-3, -y); dy <= std::min(3, rows.height - 1 - y); ++dy)
    for (int dx = std::max(-3, -x); dx <= std::min(3, rows.width - 1 - x); ++dx) {
      if (!((reach >> window7_bit(dx, dy)) & 1) || !usable_sample(rows.edge_at(x + dx, y + dy))) continue;
      const float d = float(1 + dx * dx + dy * dy), w = 1.0f / (d * d);
      const uint32_t c = rows.color_at(x + dx, y + dy);
      sum[0] += w * lut[c & 255], sum[1] += w * lut[(c >> 8) & 255], sum[2] += w * lut[(c >> 16) & 255];
      total += w;
    }
  if (total > 0) {
    for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / total;
    return;
  }
  int any = 0;
  for (int py = std::max(0, y - 2); py <= std::min(rows.height - 1, y + 2); ++py)
    for (int px = std::max(0, x - 2); px <= std::min(rows.width - 1, x + 2); ++px) any |= rows.type_at(px, py);
  if (any != kTypeEmpty) {
    if (simple_estimate(rows, x, y, rgb) > 0) return;
    if (window_average(rows, x, y, 3, rgb) > 0) return;
  }
  rgb[0] = rgb[1] = rgb[2] = 0.0f;
}

TEST(Fallback, EqualsTheStraightforwardLoopOnRandomPatterns) {
  size_t coloured = 0, black = 0;
  for (const double density : {0.02, 0.08, 0.3, 0.9})
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      const int w = 37, h = 23;
      test::Built b = test::build(test::random_pattern(w, h, 14, seed), density, seed);
      classify_rows(b.epi, b.masks, 0, h);
      const std::vector<uint8_t> types = types_of(b.epi);
      const EpiRows rows = whole_image_rows(b.epi, types.data());
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          float got[3], want[3];
          fallback_color(rows, x, y, got);
          straightforward_fallback(rows, x, y, want);
          ASSERT_EQ(0, std::memcmp(got, want, sizeof got)) << "density " << density << " seed " << seed << " pixel " << x << "," << y;
          (want[0] + want[1] + want[2] > 0 ? coloured : black) += 1;
        }
    }
  EXPECT_GT(coloured, size_t(1000));
  EXPECT_GT(black, size_t(50));  // the sparse patterns hold holes
}

// The schedules' row fallback against the per-pixel one: every pixel of every row, where any
// pixel may be unreached (found 0), on patterns from holes to dense, sizes down to 1 pixel, both
// blend settings; it must take each path (holes, edge-free windows, the general case). The same
// with the general case deferred (the vector schedules' 7x7 reachability kernel).
TEST(Fallback, RowEqualsThePixelFallbackOnRandomPatterns) {
  size_t holes = 0, edge_free = 0, general = 0;
  FallbackScratch scratch;
  std::mt19937 random(7);
  for (const auto& [w, h] : {std::pair{37, 23}, std::pair{64, 9}, std::pair{1, 12}, std::pair{13, 1}, std::pair{6, 6}})
    for (const double density : {0.01, 0.03, 0.08, 0.3, 0.9})
      for (uint64_t seed = 1; seed <= 3; ++seed) {
        test::Built b = test::build(test::random_pattern(w, h, 10, seed), density, seed);
        classify_rows(b.epi, b.masks, 0, h);
        const std::vector<uint8_t> types = types_of(b.epi);
        const EpiRows rows = whole_image_rows(b.epi, types.data());
        for (const bool blend : {true, false})
          for (int y = 0; y < h; ++y) {
            std::vector<uint8_t> found(static_cast<size_t>(w));
            for (uint8_t& f : found) f = random() % 4 == 0;  // mostly unreached
            std::vector<float> got(3 * size_t(w), -1.0f), want(3 * size_t(w), -1.0f);
            fallback_row(rows, y, found.data(), got.data(), blend, scratch);
            // Deferred as the vector schedules do: the pixels needing the 7x7 reachability are
            // marked, their masks (here the oracle's) finished by fallback_reaching_row.
            std::vector<float> deferred(3 * size_t(w), -1.0f);
            fallback_row(rows, y, found.data(), deferred.data(), blend, scratch, false, true);
            scratch.reach7.assign(size_t(w), 0);
            int marked = 0;
            for (int x = scratch.span_first; x < scratch.span_end; ++x)
              if (scratch.reaching[size_t(x)]) scratch.reach7[size_t(x)] = reach_window7(rows.type_rows(), x, y), ++marked;
            ASSERT_EQ(marked, scratch.reaching_count);
            fallback_reaching_row(rows, y, deferred.data(), blend, scratch);
            ASSERT_EQ(0, std::memcmp(got.data(), deferred.data(), got.size() * sizeof(float)))
                << w << "x" << h << " density " << density << " seed " << seed << " row " << y << " deferred";
            for (int x = 0; x < w; ++x)
              if (!found[size_t(x)]) {
                fallback_color(rows, x, y, &want[3 * size_t(x)], blend);
                const bool inside = x >= 3 && y >= 3 && x + 3 < w && y + 3 < h;
                int any_type = 0, any_sample = 0;
                for (int py = std::max(0, y - 3); py <= std::min(h - 1, y + 3); ++py)
                  for (int px = std::max(0, x - 3); px <= std::min(w - 1, x + 3); ++px)
                    any_type |= rows.type_at(px, py), any_sample |= has_sample(rows.edge_at(px, py));
                (!any_sample ? holes : inside && any_type == kTypeEmpty ? edge_free : general) += 1;
              }
            ASSERT_EQ(0, std::memcmp(got.data(), want.data(), got.size() * sizeof(float)))
                << w << "x" << h << " density " << density << " seed " << seed << " row " << y << " blend " << blend;
          }
      }
  EXPECT_GT(holes, size_t(100));
  EXPECT_GT(edge_free, size_t(100));
  EXPECT_GT(general, size_t(100));
}

// A disocclusion beside a straight edge: samples below a horizontal edge, none above. With the
// blend near edges (the default) the edge-free pixels just above the edge take the colour from
// across it (the floor colour the renderer showed above a floor's far border, docs/render.md
// "Holes"); without it they stay black at top priority (holes), while the pixels the edge
// crosses still blend. The oracle and the tiled schedule agree in both settings.
TEST(Fallback, WithoutTheBlendNearEdgesEdgeFreePixelsBesideAnEdgeStayBlack) {
  const int w = 24, h = 16;
  EpiImage epi(w, h);
  BoundaryMasks masks(w, h, true);
  const Segment edge{-5.0, 8.3, 30.0, 8.6};
  rasterize_edges(masks, std::span<const Segment>(&edge, 1));
  const float rgb[3] = {0.6f, 0.5f, 0.4f};
  for (int y = 9; y < h; ++y)
    for (int x = 0; x < w; ++x) epi.set_sample(x, y, 0.5, 0.5, rgb);
  for (const bool blend : {true, false}) {
    ReconstructSettings settings;
    settings.blend_unreached_near_edges = blend;
    const Reconstruction oracle = reconstruct_oracle(epi, masks, settings);
    const Reconstruction tiled = reconstruct_tiled(epi, masks, settings);
    ASSERT_TRUE(same_bits(oracle.image.pixels, tiled.image.pixels)) << "blend " << blend;
    ASSERT_TRUE(same_bits(oracle.priority, tiled.priority)) << "blend " << blend;
    size_t coloured_above = 0, coloured_on_edge = 0;
    for (int x = 0; x < w; ++x) {
      for (int y = 6; y <= 7; ++y)  // edge-free, the edge in their 5x5, nothing reachable
        coloured_above += oracle.image.pixels[3 * (size_t(y) * w + size_t(x))] > 0.0f;
      coloured_on_edge += oracle.image.pixels[3 * (size_t(8) * w + size_t(x))] > 0.0f;
      for (int y = 0; y <= 7; ++y) EXPECT_EQ(oracle.priority[size_t(y) * w + size_t(x)], kMaxPriority);
    }
    if (blend) EXPECT_EQ(coloured_above, size_t(2 * w));
    else EXPECT_EQ(coloured_above, size_t(0));
    EXPECT_EQ(coloured_on_edge, size_t(w)) << "blend " << blend;
  }
}

TEST(Reachability, MatchesBruteForcePathEnumeration) {
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    test::Built b = test::build(test::random_pattern(32, 24, 20, seed), 0.5, seed);
    classify_rows(b.epi, b.masks, 0, 24);
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 32; ++x) ASSERT_EQ(reach_full(b.epi, x, y), brute_reach(b.epi, x, y)) << x << "," << y;
  }
}

struct Case {
  ReconstructSettings settings;
  double density;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (double d : {0.0, 0.1, 0.5, 1.0}) {
    out.push_back({{Filter::epi, true, true}, d});
    out.push_back({{Filter::epi, false, true}, d});
    out.push_back({{Filter::epi, true, false}, d});
    out.push_back({{Filter::epi, true, true, false}, d});  // fill off
    out.push_back({{Filter::rendercache, false, false}, d});
  }
  return out;
}

void expect_tiled_equals_oracle(const Pattern& pattern, const Case& c, uint64_t seed, std::vector<Schedule> schedules) {
  test::Built b = test::build(pattern, c.density, seed);
  const Reconstruction oracle = reconstruct_oracle(b.epi, b.masks, c.settings);
  for (const Schedule& s : schedules) {
    const Reconstruction tiled = reconstruct_tiled(b.epi, b.masks, c.settings, s);
    ASSERT_TRUE(same_bits(oracle.image.pixels, tiled.image.pixels))
        << pattern.width << "x" << pattern.height << " rows " << s.rows_per_band << " threads " << s.threads;
    ASSERT_TRUE(same_bits(oracle.priority, tiled.priority));
    ASSERT_EQ(oracle.edge, tiled.edge);
    ASSERT_EQ(oracle.cache, tiled.cache);
    ASSERT_EQ(oracle.counts.simple, tiled.counts.simple);
    ASSERT_EQ(oracle.counts.complex, tiled.counts.complex);
  }
}

// Random patterns, sizes, settings, band sizes and thread counts: planes, image, priority and
// every count equal, bit for bit.
TEST(Tiled, PropertyRandomPatternsBandsAndThreads) {
  std::mt19937_64 rng(2024);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  for (int trial = 0; trial < 60; ++trial) {
    const int w = pick(1, 70), h = pick(1, 70);
    const uint64_t seed = rng();
    const Pattern pattern = test::random_pattern(w, h, pick(1, 30), seed);
    const bool rendercache = pick(0, 4) == 0;
    const ReconstructSettings settings{rendercache ? Filter::rendercache : Filter::epi, pick(0, 1) == 1,
                                       pick(0, 1) == 1, pick(0, 1) == 1};
    test::Built b = test::build(pattern, pick(0, 100) / 100.0, seed, pick(0, 3) != 0);
    const EpiImage input = b.epi;
    const Reconstruction oracle = reconstruct_oracle(b.epi, b.masks, settings);
    for (int k = 0; k < 3; ++k) {
      const Schedule schedule{pick(0, 3) == 0 ? pick(1, 1000) : pick(1, 12), pick(1, 3)};
      const Reconstruction tiled = reconstruct_tiled(b.epi, b.masks, settings, schedule);
      SCOPED_TRACE(testing::Message() << "trial " << trial << " " << w << "x" << h << " rows " << schedule.rows_per_band
                                      << " threads " << schedule.threads);
      ASSERT_TRUE(same_bits(oracle.image.pixels, tiled.image.pixels));
      ASSERT_TRUE(same_bits(oracle.priority, tiled.priority));
      ASSERT_EQ(oracle.edge, tiled.edge);
      ASSERT_EQ(oracle.cache, tiled.cache);
      // The input is never written.
      ASSERT_EQ(input.edge, b.epi.edge);
      ASSERT_EQ(input.cache, b.epi.cache);
      ASSERT_EQ(input.color, b.epi.color);
      ASSERT_EQ(oracle.counts.empty, tiled.counts.empty);
      ASSERT_EQ(oracle.counts.simple, tiled.counts.simple);
      ASSERT_EQ(oracle.counts.complex, tiled.counts.complex);
      ASSERT_EQ(oracle.counts.samples, tiled.counts.samples);
      ASSERT_EQ(oracle.counts.ambiguous, tiled.counts.ambiguous);
    }
  }
}

TEST(Tiled, BitIdenticalToTheOracleForAnyBandAndThreadCount) {
  std::vector<Schedule> schedules;
  for (int rows : {1, 2, 3, 5, 16, 1000})
    for (int threads : {1, 2}) schedules.push_back({rows, threads});
  uint64_t seed = 1;
  for (const Case& c : cases())
    expect_tiled_equals_oracle(test::random_pattern(37, 29, 25, seed), c, seed, schedules), ++seed;
  for (const char* name : {"checker.json", "discs.json"})
    expect_tiled_equals_oracle(load_pattern(test::pattern_path(name)), {{Filter::epi, true, true}, 0.3}, 5,
                               {{1, 2}, {7, 2}, {32, 1}});
}

TEST(Tiled, TinyAndThinImages) {
  for (auto [w, h] : {std::pair{1, 1}, {1, 9}, {9, 1}, {2, 2}, {3, 2}}) {
    Pattern p = test::random_pattern(w, h, 4, uint64_t(w * 10 + h));
    for (const Case& c : cases()) expect_tiled_equals_oracle(p, c, 3, {{1, 1}, {1, 2}, {2, 2}, {64, 2}});
  }
}

TEST(Tiled, FourKImage) {
  Pattern p = test::random_pattern(3840, 2160, 60, 99);
  expect_tiled_equals_oracle(p, {{Filter::epi, true, true}, 0.1}, 4, {{32, 2}, {100, 2}});
}

TEST(Tiled, ReusedOutputBuffersGiveTheSameResult) {
  Reconstruction reused;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::Built b = test::build(test::random_pattern(30 + int(seed), 20, 10, seed), 0.4, seed);
    reconstruct_tiled(b.epi, b.masks, {}, {4, 2}, reused);
    const Reconstruction fresh = reconstruct_oracle(b.epi, b.masks, {});
    ASSERT_TRUE(same_bits(reused.image.pixels, fresh.image.pixels));
    ASSERT_TRUE(same_bits(reused.priority, fresh.priority));
    ASSERT_EQ(reused.counts.simple, fresh.counts.simple);
  }
}

// Extremes in one pattern: a 300-vertex star around one pixel corner, a sliver shorter than 1/8 pixel,
// near-horizontal and near-vertical edges, a polygon far outside the image.
TEST(Reconstruct, ExtremePatternsStayFiniteAndMatchTheOracle) {
  Pattern p;
  p.width = 24, p.height = 16;
  p.background = {0.1f, 0.2f, 0.3f};
  Polygon star{{1, 1, 0}, {}};
  for (int k = 0; k < 300; ++k) {
    const double r = k % 2 ? 0.45 : 0.1, a = 6.283185307179586 * k / 300;
    star.points.push_back({5.02 + r * std::cos(a), 5.03 + r * std::sin(a)});
  }
  p.polygons.push_back(star);
  p.polygons.push_back({{0, 1, 1}, {{12.3, 3.3}, {12.35, 3.31}, {12.32, 3.36}}});
  p.polygons.push_back({{1, 0, 1}, {{-1, 10.2}, {25, 10.21}, {25, 12.7}, {-1, 12.69}}});
  p.polygons.push_back({{0, 0, 1}, {{18.4, -1}, {18.41, 17}, {20.9, 17}, {20.89, -1}}});
  p.polygons.push_back({{1, 1, 1}, {{1e6, 1e6}, {1e6 + 5, 1e6}, {1e6, 1e6 + 5}}});
  for (double d : {0.0, 0.3, 1.0}) {
    expect_tiled_equals_oracle(p, {{Filter::epi, true, true}, d}, 9, {{1, 2}, {5, 1}});
    test::Built b = test::build(p, d, 9);
    const Reconstruction r = reconstruct_tiled(b.epi, b.masks, {});
    for (float v : r.image.pixels) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
    EXPECT_EQ(test::kind_of(b.masks, 4, 4), CellKind::complex);  // the star spans four pixels
    if (d == 1.0) {  // the long near-axis edges reconstruct close to exact coverage
      const RgbImage exact = exact_image(p);
      std::vector<uint8_t> rows(size_t(24 * 16), 0);
      for (int x = 0; x < 16; ++x) rows[size_t(10 * 24 + x)] = rows[size_t(12 * 24 + x)] = 1;
      EXPECT_LT(test::mean_error(r.image, exact, rows), 0.05);
    }
  }
}

TEST(Reconstruct, PriorityFollowsAgeAndSampleDensity) {
  EpiImage epi(15, 15);
  BoundaryMasks masks(15, 15, false);
  const float grey[3] = {0.5f, 0.5f, 0.5f};
  for (int y = 0; y < 15; ++y)
    for (int x = 0; x < 6; ++x)
      if ((x + y) % 2 == 0) epi.set_sample(x, y, 0.5, 0.5, grey, 32);  // dense on the left
  epi.set_sample(11, 7, 0.5, 0.5, grey, 80);                             // one sample on the right
  const Reconstruction r = reconstruct_oracle(epi, masks, {});
  auto priority = [&](int x, int y) { return r.priority[size_t(y * 15 + x)]; };
  EXPECT_FLOAT_EQ(priority(2, 2), age_priority(32));
  EXPECT_FLOAT_EQ(priority(11, 7), age_priority(80));
  EXPECT_LT(priority(3, 2), priority(12, 7));             // denser neighbourhood, lower priority
  EXPECT_FLOAT_EQ(priority(12, 7), 1.0f / kInterpolationWeights[11]);  // only the left neighbour
  EXPECT_EQ(priority(13, 0), kMaxPriority);                // nothing within reach
}

// A pixel that reaches only a far sample (weight 1/81) still ranks strictly below one that
// reaches nothing.
TEST(Reconstruct, NothingReachableIsStrictlyTheHighestPriority) {
  EpiImage epi(15, 15);
  BoundaryMasks masks(15, 15, false);
  const float grey[3] = {0.5f, 0.5f, 0.5f};
  epi.set_sample(2, 2, 0.5, 0.5, grey, 3);
  const Reconstruction r = reconstruct_oracle(epi, masks, {});
  const float far = r.priority[size_t(4 * 15 + 4)], none = r.priority[size_t(5 * 15 + 5)];
  EXPECT_EQ(none, kMaxPriority);
  EXPECT_LT(far, none);
  EXPECT_EQ(far, kMaxReachedPriority);
  EXPECT_LT(age_priority(255), kMaxPriority);
}

// Priority by brute force on random patterns with random ages: a usable own sample gives age
// priority; otherwise (no sample, or an edge-ambiguous one, which interpolation ignores) the
// weight priority of the reachable usable samples, and kMaxPriority exactly when there are
// none (complex pixels: any sample of the 5x5).
TEST(Reconstruct, PriorityMatchesBruteForceIncludingAmbiguousSamples) {
  int ambiguous_checked = 0, unreached = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed)
    for (double density : {0.05, 0.3, 0.8}) {
      test::Built b = test::build(test::random_pattern(40, 30, 14, seed), density, seed);
      for (size_t i = 0; i < b.epi.color.size(); ++i)
        b.epi.color[i] = (b.epi.color[i] & 0xffffffu) | uint32_t((i * 37 + seed) % 256) << bits::kAgeShift;
      const Reconstruction r = reconstruct_tiled(b.epi, b.masks, {}, {7, 2});
      ASSERT_TRUE(same_bits(r.priority, reconstruct_oracle(b.epi, b.masks, {}).priority));
      for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
          const size_t i = b.epi.index(x, y);
          const bool complex = pixel_type(r.cache[i]) == kTypeComplex;
          const uint32_t reach = reach_mask(r.cache[i]);
          double total = 0;
          for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
              if (!b.epi.inside(x + dx, y + dy)) continue;
              const uint16_t e = r.edge[b.epi.index(x + dx, y + dy)];
              const bool reached = (!dx && !dy) || ((reach >> reach_bit(dx, dy)) & 1);
              if (complex ? has_sample(e) : reached && usable_sample(e)) total += kInterpolationWeights[(dy + 2) * 5 + dx + 2];
            }
          const uint16_t own = r.edge[i];
          const float p = r.priority[i];
          if (total == 0) {
            ASSERT_EQ(p, kMaxPriority) << x << "," << y;
            ++unreached;
          } else if (usable_sample(own)) {
            ASSERT_EQ(p, age_priority(sample_age(b.epi.color[i])));
          } else {
            ASSERT_LT(p, kMaxPriority);
            ASSERT_NEAR(p, std::min(1.0 / total, double(kMaxReachedPriority)), 1e-4 * p) << x << "," << y;
            ambiguous_checked += has_sample(own);
          }
        }
    }
  EXPECT_GT(ambiguous_checked, 10);
  EXPECT_GT(unreached, 10);
}

TEST(Reconstruct, AntiAliasingBlendsInLinearLight) {
  // White right of x = 10.5, black left: the edge pixels are half covered, 0.5 in linear light.
  Pattern p = parse_pattern(R"({"width":20,"height":10,"background":[0,0,0],"polygons":[
      {"color":[1,1,1],"points":[[10.5,-1],[21,-1],[21,11],[10.5,11]]}]})", "half.json");
  test::Built b = test::build(p, 1.0, 4);
  const Reconstruction r = reconstruct_tiled(b.epi, b.masks, {});
  for (int y = 0; y < 10; ++y) {
    EXPECT_NEAR(r.image.at(10, y)[0], 0.5f, 1.0f / 16) << y;
    EXPECT_NEAR(r.image.at(9, y)[0], 0.0f, 1e-6) << y;
    EXPECT_NEAR(r.image.at(11, y)[0], 1.0f, 1e-6) << y;
  }
}

TEST(Reconstruct, NoSamplesGiveBlackAtTopPriority) {
  test::Built b = test::build(test::random_pattern(20, 20, 5, 3), 0.0, 1);
  const Reconstruction r = reconstruct_tiled(b.epi, b.masks, {});
  for (float v : r.image.pixels) EXPECT_EQ(v, 0.0f);
  for (float p : r.priority) EXPECT_EQ(p, kMaxPriority);
}

TEST(Reconstruct, UniformColourIsReproducedEverywhere) {
  Pattern p;
  p.width = 17, p.height = 11;
  p.background = {0.25f, 0.5f, 0.75f};
  for (double d : {1.0, 0.2}) {
    test::Built b = test::build(p, d, 8);
    const Reconstruction r = reconstruct_oracle(b.epi, b.masks, {});
    size_t sampled = 0;  // every sample holds the background, 8-bit sRGB encoded
    while (!has_sample(b.epi.edge[sampled])) ++sampled;
    float expected[3];
    decode_color(b.epi.color[sampled], expected);
    for (size_t i = 0; i < r.image.pixels.size(); ++i) {
      EXPECT_NEAR(r.image.pixels[i], p.background[i % 3], 4e-3);  // the quantization of 8-bit sRGB
      EXPECT_NEAR(r.image.pixels[i], expected[i % 3], 1e-6);      // and nothing else
    }
  }
}

// Lights seen directly are far brighter than 1 (the Cornell box's lamp: 17, 12, 4). The EPI's
// colour codes above 1 are ratios, so a bright sample keeps its hue: clamped at 1 per channel it
// showed white where the reference's tone map shows it warm (issue 9, docs/epi.md "Colour").
TEST(Reconstruct, BrightColoursKeepTheirHue) {
  Pattern p;
  p.width = 13, p.height = 9;
  p.background = {17.0f, 12.0f, 4.0f};
  for (double d : {1.0, 0.3}) {
    test::Built b = test::build(p, d, 3);
    const Reconstruction r = reconstruct_tiled(b.epi, b.masks, {});
    const Reconstruction oracle = reconstruct_oracle(b.epi, b.masks, {});
    for (size_t i = 0; i < r.image.pixels.size(); ++i) {
      EXPECT_NEAR(r.image.pixels[i] / p.background[i % 3], 1.0f, 0.07f) << i;
      EXPECT_EQ(r.image.pixels[i], oracle.image.pixels[i]) << i;
    }
  }
}

float linear_to_srgb_display(float v) {
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

// The code table: sRGB steps over [0, 1] (at most half a step off), ratio steps above 1 up to
// kEpiColourMax (at most half a ratio step off), monotone, and every code its own encoding.
TEST(EpiColour, FineStepsUpToOneAndRatioStepsAbove) {
  const auto& table = epi_color8_to_linear();
  for (int c = 0; c < 256; ++c) {
    EXPECT_EQ(encode_epi_color8(table[size_t(c)]), c) << c;
    if (c > 0) {
      EXPECT_LT(table[size_t(c - 1)], table[size_t(c)]) << c;
    }
  }
  EXPECT_EQ(table[0], 0.0f);
  EXPECT_FLOAT_EQ(table[kEpiUnitCode], 1.0f);
  EXPECT_NEAR(table[255], kEpiColourMax, 1e-3f * kEpiColourMax);
  const float srgb_half_step = 0.5f / float(kEpiUnitCode) + 1e-6f;
  for (int k = 0; k <= 10000; ++k) {
    const float v = float(k) / 10000.0f;
    EXPECT_NEAR(linear_to_srgb_display(table[encode_epi_color8(v)]), linear_to_srgb_display(v), srgb_half_step) << v;
  }
  const float ratio_half_step = std::pow(kEpiColourMax, 0.5f / float(255 - kEpiUnitCode));
  for (float v = 1.0f; v <= kEpiColourMax; v *= 1.01f) {
    const float back = table[encode_epi_color8(v)];
    EXPECT_LE(std::max(back / v, v / back), ratio_half_step * 1.0001f) << v;
  }
  EXPECT_EQ(encode_epi_color8(1e9f), 255);
  EXPECT_EQ(encode_epi_color8(-1.0f), 0);
  EXPECT_EQ(encode_epi_color8(std::numeric_limits<float>::quiet_NaN()), 0);
}

TEST(Reconstruct, MismatchedSizesAreRejected) {
  EpiImage epi(4, 4);
  BoundaryMasks masks(5, 4, false);
  EXPECT_THROW(reconstruct_oracle(epi, masks, {}), std::invalid_argument);
  EXPECT_THROW(reconstruct_tiled(epi, masks, {}), std::invalid_argument);
}

}  // namespace
}  // namespace epi

namespace epi {
namespace {

// The schedule's numbers follow from the stage table (docs/epi.md, "Stages and schedules"):
// a stage's lag is the largest producer lag plus radius over its inputs; rings hold every row
// a reader still needs.
TEST(Stages, LagsRingsAndReportedSeriesFollowTheTable) {
  EXPECT_EQ(stage_lag(Stage::classify), 0);
  EXPECT_EQ(stage_lag(Stage::decode), 0);
  EXPECT_EQ(stage_lag(Stage::reachability), 2);
  EXPECT_EQ(stage_lag(Stage::interpolate), 3);
  EXPECT_EQ(stage_lag(Stage::fill), 5);
  EXPECT_EQ(stage_lag(Stage::antialias), 6);
  EXPECT_EQ(stage_lag(Stage::complex), 6);
  EXPECT_EQ(kMaxLag, 6);
  EXPECT_EQ(kClassRingRows, 8);  // rows y-7 (the complex filter's top) .. y
  EXPECT_EQ(ring_rows(Plane::reach), 4);
  EXPECT_EQ(ring_rows(Plane::interp), 8);
  EXPECT_EQ(ring_rows(Plane::filled), 4);
  for (const StageInfo& s : kStages) {
    EXPECT_EQ(&stage_info(s.stage), &s);
    for (int i = 0; i < s.input_count; ++i) {  // every input is produced by an earlier stage (or this one: the image)
      const Stage p = producer(s.inputs[size_t(i)].plane);
      EXPECT_LE(int(p), int(s.stage)) << s.name;
    }
  }
  ReconstructTimes t;
  for (int k = 0; k < kStageCount; ++k) t.ms[size_t(k)] = double(1 << k);
  EXPECT_EQ(t.reported(Stage::classify), 1 + 2);       // classify + decode
  EXPECT_EQ(t.reported(Stage::interpolate), 8 + 16);   // interpolate + fill
  EXPECT_EQ(t.reported(Stage::complex), 64);
  EXPECT_FALSE(is_reported(Stage::fill));
}

}  // namespace
}  // namespace epi

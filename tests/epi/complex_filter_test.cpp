// The complex-pixel filter (complex_filter.cpp) against a plain reference written from its
// description: geom::classify_cell and geom::cell_edge per sub-pixel, regions joined by relaxing
// labels over the probe pairs, the same float sums in the same order. Bit for bit, on every
// pixel (complex or not) of random patterns, dense checkers and patterns with edges along pixel
// borders. Then the row kernel complex_row against complex_pixel, bit for bit, on the same kinds
// of patterns and the extreme sizes.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "epi/complex_filter.h"
#include "test_util.h"

namespace epi {
namespace {

struct RefSub {
  CellKind kind = CellKind::complex;
  geom::CellEdge edge{};
};

void reference_complex_pixel(const EpiRows& epi, const BoundaryMasks& m, int x, int y, const float estimate[3],
                             float out[3]) {
  constexpr int kGrid = 6;
  RefSub sub[kGrid][kGrid];
  auto half = [](uint8_t mask, int h) { return uint8_t((mask >> (4 * h)) & 15); };
  for (int v = 0; v < kGrid; ++v)
    for (int u = 0; u < kGrid; ++u) {
      const int px = x - 1 + u / 2, py = y - 1 + v / 2, sx = u & 1, sy = v & 1;
      if (!epi.inside(px, py)) continue;
      const uint8_t sides[4] = {
          half(sy == 0 ? m.top[m.index(px, py)] : m.centre_h[m.index(px, py)], sx),
          half(sx == 0 ? m.centre_v[m.index(px, py)] : m.left[m.index(px + 1, py)], sy),
          half(sy == 0 ? m.centre_h[m.index(px, py)] : m.top[m.index(px, py + 1)], sx),
          half(sx == 0 ? m.left[m.index(px, py)] : m.centre_v[m.index(px, py)], sy)};
      const geom::CellClass c = geom::classify_cell(sides, 4);
      sub[v][u].kind = c.kind;
      if (c.kind == CellKind::simple) sub[v][u].edge = geom::cell_edge(c.p_low, c.p_high, 4);
    }
  auto region = [&](int u, int v, geom::Vec2 p) {
    return sub[v][u].kind == CellKind::simple ? geom::region_of(sub[v][u].edge, p) : 0;
  };
  // Labels of the nodes (v * 6 + u) * 2 + region, relaxed to the smallest over every joined pair.
  std::vector<std::pair<int, int>> joins;
  auto node = [](int u, int v, int r) { return (v * kGrid + u) * 2 + r; };
  for (int v = 0; v < kGrid; ++v)
    for (int u = 0; u < kGrid; ++u)
      for (int dir = 0; dir < 2; ++dir) {
        const int bu = u + (dir == 0), bv = v + (dir == 1);
        if (bu >= kGrid || bv >= kGrid || sub[v][u].kind == CellKind::complex || sub[bv][bu].kind == CellKind::complex)
          continue;
        for (double t : {1.0 / 16.0, 15.0 / 16.0}) {
          const geom::Vec2 pa = dir == 0 ? geom::Vec2{1, t} : geom::Vec2{t, 1};
          const geom::Vec2 pb = dir == 0 ? geom::Vec2{0, t} : geom::Vec2{t, 0};
          joins.push_back({node(u, v, region(u, v, pa)), node(bu, bv, region(bu, bv, pb))});
        }
      }
  int label[kGrid * kGrid * 2];
  for (int i = 0; i < kGrid * kGrid * 2; ++i) label[i] = i;
  for (bool changed = true; changed;) {
    changed = false;
    for (auto [a, b] : joins)
      if (label[a] != label[b]) label[a] = label[b] = std::min(label[a], label[b]), changed = true;
  }
  struct Sample {
    int label, u, v;
    float rgb[3];
  };
  std::vector<Sample> samples;
  for (int qy = y - 1; qy <= y + 1; ++qy)
    for (int qx = x - 1; qx <= x + 1; ++qx) {
      if (!epi.inside(qx, qy) || !has_sample(epi.edge_at(qx, qy))) continue;
      const int r = sample_region(epi.edge_at(qx, qy)), rx = r & 3, ry = r >> 2;
      const int u = 2 * (qx - x + 1) + (rx >> 1), v = 2 * (qy - y + 1) + (ry >> 1);
      const RefSub& s = sub[v][u];
      if (s.kind == CellKind::complex) continue;
      const int side = s.kind == CellKind::simple ? geom::square_side(s.edge, (rx & 1) * 0.5, (ry & 1) * 0.5, 0.5) : 0;
      if (side == 2) continue;
      Sample p{label[node(u, v, side)], u, v, {}};
      decode_color(epi.color_at(qx, qy), p.rgb);
      samples.push_back(p);
    }
  auto region_color = [&](int u, int v, int r, float rgb[3]) {
    float sum[3] = {0, 0, 0}, total = 0;
    for (const Sample& s : samples) {
      if (s.label != label[node(u, v, r)]) continue;
      const float d2 = float((s.u - u) * (s.u - u) + (s.v - v) * (s.v - v));
      const float w = 1.0f / ((1.0f + d2) * (1.0f + d2));
      for (int c = 0; c < 3; ++c) sum[c] += w * s.rgb[c];
      total += w;
    }
    for (int c = 0; c < 3; ++c) rgb[c] = total > 0 ? sum[c] / total : estimate[c];
  };
  out[0] = out[1] = out[2] = 0;
  for (int v = 2; v <= 3; ++v)
    for (int u = 2; u <= 3; ++u) {
      float rgb[3] = {estimate[0], estimate[1], estimate[2]};
      if (sub[v][u].kind == CellKind::empty) region_color(u, v, 0, rgb);
      if (sub[v][u].kind == CellKind::simple) {
        float a_rgb[3], b_rgb[3];
        region_color(u, v, 0, a_rgb), region_color(u, v, 1, b_rgb);
        const float a = float(geom::area_a(sub[v][u].edge));
        for (int c = 0; c < 3; ++c) rgb[c] = a * a_rgb[c] + (1.0f - a) * b_rgb[c];
      }
      for (int c = 0; c < 3; ++c) out[c] += 0.25f * rgb[c];
    }
}

// Every pixel of the built EPI through both, with random estimates; returns the complex count.
int expect_equal_everywhere(const test::Built& b, uint64_t seed, const std::string& what) {
  SCOPED_TRACE(what);
  const Reconstruction r = reconstruct_oracle(b.epi, b.masks, {});
  std::vector<uint8_t> types(r.cache.size());
  for (size_t i = 0; i < types.size(); ++i) types[i] = uint8_t(pixel_type(r.cache[i]));
  const EpiRows rows{r.edge.data(), types.data(), b.epi.color.data(), b.epi.width, b.epi.height};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int complex = 0, mismatches = 0;
  for (int y = 0; y < b.epi.height; ++y)
    for (int x = 0; x < b.epi.width; ++x) {
      const float estimate[3] = {unit(rng), unit(rng), unit(rng)};
      float fast[3], ref[3];
      complex_pixel(rows, b.masks, x, y, estimate, fast);
      reference_complex_pixel(rows, b.masks, x, y, estimate, ref);
      complex += types[b.epi.index(x, y)] == kTypeComplex;
      if (std::memcmp(fast, ref, sizeof fast) != 0 && ++mismatches <= 5)
        ADD_FAILURE() << "pixel " << x << "," << y << ": " << fast[0] << " " << fast[1] << " " << fast[2] << " vs "
                      << ref[0] << " " << ref[1] << " " << ref[2];
    }
  EXPECT_EQ(mismatches, 0);
  return complex;
}

TEST(ComplexFilter, EqualsThePlainReferenceOnRandomPatterns) {
  std::mt19937_64 rng(2024);
  int complex = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const int w = 8 + int(rng() % 40), h = 8 + int(rng() % 30);
    const uint64_t seed = rng();
    const double density = double(rng() % 101) / 100.0;
    complex += expect_equal_everywhere(test::build(test::random_pattern(w, h, 5 + int(rng() % 60), seed), density, seed),
                                       seed, "trial " + std::to_string(trial));
  }
  EXPECT_GT(complex, 300);  // the patterns really exercise the filter
}

// A fine checker of 0.4-pixel squares (nearly every pixel complex, many sub-pixels complex),
// and axis-aligned edges on pixel borders and centre lines.
TEST(ComplexFilter, EqualsThePlainReferenceOnCheckersAndBorders) {
  const Pattern p = test::fine_checker(19, 11);
  for (double d : {0.3, 1.0}) EXPECT_GT(expect_equal_everywhere(test::build(p, d, 5), 9, "checker"), 19 * 11 / 2);
  Pattern q;
  q.width = 21, q.height = 13;
  q.background = {0.2f, 0.2f, 0.2f};
  q.polygons.push_back({{1, 1, 0}, {{3, 2}, {9, 2}, {9, 8}, {3, 8}}});
  q.polygons.push_back({{0, 1, 1}, {{12.5, 0}, {20, 7.5}, {12.5, 7.5}}});
  q.polygons.push_back({{1, 0, 1}, {{0, 10}, {21, 10.5}, {21, 11}, {0, 11}}});
  for (double d : {0.2, 1.0}) expect_equal_everywhere(test::build(q, d, 6), 10, "borders");
}

// The row kernel's sub-pixel classes (no 65,536-entry table) equal geom::classify_cell's.
TEST(ComplexRow, SubPixelClassEqualsClassifyCellEverywhere) {
  int mismatches = 0;
  for (uint32_t i = 0; i < 65536; ++i) {
    const uint8_t sides[4] = {uint8_t(i & 15), uint8_t((i >> 4) & 15), uint8_t((i >> 8) & 15), uint8_t(i >> 12)};
    const geom::CellClass c = geom::classify_cell(sides, 4);
    if (sub_cell_class(i) != uint16_t(int(c.kind) | c.p_low << 2 | c.p_high << 6) && ++mismatches <= 5)
      ADD_FAILURE() << "sides index " << i;
  }
  EXPECT_EQ(mismatches, 0);
}

// complex_row against complex_pixel, bit for bit: once over the real types (only complex pixels
// written, the others untouched), once with every pixel marked complex (every window position,
// image borders included); random estimates. Returns the complex count.
int expect_row_equal(const test::Built& b, uint64_t seed, const std::string& what, ComplexRowCache& cache,
                     int64_t target) {
  SCOPED_TRACE(what + ", target " + std::to_string(target));
  const Reconstruction r = reconstruct_oracle(b.epi, b.masks, {});
  const int w = b.epi.width, h = b.epi.height;
  std::vector<uint8_t> types(r.cache.size());
  for (size_t i = 0; i < types.size(); ++i) types[i] = uint8_t(pixel_type(r.cache[i]));
  const EpiRows rows{r.edge.data(), types.data(), b.epi.color.data(), w, h};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> estimate(3 * size_t(w));
  const std::vector<uint8_t> all_complex(static_cast<size_t>(w), uint8_t{kTypeComplex});
  cache.reset();  // another image; then kept over the rows (in order, as in the stages)
  int complex = 0, mismatches = 0;
  for (int y = 0; y < h; ++y)
    for (bool every : {false, true}) {
      for (float& e : estimate) e = unit(rng);
      const uint8_t* row_types = every ? all_complex.data() : &types[size_t(y) * size_t(w)];
      std::vector<float> fast(3 * size_t(w), -1.0f), ref = fast;
      complex_row(rows, b.masks, y, row_types, estimate.data(), fast.data(), cache, target);
      for (int x = 0; x < w; ++x)
        if (row_types[x] == kTypeComplex) complex_pixel(rows, b.masks, x, y, &estimate[3 * size_t(x)], &ref[3 * size_t(x)]);
      for (int x = 0; x < w; ++x) {
        complex += !every && row_types[x] == kTypeComplex;
        if (std::memcmp(&fast[3 * size_t(x)], &ref[3 * size_t(x)], 3 * sizeof(float)) != 0 && ++mismatches <= 5)
          ADD_FAILURE() << "pixel " << x << "," << y << (every ? " (all marked complex)" : "") << ": " << fast[3 * x]
                        << " " << fast[3 * x + 1] << " " << fast[3 * x + 2] << " vs " << ref[3 * x] << " "
                        << ref[3 * x + 1] << " " << ref[3 * x + 2];
      }
    }
  EXPECT_EQ(mismatches, 0);
  return complex;
}

// Every compiled target this CPU runs (complex_row is compiled once per Highway target; the
// lane-parallel window of AVX2 and AVX3 is other code than the SSE and scalar targets' one).
TEST(ComplexRow, EqualsComplexPixelOnRandomPatterns) {
  ASSERT_FALSE(complex_row_targets().empty());
  for (int64_t target : complex_row_targets()) {
    std::mt19937_64 rng(77);
    ComplexRowCache cache;  // one for all: reset() between images (sizes vary) must be enough
    int complex = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const int w = 1 + int(rng() % 70), h = 1 + int(rng() % 30);
      const uint64_t seed = rng();
      const double density = double(rng() % 101) / 100.0;
      complex += expect_row_equal(test::build(test::random_pattern(w, h, 3 + int(rng() % 60), seed), density, seed), seed,
                                  "trial " + std::to_string(trial) + ", " + std::to_string(w) + "x" + std::to_string(h),
                                  cache, target);
    }
    EXPECT_GT(complex, 300);
  }
}

TEST(ComplexRow, EqualsComplexPixelOnExtremes) {
  for (int64_t target : complex_row_targets()) {
    // Nearly every pixel complex, also cut to one row, one column and one pixel.
    ComplexRowCache cache;
    for (auto [w, h] : {std::pair{19, 11}, {33, 1}, {1, 17}, {1, 1}, {2, 2}, {64, 3}, {65, 2}})
      for (double d : {0.0, 0.3, 1.0}) {
        const int complex = expect_row_equal(test::build(test::fine_checker(w, h), d, 5), 9,
                                             "checker " + std::to_string(w) + "x" + std::to_string(h), cache, target);
        if (w * h > 100) {
          EXPECT_GT(complex, w * h / 2);
        }
      }
    Pattern q;  // edges along pixel borders and centre lines
    q.width = 21, q.height = 13;
    q.background = {0.2f, 0.2f, 0.2f};
    q.polygons.push_back({{1, 1, 0}, {{3, 2}, {9, 2}, {9, 8}, {3, 8}}});
    q.polygons.push_back({{0, 1, 1}, {{12.5, 0}, {20, 7.5}, {12.5, 7.5}}});
    q.polygons.push_back({{1, 0, 1}, {{0, 10}, {21, 10.5}, {21, 11}, {0, 11}}});
    for (double d : {0.2, 1.0}) expect_row_equal(test::build(q, d, 6), 10, "borders", cache, target);
  }
}

// A target that is not compiled or not supported is refused, never run.
TEST(ComplexRow, RefusesUnknownTargets) {
  const test::Built b = test::build(test::fine_checker(4, 4), 0.5, 1);
  ComplexRowCache cache;
  std::vector<float> estimate(12, 0.5f), out(12);
  const std::vector<uint8_t> types(16, uint8_t{kTypeComplex});
  const std::vector<uint16_t> edge(16, 0);
  const EpiRows rows{edge.data(), types.data(), b.epi.color.data(), 4, 4};
  EXPECT_THROW(complex_row(rows, b.masks, 1, types.data(), estimate.data(), out.data(), cache, int64_t{3}),
               std::invalid_argument);
}

}  // namespace
}  // namespace epi

// What the reconstruction must show, measured against the exact (supersampled) image.
#include <gtest/gtest.h>

#include <cstdio>

#include "epi/interpolate.h"
#include "epi/reconstruct.h"
#include "test_util.h"

namespace epi {
namespace {

const char* kPatterns[] = {"wedges.json", "slivers.json", "checker.json", "discs.json"};

// The samples themselves: plain one-sample point sampling (black where none).
RgbImage point_sampled(const EpiImage& epi) {
  RgbImage image(epi.width, epi.height);
  for (int y = 0; y < epi.height; ++y)
    for (int x = 0; x < epi.width; ++x)
      if (has_sample(epi.edge[epi.index(x, y)])) decode_color(epi.color[epi.index(x, y)], image.at(x, y));
  return image;
}

// Pixels within `radius` of an edge pixel.
std::vector<uint8_t> dilate(const std::vector<uint8_t>& mask, int w, int h, int radius) {
  std::vector<uint8_t> out(mask.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int dy = -radius; dy <= radius && !out[size_t(y * w + x)]; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
          const int px = x + dx, py = y + dy;
          if (px >= 0 && py >= 0 && px < w && py < h && mask[size_t(py * w + px)]) {
            out[size_t(y * w + x)] = 1;
            break;
          }
        }
  return out;
}

TEST(Quality, AntiAliasingFromEdgesAloneHalvesPointSamplingError) {
  for (const char* name : kPatterns) {
    test::Built b = test::build(load_pattern(test::pattern_path(name)), 1.0, 3);
    const RgbImage exact = exact_image(b.pattern);
    const std::vector<uint8_t> edges = edge_pixels(b.pattern);
    const double point_error = test::mean_error(point_sampled(b.epi), exact, edges);
    const Reconstruction r = reconstruct_tiled(b.epi, b.masks, {});
    const double epi_error = test::mean_error(r.image, exact, edges);
    std::printf("%-14s edge pixels: point sampling %.4f, EPI anti-aliased %.4f (ratio %.2f)\n", name, point_error,
                epi_error, epi_error / point_error);
    EXPECT_LT(epi_error, 0.5 * point_error) << name;
  }
}

TEST(Quality, SparseEdgeRespectingInterpolationBeatsTheRenderCacheAtEdges) {
  for (const char* name : kPatterns) {
    double epi_error = 0, rc_error = 0;
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      test::Built b = test::build(load_pattern(test::pattern_path(name)), 0.1, seed);
      const RgbImage exact = exact_image(b.pattern);
      const std::vector<uint8_t> near_edges = dilate(edge_pixels(b.pattern), b.epi.width, b.epi.height, 1);
      EpiImage copy = b.epi;
      epi_error += test::mean_error(reconstruct_tiled(b.epi, b.masks, {}).image, exact, near_edges);
      rc_error += test::mean_error(reconstruct_tiled(copy, b.masks, {Filter::rendercache, false, false}).image,
                                   exact, near_edges);
    }
    std::printf("%-14s 10%% sampled, near edges: render cache %.4f, EPI %.4f (ratio %.2f)\n", name, rc_error / 3,
                epi_error / 3, epi_error / rc_error);
    EXPECT_LT(epi_error, 0.8 * rc_error) << name;
  }
}

TEST(Quality, ComplexFilterLowersTheErrorOnComplexPixels) {
  double with_total = 0, without_total = 0;
  for (const char* name : kPatterns) {
    test::Built b = test::build(load_pattern(test::pattern_path(name)), 1.0, 2);
    const RgbImage exact = exact_image(b.pattern);
    EpiImage copy = b.epi;
    const Reconstruction with = reconstruct_tiled(b.epi, b.masks, {Filter::epi, true, true});
    const Reconstruction without = reconstruct_tiled(copy, b.masks, {Filter::epi, true, false});
    std::vector<uint8_t> complex(size_t(b.epi.width) * size_t(b.epi.height));
    for (size_t i = 0; i < complex.size(); ++i) complex[i] = pixel_type(b.epi.cache[i]) == kTypeComplex;
    const double e_with = test::mean_error(with.image, exact, complex);
    const double e_without = test::mean_error(without.image, exact, complex);
    std::printf("%-14s %lld complex pixels: simple estimate %.4f, complex filter %.4f\n", name,
                (long long)with.counts.complex, e_without, e_with);
    if (with.counts.complex > 20) {
      EXPECT_LT(e_with, e_without) << name;
    }
    with_total += e_with, without_total += e_without;
  }
  EXPECT_LT(with_total, 0.85 * without_total);
}

// A pixel whose whole neighbourhood lies inside one polygon, away from its corners, takes its
// colour only from samples of that polygon, whatever is sampled around it.
TEST(Quality, NoColourCrossesAClosedEdge) {
  const Pattern p = load_pattern(test::pattern_path("closed.json"));
  const RgbImage exact = exact_image(p);
  const std::vector<uint8_t> edges = edge_pixels(p);
  for (double density : {0.05, 0.1, 0.3, 1.0})
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      test::Built b = test::build(p, density, seed);
      const Reconstruction r = reconstruct_tiled(b.epi, b.masks, {Filter::epi, false, true});
      int checked = 0;
      for (int y = 0; y < p.height; ++y)
        for (int x = 0; x < p.width; ++x) {
          const size_t i = size_t(y * p.width + x);
          if (edges[i] || r.priority[i] == kMaxPriority) continue;  // edge pixel, or nothing reachable
          bool near_corner = false;
          for (const Polygon& poly : p.polygons)
            for (const auto& v : poly.points) near_corner |= std::abs(v[0] - x) < 4 && std::abs(v[1] - y) < 4;
          if (near_corner) continue;
          for (int c = 0; c < 3; ++c) ASSERT_NEAR(r.image.at(x, y)[c], exact.at(x, y)[c], 1e-5) << x << "," << y;
          ++checked;
        }
      EXPECT_GT(checked, 1000);
      // Whatever the fallbacks do, a pixel whose whole footprint (9x9: fill over 5x5 of
      // interpolations over 5x5) is free of edges gets its polygon's colour, or black.
      for (int y = 4; y + 4 < p.height; ++y)
        for (int x = 4; x + 4 < p.width; ++x) {
          bool clear = true;
          for (int dy = -4; dy <= 4; ++dy)
            for (int dx = -4; dx <= 4; ++dx) clear = clear && !edges[size_t((y + dy) * p.width + x + dx)];
          if (!clear) continue;
          const float* got = r.image.at(x, y);
          const bool black = got[0] == 0 && got[1] == 0 && got[2] == 0;
          for (int c = 0; c < 3 && !black; ++c) ASSERT_NEAR(got[c], exact.at(x, y)[c], 1e-5) << x << "," << y;
        }
    }
}

// Polygons on grid lines and through pixel corners: with every pixel sampled the result is
// close to exact, with the error bounded by the 1/8-pixel edge resolution.
TEST(Quality, GridAlignedAndCornerPolygons) {
  const Pattern p = parse_pattern(R"({"width":40,"height":40,"background":[0,0,0],"polygons":[
      {"color":[1,1,1],"points":[[5,5],[17,5],[17,17],[5,17]]},
      {"color":[1,0.5,0],"points":[[30,21],[38,29],[30,37],[22,29]]},
      {"color":[0,0.5,1],"points":[[3,22.5],[14,22.5],[14,33.5],[3,33.5]]}]})", "grid.json");
  test::Built b = test::build(p, 1.0, 1);
  const RgbImage exact = exact_image(p);
  const std::vector<uint8_t> edges = edge_pixels(p);
  const Reconstruction r = reconstruct_tiled(b.epi, b.masks, {});
  const double error = test::mean_error(r.image, exact, edges);
  const double point = test::mean_error(point_sampled(b.epi), exact, edges);
  std::printf("grid/corners  edge pixels: point sampling %.4f, EPI %.4f\n", point, error);
  EXPECT_LT(error, 0.06);
  EXPECT_LT(error, 0.5 * point);
  // The axis-aligned square's edges are on grid lines: no complex pixel except near corners.
  EXPECT_LE(r.counts.complex, 12);
}

}  // namespace
}  // namespace epi

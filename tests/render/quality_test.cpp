// What the renderer must show, on every bundled scene (small images, few frames, subdivision
// level 2 to keep the suite fast): at equal budget and frames the EPI image is closer to the
// reference than the render cache's, also at the pixels its geometric edges cross; and with a still
// camera the EPI error keeps falling.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "load_scene.h"
#include "epi/interpolate.h"
#include "render/camera_path.h"
#include "render/renderer.h"
#include "shade/render_image.h"

namespace epi::render {
namespace {

constexpr int kSize = 96;

struct Loaded {
  explicit Loaded(const std::string& name)
      : scene(load_scene(std::string(EPI_SOURCE_DIR) + "/scenes/" + name, LoadOptions{2})),
        ray_scene(scene),
        shader(ray_scene, ShaderSettings{}) {}
  Scene scene;
  RayScene ray_scene;
  Shader shader;
};

View still_view(const Scene& scene) {
  View v;
  v.camera = scene.cameras.at(0), v.width = kSize, v.height = kSize;
  return v;
}

// Per-pixel absolute error summed over channels, on linear values clamped to [0, 1] (what a screen
// shows). Unclamped, the few pixels at the Cornell lamp's edge (17 times white, kept by the EPI's
// colour codes since issue 9) outweighed the whole rest of the image.
std::vector<double> pixel_errors(const RgbImage& a, const RgbImage& b) {
  std::vector<double> e(size_t(a.width) * size_t(a.height));
  auto shown = [](float v) { return std::clamp(double(v), 0.0, 1.0); };
  for (size_t i = 0; i < e.size(); ++i)
    for (int c = 0; c < 3; ++c) e[i] += std::abs(shown(a.pixels[i * 3 + size_t(c)]) - shown(b.pixels[i * 3 + size_t(c)]));
  return e;
}

// Pixels the edge pieces the renderer rasterized pass through (sampled finely): geometric ones
// (silhouette, sharp, border), or shadow ones (umbral, penumbral, shadow).
std::vector<uint8_t> edge_pixels(const FrameRenderer& renderer, int w, int h, bool shadow = false) {
  std::vector<uint8_t> mask(size_t(w) * size_t(h), 0);
  for (size_t k = 0; k < renderer.segments().size(); ++k) {
    const Segment& s = renderer.segments()[k];
    const edges::EdgeKind kind = renderer.segment_kinds()[k];
    const bool geometric = kind == edges::EdgeKind::silhouette || kind == edges::EdgeKind::sharp || kind == edges::EdgeKind::border;
    if (geometric == shadow) continue;
    const int steps = 1 + int(4.0 * std::hypot(s.x1 - s.x0, s.y1 - s.y0));
    for (int k = 0; k <= steps; ++k) {
      const double t = double(k) / steps;
      const int x = int(std::floor(s.x0 + t * (s.x1 - s.x0))), y = int(std::floor(s.y0 + t * (s.y1 - s.y0)));
      if (x >= 0 && y >= 0 && x < w && y < h) mask[size_t(y) * size_t(w) + size_t(x)] = 1;
    }
  }
  return mask;
}

// RMSE of sRGB-encoded values clamped to [0, 1] (what a screen shows; the light's own pixels,
// far above 1, count as 1).
double display_rmse(const RgbImage& a, const RgbImage& b) {
  auto display = [](float v) {
    const double c = std::clamp(double(v), 0.0, 1.0);
    return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  };
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) sum += std::pow(display(a.pixels[i]) - display(b.pixels[i]), 2.0);
  return std::sqrt(sum / double(a.pixels.size()));
}

class Quality : public ::testing::TestWithParam<const char*> {};

TEST_P(Quality, EpiIsCloserToTheReferenceThanTheRenderCacheAndKeepsImproving) {
  Loaded loaded(GetParam());
  const View view = still_view(loaded.scene);
  const RgbImage reference = render_image(loaded.shader, view, 8);
  FrameSettings s;
  s.width = kSize, s.height = kSize, s.sync = true, s.sample_budget = 0.04, s.seed = 2;

  s.mode = RenderMode::epi;
  FrameRenderer epi(loaded.scene, loaded.ray_scene, loaded.shader, s);
  s.mode = RenderMode::rendercache;
  FrameRenderer cache(loaded.scene, loaded.ray_scene, loaded.shader, s);
  std::vector<double> epi_errors;
  RgbImage epi_image, cache_image;
  for (int f = 0; f < 12; ++f) {
    epi_image = epi.render(view.camera);
    cache_image = cache.render(view.camera);
    if (f % 3 == 2) {
      double sum = 0.0;
      for (double e : pixel_errors(epi_image, reference)) sum += e;
      epi_errors.push_back(sum);
    }
  }
  for (size_t k = 1; k < epi_errors.size(); ++k) EXPECT_LT(epi_errors[k], epi_errors[k - 1]) << "step " << k;

  const std::vector<double> e_epi = pixel_errors(epi_image, reference), e_cache = pixel_errors(cache_image, reference);
  const std::vector<uint8_t> near_edges = edge_pixels(epi, kSize, kSize);
  double all_epi = 0, all_cache = 0, edge_epi = 0, edge_cache = 0;
  size_t edge_count = 0;
  for (size_t i = 0; i < e_epi.size(); ++i) {
    all_epi += e_epi[i], all_cache += e_cache[i];
    if (near_edges[i]) edge_epi += e_epi[i], edge_cache += e_cache[i], ++edge_count;
  }
  ASSERT_GT(edge_count, 50u);
  EXPECT_LT(all_epi, all_cache);
  EXPECT_LT(edge_epi, edge_cache);  // ratios per scene: docs/render.md
  // Shadow boundaries: the pixels crossed by the shadow edges this frame (scenes that have them).
  const std::vector<uint8_t> near_shadows = edge_pixels(epi, kSize, kSize, true);
  double shadow_epi = 0, shadow_cache = 0;
  size_t shadow_count = 0;
  for (size_t i = 0; i < e_epi.size(); ++i)
    if (near_shadows[i]) shadow_epi += e_epi[i], shadow_cache += e_cache[i], ++shadow_count;
  if (shadow_count >= 20) {
    // Hard shadow edges (punctual lights; soft-shadow edges are off by default, test below). At
    // rest the render cache averages results at every pixel while the EPI keeps one side's sample
    // at a pixel an edge crosses (PointCache::set_refine_mask): rooms measures 1.01 here.
    EXPECT_LT(shadow_epi, 1.05 * shadow_cache);
  }
  std::printf("%s: EPI/render cache error %.3f at %zu shadow edge pixels\n", GetParam(),
              shadow_count ? shadow_epi / shadow_cache : 0.0, shadow_count);
  RecordProperty("error_ratio_all", std::to_string(all_epi / all_cache));
  RecordProperty("error_ratio_edges", std::to_string(edge_epi / edge_cache));
  std::printf("%s: EPI/render cache error %.3f overall, %.3f at %zu edge pixels\n", GetParam(), all_epi / all_cache,
              edge_epi / edge_cache, edge_count);
}

// torus_capsule's shadow-edge excess (docs/render.md, "Quality") is the narrow penumbra, not a
// misplaced edge: under the capsule the umbral and penumbral edges are 2-3 pixels apart and the
// shading climbs from black to lit between them. The EPI estimates that strip from its own few
// samples, whose mean lies mid-ramp, so pixels on the umbral edges come out too bright and those
// on the penumbral edges too dark; without the shadow edges the same pixels beat the render cache.
// The Cornell box at rest, 96x96, 4 %: the pixel holding the lamp's top-left corner (39, 12) has
// one crossing on its right side and one on its bottom, so it used to be simple with a chord far
// from the corner, and from frame 8 a lamp sample there gave 35-50 % of its colour to the black
// ceiling pixels up and left of it (docs/render.md, "Bright colours"). The centre lines now show
// the corner and make the pixel complex (core/epi classify.cpp; tests/epi/classify_test.cpp).
// The reference is black there (the direct shader leaves the ceiling unlit).
TEST(QualityCornell, LampColourStaysOffTheCeilingNextToItsCorner) {
  Loaded loaded("cornell_box.gltf");
  const View view = still_view(loaded.scene);
  FrameSettings s;
  s.width = kSize, s.height = kSize, s.sync = true, s.sample_budget = 0.04, s.seed = 2, s.mode = RenderMode::epi;
  FrameRenderer epi(loaded.scene, loaded.ray_scene, loaded.shader, s);
  RgbImage image;
  for (int f = 0; f <= 8; ++f) image = epi.render(view.camera);
  for (int y = 10; y <= 11; ++y)
    for (int x = 37; x <= 39; ++x) EXPECT_LT(image.at(x, y)[0], 0.05f) << x << "," << y;
}

TEST(QualityTorusCapsule, ShadowEdgeExcessIsTheNarrowPenumbraStrip) {
  Loaded loaded("torus_capsule.gltf");
  const View view = still_view(loaded.scene);
  const RgbImage reference = render_image(loaded.shader, view, 8);
  auto run = [&](RenderMode mode, bool shadow_edges, RgbImage& image) {
    FrameSettings s;
    s.width = kSize, s.height = kSize, s.sync = true, s.sample_budget = 0.04, s.seed = 2;
    s.mode = mode, s.shadow_edges = shadow_edges, s.soft_shadow_edges = shadow_edges;  // the paper's behaviour
    auto r = std::make_unique<FrameRenderer>(loaded.scene, loaded.ray_scene, loaded.shader, s);
    for (int f = 0; f < 12; ++f) image = r->render(view.camera);
    return r;
  };
  RgbImage epi_image, plain_image, cache_image;
  const auto epi = run(RenderMode::epi, true, epi_image);
  run(RenderMode::epi, false, plain_image);
  run(RenderMode::rendercache, false, cache_image);
  // Pixels crossed by one kind of shadow edge only.
  auto kind_pixels = [&](edges::EdgeKind kind) {
    std::vector<uint8_t> mask(size_t(kSize) * size_t(kSize), 0);
    for (size_t k = 0; k < epi->segments().size(); ++k) {
      if (epi->segment_kinds()[k] != kind) continue;
      const Segment& s = epi->segments()[k];
      const int steps = 1 + int(4.0 * std::hypot(s.x1 - s.x0, s.y1 - s.y0));
      for (int j = 0; j <= steps; ++j) {
        const double t = double(j) / steps;
        const int x = int(std::floor(s.x0 + t * (s.x1 - s.x0))), y = int(std::floor(s.y0 + t * (s.y1 - s.y0)));
        if (x >= 0 && y >= 0 && x < kSize && y < kSize) mask[size_t(y) * size_t(kSize) + size_t(x)] = 1;
      }
    }
    return mask;
  };
  const std::vector<uint8_t> umbral = kind_pixels(edges::EdgeKind::umbral), penumbral = kind_pixels(edges::EdgeKind::penumbral);
  const std::vector<uint8_t> shadow = edge_pixels(*epi, kSize, kSize, true);
  // Signed error (EPI - reference, summed over channels) on pixels of one kind only.
  auto signed_error = [&](const std::vector<uint8_t>& mine, const std::vector<uint8_t>& other) {
    double sum = 0.0;
    for (size_t i = 0; i < mine.size(); ++i)
      if (mine[i] && !other[i])
        for (int c = 0; c < 3; ++c) sum += double(epi_image.pixels[i * 3 + size_t(c)]) - double(reference.pixels[i * 3 + size_t(c)]);
    return sum;
  };
  const double umbral_bias = signed_error(umbral, penumbral), penumbral_bias = signed_error(penumbral, umbral);
  auto masked = [&](const RgbImage& image) {
    double sum = 0.0;
    const std::vector<double> e = pixel_errors(image, reference);
    for (size_t i = 0; i < e.size(); ++i)
      if (shadow[i]) sum += e[i];
    return sum;
  };
  const double with_edges = masked(epi_image), without = masked(plain_image), cache = masked(cache_image);
  std::printf("torus_capsule shadow edge pixels: EPI/render cache %.3f with shadow edges, %.3f without; "
              "EPI signed error %+.2f on umbral pixels, %+.2f on penumbral pixels\n",
              with_edges / cache, without / cache, umbral_bias, penumbral_bias);
  EXPECT_GT(umbral_bias, 0.0);     // too bright next to the umbra
  EXPECT_LT(penumbral_bias, 0.0);  // too dark next to the lit floor
  // The evidence for FrameSettings::soft_shadow_edges = false (docs/render.md, "Soft-shadow
  // edges"): the same pixels are clearly better without the soft edges, and the paper's behaviour
  // is worse there than the render cache.
  EXPECT_LT(without, 0.9 * with_edges);  // 0.85 before the sparse occlusion test (0.852 since: docs/render.md)
  EXPECT_GT(with_edges, cache);
}

// Convergence at rest (issue 9): with the gi shader each result is one noisy estimate. Refined
// in place (running means per point), a still view keeps improving past a 1-spp path trace of the
// same shader; replaced (the render cache's rule), it never gets much better than one.
TEST(QualityAtRest, StillGiViewConvergesPastAOneSampleRayTrace) {
  const Scene scene = load_scene(std::string(EPI_SOURCE_DIR) + "/scenes/cornell_box.gltf", LoadOptions{2});
  RayScene ray_scene(scene);
  ShaderSettings ss;
  ss.kind = ShaderKind::gi, ss.gi_paths = 2, ss.area_light_samples = 2;
  const Shader shader(ray_scene, ss);
  View view;
  view.camera = scene.cameras.at(0), view.width = 64, view.height = 64;
  const RgbImage reference = render_image(shader, view, 256);
  auto total_error = [&](const RgbImage& image) { return display_rmse(image, reference); };
  const double one_spp = total_error(render_image(shader, view, 1));
  auto run = [&](bool refine) {
    FrameSettings s;
    s.width = 64, s.height = 64, s.sync = true, s.sample_budget = 0.1, s.seed = 4;
    s.cache.refine = refine;
    FrameRenderer renderer(scene, ray_scene, shader, s);
    RgbImage image;
    for (int f = 0; f < 100; ++f) image = renderer.render(view.camera);
    return total_error(image);
  };
  const double refined = run(true), replaced = run(false);
  std::printf("cornell_box gi at rest, 64x64, 100 frames at 10%%: display RMSE / 1-spp ray trace %.3f refined, %.3f replaced\n",
              refined / one_spp, replaced / one_spp);
  // Measured 0.40 and 0.49; at 64x64 the reconstruction's own error at edges sets the floor
  // (300 frames give the same 0.40), so the margin between the two is what refinement buys here.
  EXPECT_LT(refined, 0.45 * one_spp);
  EXPECT_LT(refined, 0.9 * replaced);
}

// Holes (issue 9): a short run along rooms' fast path leaves pixels that reach no sample; they
// were black. Filled from their own region, none stays black.
TEST(QualityHoles, AFastPathLeavesNoBlackHoles) {
  Loaded loaded("rooms.gltf");
  const CameraPath path = scene_camera_path(loaded.scene, 30);
  auto black_holes = [&](bool fill) {
    FrameSettings s;
    s.width = 192, s.height = 128, s.sync = true, s.seed = 3, s.fill_holes = fill;
    FrameRenderer renderer(loaded.scene, loaded.ray_scene, loaded.shader, s);
    RgbImage image;
    for (int f = 0; f < 30; ++f) image = renderer.render(path.camera_at(f));
    size_t count = 0;
    for (size_t i = 0; i < renderer.priority().size(); ++i)
      count += renderer.priority()[i] >= kMaxPriority && image.pixels[3 * i] == 0.0f && image.pixels[3 * i + 1] == 0.0f &&
               image.pixels[3 * i + 2] == 0.0f;
    return count;
  };
  const size_t without = black_holes(false), with = black_holes(true);
  std::printf("rooms 192x128 after 30 frames of its path: %zu black hole pixels unfilled, %zu filled\n", without, with);
  EXPECT_GT(without, 10u);  // 40 with prediction at stride 2, splat 3; 19 at 8, 5; 43 with it off
  EXPECT_EQ(with, 0u);
}

INSTANTIATE_TEST_SUITE_P(BundledScenes, Quality,
                         ::testing::Values("cornell_box.gltf", "chains.gltf", "rooms.gltf", "torus_capsule.gltf",
                                           "grid_dragon.gltf"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           return name.substr(0, name.find('.'));
                         });

}  // namespace
}  // namespace epi::render

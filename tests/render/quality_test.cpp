// What the renderer must show, on every bundled scene (small images, few frames, subdivision
// level 2 to keep the suite fast): at equal budget and frames the EPI image is closer to the
// reference than the render cache's, also at the pixels its geometric edges cross; and with a still
// camera the EPI error keeps falling.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "load_scene.h"
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

// Per-pixel absolute error summed over channels.
std::vector<double> pixel_errors(const RgbImage& a, const RgbImage& b) {
  std::vector<double> e(size_t(a.width) * size_t(a.height));
  for (size_t i = 0; i < e.size(); ++i)
    for (int c = 0; c < 3; ++c) e[i] += std::abs(double(a.pixels[i * 3 + size_t(c)]) - double(b.pixels[i * 3 + size_t(c)]));
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
    // torus_capsule is a known open defect (docs/render.md, "Quality"): EPI is 1.38x the render
    // cache's error at its shadow edges; held at that level here so it cannot get worse unseen.
    const double allowed = std::string(GetParam()) == "torus_capsule.gltf" ? 1.45 : 1.0;
    EXPECT_LT(shadow_epi, allowed * shadow_cache);
  }
  std::printf("%s: EPI/render cache error %.3f at %zu shadow edge pixels\n", GetParam(),
              shadow_count ? shadow_epi / shadow_cache : 0.0, shadow_count);
  RecordProperty("error_ratio_all", std::to_string(all_epi / all_cache));
  RecordProperty("error_ratio_edges", std::to_string(edge_epi / edge_cache));
  std::printf("%s: EPI/render cache error %.3f overall, %.3f at %zu edge pixels\n", GetParam(), all_epi / all_cache,
              edge_epi / edge_cache, edge_count);
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

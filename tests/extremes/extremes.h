// Shared by the extremes suite (docs/reliability.md, "Extremes"): scenes built in code, the frame
// loop run over a list of cameras, and the checks every rendered frame must pass.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/renderer.h"
#include "test_scenes.h"

namespace epi::extremes {

using namespace epi::test;

// Every channel finite and in [0, max]. Returns the number of bad values (reported once).
inline size_t count_insane(const RgbImage& image, float max, const std::string& what) {
  size_t bad = 0;
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    const float v = image.pixels[i];
    if (std::isfinite(v) && v >= 0.0f && v <= max) continue;
    if (bad++ == 0) ADD_FAILURE() << what << ": pixel " << i / 3 << " channel " << i % 3 << " is " << v;
  }
  return bad;
}

// With EPI_EXTREMES_DUMP=DIR set, writes the image as DIR/<test>_<n>.ppm (sRGB) to look at.
inline void dump(const RgbImage& image) {
  const char* dir = std::getenv("EPI_EXTREMES_DUMP");
  if (!dir) return;
  static int n = 0;
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = std::string(dir) + "/" + info->test_suite_name() + "." + info->name() + "_" + std::to_string(n++) + ".ppm";
  std::replace(name.begin() + ptrdiff_t(std::string(dir).size()) + 1, name.end(), '/', '_');
  FILE* f = std::fopen(name.c_str(), "wb");
  if (!f) return;
  std::fprintf(f, "P6\n%d %d\n255\n", image.width, image.height);
  for (float v : image.pixels) {
    const float c = std::clamp(v, 0.0f, 1.0f);
    std::fputc(int(255.0f * (c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f) + 0.5f), f);
  }
  std::fclose(f);
}

struct Rendered {
  RgbImage image;            // the last frame
  render::FrameStats stats;  // of the last frame
  size_t insane = 0;         // bad channel values over all frames
  std::vector<edges::SceneEdge> edges;  // the last frame's 3D edges
};

// Renders the cameras in turn (sync, deterministic) and checks every frame.
inline Rendered render_frames(const Scene& scene, const std::vector<Camera>& cameras, render::FrameSettings settings,
                         const ShaderSettings& shading = {}, float max_value = 50.0f) {
  RayScene ray_scene(scene);
  Shader shader(ray_scene, shading);
  settings.sync = true;
  render::FrameRenderer renderer(scene, ray_scene, shader, settings);
  Rendered run;
  for (size_t k = 0; k < cameras.size(); ++k) {
    const RgbImage& image = renderer.render(cameras[k]);
    run.insane += count_insane(image, max_value, "frame " + std::to_string(k));
    for (const float p : renderer.priority())
      if (!std::isfinite(p) || p < 0.0f) ++run.insane;
    for (const edges::SceneEdge& e : renderer.scene_edges())
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(e.a[c]) || !std::isfinite(e.b[c])) ++run.insane;
  }
  run.image = renderer.render(cameras.back());
  run.insane += count_insane(run.image, max_value, "last frame");
  run.stats = renderer.stats();
  run.edges = renderer.scene_edges();
  dump(run.image);
  return run;
}

inline render::FrameSettings settings(int w, int h, double budget = 0.25) {
  render::FrameSettings s;
  s.width = w, s.height = h, s.sample_budget = budget, s.seed = 7;
  return s;
}

// The camera moving: n frames stepping the eye (and target) by `step` each.
inline std::vector<Camera> moving(Camera c, glm::vec3 step, int n) {
  std::vector<Camera> list;
  for (int k = 0; k < n; ++k) {
    list.push_back(c);
    c.eye += step, c.target += step;
  }
  return list;
}

inline float luminance(const float* rgb) { return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2]; }

}  // namespace epi::extremes

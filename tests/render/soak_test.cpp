// The soak run (issue 14, docs/reliability.md): the frame loop with asynchronous shading for many
// frames while the camera orbits, a chain link slides and the point light swings (chains.gltf).
// Every 100 frames: no pixel is NaN or infinite, memory stays bounded, frame time does not drift.
// ctest runs a short version; the long one is
//   EPI_SOAK_FRAMES=10000 build/bin/render_soak_test
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include "load_scene.h"
#include "render/renderer.h"

namespace epi::render {
namespace {

// Resident memory of this process, bytes (/proc/self/statm: size resident ...).
double resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  double size = 0, resident = 0;
  statm >> size >> resident;
  return resident * double(::sysconf(_SC_PAGESIZE));
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[size_t(q * double(v.size() - 1))];
}
double median(std::vector<double> v) { return quantile(std::move(v), 0.5); }
double low_decile(std::vector<double> v) { return quantile(std::move(v), 0.1); }

TEST(Soak, MovingCameraObjectAndLightWithAsyncShadingStayFiniteBoundedAndSteady) {
  const char* env = std::getenv("EPI_SOAK_FRAMES");
  const int frames = env ? std::max(300, std::atoi(env)) : 400;
  const Scene scene = load_scene(std::filesystem::path(EPI_SOURCE_DIR) / "scenes" / "chains.gltf");
  const auto link = std::find_if(scene.objects.begin(), scene.objects.end(), [](const Object& o) { return o.name == "red_chain_0"; });
  const auto point = std::find_if(scene.punctual_lights.begin(), scene.punctual_lights.end(),
                                  [](const PunctualLight& l) { return l.name == "point"; });
  ASSERT_NE(link, scene.objects.end());
  ASSERT_NE(point, scene.punctual_lights.end());
  const size_t moved_object = size_t(link - scene.objects.begin()), moved_light = size_t(point - scene.punctual_lights.begin());

  RayScene ray_scene(scene);
  ShaderSettings shading;
  shading.area_light_samples = 2;
  const Shader shader(ray_scene, shading);
  FrameSettings settings;
  settings.width = 96, settings.height = 72, settings.sample_budget = 0.03, settings.sync = false;
  FrameRenderer renderer(scene, ray_scene, shader, settings);

  // Everything moves with a period of 100 frames, so that windows of one period see the same views
  // and their frame times compare like with like. The first period fills the caches (warm-up).
  constexpr int kPeriod = 100;
  const double w = 2.0 * 3.14159265358979 / kPeriod;
  double memory_after_warm_up = 0.0, memory_peak = 0.0;
  std::vector<double> frame_ms, period_fast;
  int fed = 0;  // frames that integrated shading results
  for (int f = 0; f < frames; ++f) {
    const double t = double(f);
    Camera camera = scene.cameras.front();
    camera.target = {0.0f, 0.4f, 0.0f};
    camera.eye = {float(4.0 * std::cos(t * w)), float(1.6 + 0.5 * std::sin(2.0 * t * w)), float(4.0 * std::sin(t * w))};
    std::vector<glm::mat4> objects;
    for (const Object& o : scene.objects) objects.push_back(o.object_to_world);
    objects[moved_object][3] += glm::vec4(float(0.4 * std::sin(2.0 * t * w)), 0.0f, float(0.3 * std::cos(t * w)), 0.0f);
    std::vector<glm::vec3> lights;
    for (const PunctualLight& l : scene.punctual_lights) lights.push_back(l.position);
    lights[moved_light] += glm::vec3(float(0.8 * std::sin(t * w)), 0.0f, float(0.8 * std::cos(t * w)));

    const RgbImage& image = renderer.render(camera, objects, lights);
    frame_ms.push_back(renderer.stats().ms.total);
    fed += renderer.stats().samples > 0;
    if ((f + 1) % kPeriod != 0) continue;

    // A checkpoint at the end of every period.
    SCOPED_TRACE("frame " + std::to_string(f));
    const size_t bad = size_t(std::count_if(image.pixels.begin(), image.pixels.end(), [](float v) { return !std::isfinite(v); }));
    ASSERT_EQ(bad, 0u) << "non-finite pixel values";
    const double memory = resident_bytes();
    memory_peak = std::max(memory_peak, memory);
    if (memory_after_warm_up == 0.0) memory_after_warm_up = memory;
    // Bounded: the point cache, edges and images have fixed capacities.
    EXPECT_LT(memory, memory_after_warm_up * 1.25 + 16e6) << "resident memory grows";
    if (f + 1 > kPeriod) period_fast.push_back(low_decile(std::vector<double>(frame_ms.end() - kPeriod, frame_ms.end())));
  }
  ASSERT_GE(period_fast.size(), 2u) << "EPI_SOAK_FRAMES: at least 300";
  // The shader fed while everything moves: until 2026-11-26 a move cancelled the requests not yet
  // started, and some runs integrated no result in 277 of 300 frames (whose fast frames then
  // also tripped the drift check below; docs/render.md, "The loop").
  EXPECT_GT(fed, frames * 2 / 3) << "frames that integrated shading results";
  // No drift: the last period's fast frames (its 10th percentile) within 3x (+5 ms) of the first
  // period's after warm-up. Growing work raises every frame; other programs' load on a shared
  // machine raises many frames but rarely the fastest tenth (medians moved 3.8 -> 18.8 ms in a
  // loaded ctest run with no drift).
  EXPECT_LT(period_fast.back(), 3.0 * period_fast.front() + 5.0)
      << "frame time drifted from " << period_fast.front() << " ms to " << period_fast.back() << " ms";
  std::printf("soak: %d frames (%d with results), median frame %.2f ms (10th percentile: first period after warm-up %.2f, last %.2f), resident %.1f MB after warm-up, "
              "peak %.1f MB\n",
              frames, fed, median(frame_ms), period_fast.front(), period_fast.back(), memory_after_warm_up / 1e6,
              memory_peak / 1e6);
}

}  // namespace
}  // namespace epi::render

// The point cache along the Cornell box's camera path (sync, small image): after the camera
// swings, the points drawn must be the nearest surface along their own ray (a point hidden
// behind a surface the camera has since seen must not be drawn; docs/render.md, "Points").
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "load_scene.h"
#include "render/camera_path.h"
#include "render/renderer.h"

namespace epi::render {
namespace {

struct HiddenCount {
  size_t drawn = 0, hidden = 0;
  size_t interior = 0;  // of which hidden also one pixel away in all four directions (not at a silhouette)
};

// Drawn points that are not the nearest surface along the eye ray through their own projected
// position (or background points where that ray hits something).
HiddenCount count_hidden(const FrameRenderer& renderer, const RayScene& ray_scene, const ViewFrame& frame,
                         std::span<const glm::mat4> transforms) {
  const PointCache& cache = renderer.cache();
  const PointImage& image = cache.image();
  HiddenCount c;
  for (size_t i = 0; i < image.point.size(); ++i) {
    if (image.point[i] < 0) continue;
    const CachePoint& p = cache.points()[size_t(image.point[i])];
    ++c.drawn;
    const Projection proj = frame.project(cache.world_position(p, frame, transforms));
    const Ray ray = frame.ray(proj.pixel.x, proj.pixel.y);
    const RayHit hit = ray_scene.intersect(ray);
    if (p.object == kNone) {
      if (hit.hit) ++c.hidden;
      continue;
    }
    if (!hit.hit) continue;  // grazing: not counted
    const float hit_depth = frame.project(ray.origin + hit.t * ray.direction).depth;
    if (proj.depth > hit_depth * 1.02f + 1e-3f) {
      ++c.hidden;
      bool all = true;
      for (const glm::vec2 o : {glm::vec2(1, 0), glm::vec2(-1, 0), glm::vec2(0, 1), glm::vec2(0, -1)}) {
        const Ray r2 = frame.ray(proj.pixel.x + o.x, proj.pixel.y + o.y);
        const RayHit h2 = ray_scene.intersect(r2);
        if (!h2.hit || proj.depth <= frame.project(r2.origin + h2.t * r2.direction).depth * 1.02f + 1e-3f) all = false;
      }
      if (all) ++c.interior;
    }
  }
  return c;
}

HiddenCount run_path(const std::string& scene_name, int size, int frames, double budget, RenderMode mode,
                     bool occlusion_test = true, uint64_t seed = 5) {
  const Scene scene = load_scene(std::string(EPI_SOURCE_DIR) + "/scenes/" + scene_name, LoadOptions{2});
  RayScene ray_scene(scene);
  const Shader shader(ray_scene, ShaderSettings{});
  FrameSettings s;
  s.mode = mode, s.width = size, s.height = size, s.sync = true, s.sample_budget = budget, s.seed = seed;
  s.occlusion_test = occlusion_test;
  FrameRenderer renderer(scene, ray_scene, shader, s);
  const CameraPath path = scene_camera_path(scene, frames);
  for (int f = 0; f < frames; ++f) renderer.render(path.camera_at(f));
  const Camera last = path.camera_at(frames - 1);
  View view;
  view.camera = last, view.width = size, view.height = size;
  const ViewFrame frame(view);
  std::vector<glm::mat4> transforms(scene.objects.size());
  for (size_t o = 0; o < transforms.size(); ++o) transforms[o] = ray_scene.object_to_world(uint32_t(o));
  return count_hidden(renderer, ray_scene, frame, transforms);
}

// Measured (seed 5; interior = hidden also one pixel away all round, i.e. speckles, not silhouette
// pixels): before the ray-evidence rule 100 of 36681 drawn points hidden, 56 interior; after it
// 75 of 39842, 25 interior (docs/render.md, "Points").
TEST(PointCachePath, DrawnPointsAreTheNearestSurfaceAlongTheirRayAfterCameraMotion) {
  const HiddenCount c = run_path("cornell_box.gltf", 256, 60, 0.1, RenderMode::rendercache);
  std::printf("cornell_box 256x256, 60 frames: %zu of %zu drawn points hidden, %zu interior\n", c.hidden, c.drawn,
              c.interior);
  ASSERT_GT(c.drawn, size_t(256 * 256 / 2));
  EXPECT_LT(double(c.interior) / double(c.drawn), 0.001);
  EXPECT_LT(double(c.hidden) / double(c.drawn), 0.0024);
}

// The main job's defect (issue 9): the Cornell box along its path at the default 2 % budget showed
// the back wall through the blocks and the background through the red wall. The EPI's occlusion
// test (no geometric edge between a far point and a nearer point's plane: hidden) removes them.
// Summed over three seeds: one seed's count of a dozen points moves by a third whenever the
// sampling changes (seeds 1-7: 8-14 interior before the corner rule of classification, 11-18 after).
TEST(PointCachePath, TheEpiShowsNoFarPointsThroughNearerSurfacesAfterCameraMotion) {
  HiddenCount without, with;
  for (uint64_t seed : {5, 6, 7}) {
    const HiddenCount a = run_path("cornell_box.gltf", 256, 60, 0.02, RenderMode::epi, false, seed);
    const HiddenCount b = run_path("cornell_box.gltf", 256, 60, 0.02, RenderMode::epi, true, seed);
    without.drawn += a.drawn, without.hidden += a.hidden, without.interior += a.interior;
    with.drawn += b.drawn, with.hidden += b.hidden, with.interior += b.interior;
  }
  std::printf("cornell_box 256x256, 60 frames, budget 0.02, epi: hidden %zu of %zu drawn (%zu interior) without the "
              "occlusion test, %zu of %zu (%zu interior) with it\n",
              without.hidden, without.drawn, without.interior, with.hidden, with.drawn, with.interior);
  ASSERT_GT(with.drawn, size_t(3 * 256 * 256 / 2));
  EXPECT_GT(without.interior, 5 * std::max<size_t>(with.interior, 1));
  EXPECT_LT(double(with.interior) / double(with.drawn), 0.0005);
}

}  // namespace
}  // namespace epi::render

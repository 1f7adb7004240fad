// The FrameSettings the study varies that no other test covers: silhouettes only
// (sharp_border_edges), the edge finder's forced choice (edge_finder.force) and the
// reconstruction's kernels (kernels).
#include <gtest/gtest.h>

#include "load_scene.h"
#include "render/camera_path.h"
#include "render/renderer.h"
#include "simd/row_kernels.h"

namespace epi::render {
namespace {

struct Cornell {
  Cornell() : scene(load_scene(std::string(EPI_SOURCE_DIR) + "/scenes/cornell_box.gltf")), ray_scene(scene), shader(ray_scene, {}) {}
  Scene scene;
  RayScene ray_scene;
  Shader shader;
};

FrameSettings small() {
  FrameSettings s;
  s.width = 64, s.height = 64, s.sync = true, s.seed = 3;
  return s;
}

TEST(StudySettings, SilhouettesOnlyDropsSharpAndBorderEdges) {
  Cornell c;
  const Camera camera = c.scene.cameras.at(0);
  FrameSettings s = small();
  FrameRenderer all(c.scene, c.ray_scene, c.shader, s);
  all.render(camera);
  ASSERT_GT(all.stats().edges.sharp + all.stats().edges.border, 0);  // the box has creases and open borders
  ASSERT_GT(all.stats().edges.silhouette, 0);
  s.sharp_border_edges = false;
  FrameRenderer silhouettes(c.scene, c.ray_scene, c.shader, s);
  silhouettes.render(camera);
  EXPECT_EQ(silhouettes.stats().edges.sharp, 0);
  EXPECT_EQ(silhouettes.stats().edges.border, 0);
  EXPECT_EQ(silhouettes.stats().edges.silhouette, all.stats().edges.silhouette);
}

TEST(StudySettings, EdgeFinderForceReachesTheFinderAndKeepsTheImage) {
  Cornell c;
  const Camera camera = c.scene.cameras.at(0);
  std::vector<float> first;
  for (int force : {1, -1}) {
    FrameSettings s = small();
    s.edge_finder.force = force;
    FrameRenderer r(c.scene, c.ray_scene, c.shader, s);
    const RgbImage& image = r.render(camera);
    ASSERT_NE(r.edge_finder(), nullptr);
    for (uint32_t m = 0; m < c.scene.meshes.size(); ++m) EXPECT_EQ(r.edge_finder()->choice(m).tree, force == 1) << "mesh " << m;
    if (first.empty()) first = image.pixels;
    else EXPECT_EQ(image.pixels, first);  // both finders find the same edges
  }
}

TEST(StudySettings, EveryKernelChoiceGivesTheSameImage) {
  Cornell c;
  const CameraPath path = scene_camera_path(c.scene, 6);
  auto render = [&](KernelChoice k, std::string& name) {
    FrameSettings s = small();
    s.kernels = k;
    FrameRenderer r(c.scene, c.ray_scene, c.shader, s);
    RgbImage image;
    for (int f = 0; f < 6; ++f) image = r.render(path.camera_at(f));
    name = r.kernel_name();
    return image.pixels;
  };
  std::string name;
  const std::vector<float> oracle = render(KernelChoice{.oracle = true}, name);
  EXPECT_EQ(name, "oracle");
  for (int64_t target : simd::compiled_targets()) {
    EXPECT_EQ(render(KernelChoice{.target = target}, name), oracle) << simd::row_kernels(target).target_name;
    EXPECT_EQ(name, simd::row_kernels(target).target_name);  // the choice reached the reconstructor
  }
}

}  // namespace
}  // namespace epi::render

// How many pixels classification's corner rule makes complex (docs/epi.md, "Corners"; docs/render.md,
// "Bright colours"): each bundled scene along its camera path as render_motion_quality runs it
// (256x256, 60 frames, sync, budget 2 %, seed 5), per frame the pixels whose two crossings alone
// would make them simple but whose centre lines make them complex, and all complex pixels.
// Usage: render_corner_pixels SCENE.gltf...   (prints the means per frame and the frames that had any)
#include <cstdio>
#include <string>

#include "epi/classify.h"
#include "load_scene.h"
#include "render/camera_path.h"
#include "render/renderer.h"

int main(int argc, char** argv) {
  using namespace epi;
  using namespace epi::render;
  if (argc < 2) {
    std::fprintf(stderr, "usage: render_corner_pixels SCENE.gltf...\n");
    return 2;
  }
  constexpr int kSize = 256, kFrames = 60;
  std::printf("| scene | corner pixels per frame | complex pixels per frame | frames with corner pixels |\n|---|---|---|---|\n");
  for (int a = 1; a < argc; ++a) {
    const Scene scene = load_scene(argv[a]);
    RayScene ray_scene(scene);
    const Shader shader(ray_scene, ShaderSettings{});
    FrameSettings s;
    s.width = kSize, s.height = kSize, s.sync = true, s.sample_budget = 0.02, s.seed = 5;
    FrameRenderer renderer(scene, ray_scene, shader, s);
    const CameraPath path = scene_camera_path(scene, kFrames);
    long corners = 0, complex = 0;
    int frames_with = 0;
    for (int f = 0; f < kFrames; ++f) {
      renderer.render(path.camera_at(f));
      const BoundaryMasks& m = renderer.masks();
      int here = 0;
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
          uint8_t sides[4];
          m.pixel_sides(x, y, sides);
          const CellKind kind = classify_pixel(m, x, y, 0).kind;
          here += kind == CellKind::complex && geom::classify_cell(sides, 8).kind == CellKind::simple;
          complex += kind == CellKind::complex;
        }
      corners += here, frames_with += here > 0;
    }
    std::printf("| %s | %.1f | %.1f | %d of %d |\n", argv[a], double(corners) / kFrames, double(complex) / kFrames,
                frames_with, kFrames);
  }
  return 0;
}

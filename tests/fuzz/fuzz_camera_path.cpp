// libFuzzer target: the camera-path parser (core/render, docs/camera-path.md) against a small
// fixed scene, then the path evaluated at a few frames and every camera checked as the frame
// loop would. Any outcome but a path or a one-line std::runtime_error naming "fuzz.txt:" is a
// finding. docs/reliability.md.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "render/camera_path.h"
#include "shade/view.h"

namespace {

epi::Scene fixed_scene() {
  epi::Scene scene;
  epi::Mesh mesh;
  mesh.name = "tri";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  scene.meshes.push_back(mesh);
  scene.objects.push_back({"short_block", 0, glm::mat4(1.0f)});
  epi::PunctualLight point;
  point.name = "point";
  point.position = {0, 2, 0};
  scene.punctual_lights.push_back(point);
  epi::Camera camera;
  camera.name = "cam";
  scene.cameras.push_back(camera);
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const epi::Scene scene = fixed_scene();
  epi::render::CameraPath path;
  try {
    path = epi::render::parse_camera_path(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.txt", scene);
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    if (what.rfind("fuzz.txt:", 0) != 0 || what.find('\n') != std::string::npos) std::abort();  // not one line naming the file
    return 0;
  }
  for (double frame : {0.0, 0.5, 7.0, 1e6}) {
    epi::View view;
    view.camera = path.camera_at(frame);
    view.width = 16, view.height = 16;
    try {
      const epi::ViewFrame check(view);
    } catch (const std::invalid_argument&) {  // an interpolated camera the frame loop refuses, by name
    }
    path.object_transforms_at(scene, frame);
    path.light_positions_at(scene, frame);
  }
  return 0;
}

// Camera path files: keys, interpolation, object offsets, the scene's own path, and errors
// that name the file and line.
#include <gtest/gtest.h>

#include "render/camera_path.h"

namespace epi::render {
namespace {

Scene two_objects() {
  Scene scene;
  scene.objects.resize(2);
  scene.objects[0].name = "floor";
  scene.objects[1].name = "ball";
  scene.objects[1].object_to_world[3] = glm::vec4(0, 1, 0, 1);
  Camera c;
  c.eye = {0, 0, 5}, c.znear = 0.05f;
  scene.cameras.push_back(c);
  return scene;
}

TEST(CameraPath, KeysInterpolateLinearlyAndHoldAtTheEnds) {
  const Scene scene = two_objects();
  const CameraPath path = parse_camera_path(
      "# a path\n"
      "camera 10 eye 10 0 5 target 0 0 0 fov 30\n"
      "camera 0 eye 0 0 5 target 0 0 0   # first key listed second\n"
      "\n"
      "object 0 ball translate 0 0 0\n"
      "object 4 ball translate 2 0 0\n",
      "p.txt", scene);
  ASSERT_EQ(path.cameras.size(), 2u);
  EXPECT_FLOAT_EQ(path.camera_at(5).eye.x, 5.0f);
  EXPECT_FLOAT_EQ(path.camera_at(5).yfov_degrees, 37.5f);  // default 45 -> 30
  EXPECT_FLOAT_EQ(path.camera_at(-3).eye.x, 0.0f);
  EXPECT_FLOAT_EQ(path.camera_at(99).eye.x, 10.0f);
  EXPECT_FLOAT_EQ(path.camera_at(5).znear, 0.05f);  // from the scene's camera
  const auto at2 = path.object_transforms_at(scene, 2);
  EXPECT_FLOAT_EQ(at2[1][3].x, 1.0f);
  EXPECT_FLOAT_EQ(at2[1][3].y, 1.0f);  // the scene's placement kept
  EXPECT_EQ(at2[0], glm::mat4(1.0f));
  EXPECT_FLOAT_EQ(path.object_transforms_at(scene, 50)[1][3].x, 2.0f);
}

TEST(CameraPath, ErrorsNameTheFileAndLine) {
  const Scene scene = two_objects();
  const char* bad[] = {
      "camera x eye 0 0 0 target 1 1 1",        "camera 0 eye 0 0 0",
      "camera 0 eye 0 0 0 target 0 0 0",        "camera 0 eye 0 0 nan target 1 1 1",
      "camera 0 eye 0 0 0 target 1 1 1 fov 0",  "camera 0 eye 0 0 0 target 1 1 1 zoom 2",
      "object 0 nobody translate 1 2 3",         "object 0 ball rotate 1 2 3",
      "object 0 ball translate 1 2",             "light 0 sun",
      "camera -1 eye 0 0 0 target 1 1 1",        "object 0 ball translate 1 2 3 4",
  };
  for (const char* text : bad) {
    try {
      parse_camera_path(std::string("# ok\n") + text + "\n", "path.txt", scene);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("path.txt:2: ", 0), 0u) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
  EXPECT_THROW(read_camera_path("/nonexistent/path.txt", scene), std::runtime_error);
}

TEST(CameraPath, TheScenesPathSpreadsOverTheRun) {
  Scene scene = two_objects();
  EXPECT_EQ(scene_camera_path(scene, 10).camera_at(7).eye, scene.cameras[0].eye);  // no path: still
  Camera a, b;
  a.eye = {0, 0, 1}, b.eye = {9, 0, 1};
  scene.camera_path = {a, b};
  const CameraPath path = scene_camera_path(scene, 10);
  EXPECT_FLOAT_EQ(path.camera_at(0).eye.x, 0.0f);
  EXPECT_FLOAT_EQ(path.camera_at(3).eye.x, 3.0f);
  EXPECT_FLOAT_EQ(path.camera_at(9).eye.x, 9.0f);
  EXPECT_FLOAT_EQ(path.camera_at(9).znear, 0.05f);
}

}  // namespace
}  // namespace epi::render

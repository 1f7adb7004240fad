// Camera path files: keys, interpolation, object offsets, the scene's own path, and errors
// that name the file and line.
#include <cmath>
#include <random>
#include <vector>

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

// A hold (two equal keys, as the README's orbit ends with) gives the key's camera and placement
// exactly at every frame between, so the renderer sees a view at rest (render.md, "Idle shading
// at rest") and no object move (a move starts a new epoch of shading); glm::mix's
// a (1 - t) + a t missed the key's value in its last bit on these keys.
TEST(CameraPath, HeldKeysGiveTheKeyExactly) {
  const Scene scene = two_objects();
  const CameraPath path = parse_camera_path(
      "camera 0 eye 0.0535 0.2730 -0.7764 target 0.278 0.273 0.28\n"
      "camera 90 eye 0.2780 0.2730 -0.8000 target 0.278 0.273 0.28 fov 39.3\n"
      "camera 330 eye 0.2780 0.2730 -0.8000 target 0.278 0.273 0.28 fov 39.3\n"
      "object 0 ball translate 0.1 0.37 -0.29\n"
      "object 200 ball translate 0.1 0.37 -0.29\n",
      "p.txt", scene);
  const Camera held = path.camera_at(90);
  const glm::mat4 placed = path.object_transforms_at(scene, 0)[1];
  for (int f = 91; f < 330; ++f) {
    const Camera c = path.camera_at(f);
    ASSERT_TRUE(c.eye == held.eye && c.target == held.target && c.up == held.up && c.yfov_degrees == held.yfov_degrees)
        << "frame " << f;
  }
  for (int f = 1; f < 200; ++f) ASSERT_EQ(path.object_transforms_at(scene, f)[1], placed) << "frame " << f;
  // Components that differ still interpolate (eye.x), those equal stay (eye.y).
  EXPECT_FLOAT_EQ(path.camera_at(45).eye.x, 0.5f * (0.0535f + 0.278f));
  EXPECT_EQ(path.camera_at(45).eye.y, 0.2730f);
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

Scene with_lights() {
  Scene scene = two_objects();
  PunctualLight lamp, spot, sun;
  lamp.name = "lamp", lamp.position = {1, 2, 3};
  spot.name = "spot", spot.type = LightType::spot, spot.position = {0, 4, 0};
  sun.name = "sun", sun.type = LightType::directional;
  scene.punctual_lights = {lamp, spot, sun};
  return scene;
}

TEST(CameraPath, LightKeysMovePointAndSpotLights) {
  const Scene scene = with_lights();
  const CameraPath path = parse_camera_path(
      "light 4 spot translate 0 -2 0\n"
      "light 0 lamp translate 0 0 0\n"
      "light 10 lamp translate 2 0 -4  # listed after\n",
      "p.txt", scene);
  ASSERT_EQ(path.lights.size(), 3u);
  EXPECT_TRUE(path.moves_lights());
  EXPECT_FALSE(path.moves_objects());
  const auto at5 = path.light_positions_at(scene, 5);
  ASSERT_EQ(at5.size(), 3u);
  EXPECT_FLOAT_EQ(at5[0].x, 2.0f);  // 1 + 2 * 0.5
  EXPECT_FLOAT_EQ(at5[0].y, 2.0f);
  EXPECT_FLOAT_EQ(at5[0].z, 1.0f);  // 3 - 4 * 0.5
  EXPECT_FLOAT_EQ(at5[1].y, 2.0f);  // held after its only key
  EXPECT_EQ(at5[2], scene.punctual_lights[2].position);  // directional: untouched
  EXPECT_EQ(path.light_positions_at(scene, 0)[0], scene.punctual_lights[0].position);
  EXPECT_FLOAT_EQ(path.light_positions_at(scene, 99)[0].z, -1.0f);
  EXPECT_FALSE(parse_camera_path("camera 0 eye 0 0 0 target 1 1 1\n", "p.txt", scene).moves_lights());
}

TEST(CameraPath, BadLightKeysNameTheFileAndLine) {
  const Scene scene = with_lights();
  const struct {
    const char* text;
    const char* problem;
  } bad[] = {
      {"light 0 nobody translate 1 2 3", "no point or spot light named 'nobody'"},
      {"light 0 ball translate 1 2 3", "no point or spot light named 'ball'"},  // an object, not a light
      {"light 0 sun translate 1 2 3", "'sun' is directional"},
      {"light 0 lamp translate 1 2", "three finite numbers"},
      {"light 0 lamp translate 1 x 3", "three finite numbers"},
      {"light 0 lamp translate 1 inf 3", "three finite numbers"},
      {"light 0 lamp translate 1 1e38 3", "out of range"},
      {"light 0 lamp translate 1 2 3 4", "unexpected '4'"},
      {"light 0 lamp rotate 1 2 3", "'translate X Y Z'"},
      {"light 0", "needs the light's name"},
      {"light -2 lamp translate 1 2 3", "frame number"},
  };
  for (const auto& b : bad) {
    try {
      parse_camera_path(std::string("light 0 lamp translate 0 0 0\n") + b.text + "\n", "path.txt", scene);
      ADD_FAILURE() << "accepted: " << b.text;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("path.txt:2: ", 0), 0u) << what;
      EXPECT_NE(what.find(b.problem), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  }
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

TEST(PathClock, WithoutARateEachFrameIsTheNextPathFrame) {
  PathClock every(0.0, 4, {});
  for (int f = 0; f <= 4; ++f) {
    EXPECT_FALSE(every.done());
    EXPECT_EQ(every.next(1e9 * f), double(f));  // the clock does not matter
    EXPECT_TRUE(every.exact());
  }
  EXPECT_TRUE(every.done());
  EXPECT_EQ(every.frames(), 5);
  PathClock chosen(0.0, 4, {1, 3});  // --frames-at: only those are "exact" (written)
  std::vector<bool> exact;
  while (!chosen.done()) chosen.next(0.0), exact.push_back(chosen.exact());
  EXPECT_EQ(exact, (std::vector<bool>{false, true, false, true, false}));
}

TEST(PathClock, TheClockPlacesFramesAndDrawsEachChosenKeyExactlyOnce) {
  // 10 path frames a second: 100 ms per path frame.
  PathClock clock(10.0, 59, {15, 16, 40, 59});
  EXPECT_DOUBLE_EQ(clock.next(0.0), 0.0);
  EXPECT_FALSE(clock.exact());
  EXPECT_DOUBLE_EQ(clock.next(250.0), 2.5);  // between keys: where the clock is
  EXPECT_FALSE(clock.exact());
  EXPECT_DOUBLE_EQ(clock.next(1690.0), 15.0);  // passed 15 and 16 in one frame (a slow loop): 15 now ...
  EXPECT_TRUE(clock.exact());
  EXPECT_DOUBLE_EQ(clock.next(1700.0), 16.0);  // ... and 16 next, although the clock is at 17
  EXPECT_TRUE(clock.exact());
  EXPECT_DOUBLE_EQ(clock.next(1750.0), 17.5);
  clock.pause(1000.0);                          // time spent writing a file does not move the camera
  EXPECT_DOUBLE_EQ(clock.next(2800.0), 18.0);
  EXPECT_FALSE(clock.done());
  EXPECT_DOUBLE_EQ(clock.next(1e6), 40.0);  // far past the end: the keys left, in order, then the end
  EXPECT_FALSE(clock.done());
  EXPECT_DOUBLE_EQ(clock.next(1e6), 59.0);
  EXPECT_TRUE(clock.exact());
  EXPECT_TRUE(clock.done());
  EXPECT_EQ(clock.frames(), 8);
}

TEST(PathClock, PositionsNeverDecreaseAndTheRunEndsAtTheLastFrame) {
  std::mt19937 random(7);
  for (int run = 0; run < 200; ++run) {
    const int last = int(random() % 80);
    std::vector<int> keys;
    for (int k = 0; k <= last; ++k)
      if (random() % 8 == 0) keys.push_back(k);
    const double rate = std::exp(std::uniform_real_distribution<double>(-2.0, 8.0)(random));
    PathClock clock(rate, last, keys);
    double t = 0.0, before = 0.0;
    std::vector<int> drawn;
    int frames = 0;
    while (!clock.done()) {
      t += std::uniform_real_distribution<double>(0.0, 300.0)(random);
      if (random() % 4 == 0) clock.pause(std::uniform_real_distribution<double>(0.0, 50.0)(random)), t += 50.0;
      const double at = clock.next(t);
      ASSERT_GE(at, before);
      ASSERT_LE(at, double(last));
      if (clock.exact()) {
        ASSERT_EQ(double(int(at)), at);
        drawn.push_back(int(at));
      }
      before = at;
      ASSERT_LT(++frames, 1000000);
    }
    EXPECT_EQ(before, double(last));
    EXPECT_EQ(drawn, keys);  // every chosen key, once, in order
  }
}

}  // namespace
}  // namespace epi::render

// Viewer navigation (orbit, pan, dolly, fly, frame) and script parsing, without a window.
#include <gtest/gtest.h>

#include <cmath>

#include "navigation.h"
#include "render/camera_path.h"
#include "script.h"

namespace epi::viewer {
namespace {

Camera test_camera() {
  Camera c;
  c.eye = {0.0f, 1.0f, 5.0f};
  c.target = {0.0f, 1.0f, 0.0f};
  c.up = {0.0f, 1.0f, 0.0f};
  c.yfov_degrees = 40.0f;
  return c;
}

TEST(Navigation, OrbitTurnsTheEyeAboutTheTarget) {
  Camera c = test_camera();
  orbit(c, 300.0f, 0.0f);  // 90 degrees of yaw
  EXPECT_EQ(c.target, test_camera().target);
  EXPECT_NEAR(glm::distance(c.eye, c.target), 5.0f, 1e-4f);
  EXPECT_NEAR(c.eye.y, 1.0f, 1e-4f) << "yaw keeps the height";
  EXPECT_NEAR(std::abs(c.eye.x), 5.0f, 1e-3f);
  // Dragging down shows the scene from higher up; the pitch stops short of the pole.
  Camera d = test_camera();
  orbit(d, 0.0f, 100.0f);
  EXPECT_GT(d.eye.y, 1.0f);
  EXPECT_NEAR(glm::distance(d.eye, d.target), 5.0f, 1e-4f);
  orbit(d, 0.0f, 10000.0f);
  const float polar = glm::degrees(std::acos(glm::dot(glm::normalize(d.eye - d.target), glm::vec3(0, 1, 0))));
  EXPECT_NEAR(polar, 1.0f, 1e-2f);
}

TEST(Navigation, PanMovesEyeAndTargetTogetherWithTheMouse) {
  Camera c = test_camera();
  pan(c, 100.0f, 0.0f, 500);
  const glm::vec3 move = c.eye - test_camera().eye;
  EXPECT_LT(glm::length(move - (c.target - test_camera().target)), 1e-5f);
  // 100 px of 500 at distance 5 and 40 degrees: the point at the target's depth follows the mouse.
  EXPECT_NEAR(move.x, -100.0f / 500.0f * 2.0f * 5.0f * std::tan(glm::radians(20.0f)), 1e-4f);
  EXPECT_NEAR(move.y, 0.0f, 1e-6f);
}

TEST(Navigation, DollyScalesTheDistanceAndNeverReachesTheTarget) {
  Camera c = test_camera();
  dolly(c, 2.0f);
  EXPECT_NEAR(glm::distance(c.eye, c.target), 5.0f * kDollyPerStep * kDollyPerStep, 1e-4f);
  dolly(c, -2.0f);
  EXPECT_NEAR(glm::distance(c.eye, c.target), 5.0f, 1e-4f);
  dolly(c, 1000.0f);
  EXPECT_GT(glm::distance(c.eye, c.target), 0.0f);
}

TEST(Navigation, FlyAndLookMoveThroughTheScene) {
  Camera c = test_camera();
  fly(c, {0.0f, 0.0f, 1.0f});
  EXPECT_NEAR(c.eye.z, 4.0f, 1e-5f);
  EXPECT_NEAR(c.target.z, -1.0f, 1e-5f);
  look(c, 300.0f, 0.0f);  // 90 degrees to the right
  EXPECT_EQ(c.eye, glm::vec3(0.0f, 1.0f, 4.0f));
  EXPECT_GT(glm::normalize(c.target - c.eye).x, 0.99f);
}

TEST(Navigation, FrameBoundsSeesTheWholeScene) {
  Camera c = test_camera();
  Bounds b;
  b.extend({10.0f, 10.0f, 10.0f});
  b.extend({14.0f, 12.0f, 11.0f});
  frame_bounds(c, b);
  EXPECT_EQ(c.target, glm::vec3(12.0f, 11.0f, 10.5f));
  const float radius = 0.5f * glm::length(b.max - b.min);
  EXPECT_GE(glm::distance(c.eye, c.target) * std::sin(glm::radians(20.0f)), radius);
}

TEST(Script, ParsesEveryCommand) {
  const auto s = parse_script(
      "# a comment\nwait 3\nkey F\nkey ctrl+1\nhold W 5\nclick left 10 20\ndrag middle 1 2 3 4\ndrag right 1 2 3 4 7\n"
      "move 5 6\nscroll -2\nscreenshot a.png\nwindow-screenshot b.png  # trailing\n\nquit\n",
      "s.txt");
  ASSERT_EQ(s.size(), 12u);
  using K = ScriptCommand::Kind;
  EXPECT_EQ(s[0].kind, K::wait);
  EXPECT_EQ(s[0].frames, 3);
  EXPECT_EQ(s[1].key, key_code("F"));
  EXPECT_NE(s[2].mods, 0);
  EXPECT_EQ(s[2].key, key_code("1"));
  EXPECT_EQ(s[3].frames, 5);
  EXPECT_EQ(s[4].button, Button::left);
  EXPECT_EQ(s[4].y0, 20.0f);
  EXPECT_EQ(s[5].frames, 10);
  EXPECT_EQ(s[6].frames, 7);
  EXPECT_EQ(s[6].button, Button::right);
  EXPECT_EQ(s[8].scroll, -2.0f);
  EXPECT_EQ(s[9].file, "a.png");
  EXPECT_EQ(s[10].kind, K::window_screenshot);
  EXPECT_EQ(s[11].kind, K::quit);
  EXPECT_EQ(s[11].line, 14);
}

TEST(Script, ErrorsNameTheFileAndLine) {
  const struct {
    const char* text;
    const char* message;
  } cases[] = {{"wait 1\njump 3\n", "s.txt:2: unknown command 'jump'"},
               {"wait -1\n", "s.txt:1: 'wait': a frame count must be a whole number >= 0"},
               {"wait x\n", "s.txt:1: 'wait': a frame count must be a finite number, got 'x'"},
               {"key NOPE\n", "s.txt:1: unknown key 'NOPE'"},
               {"click up 1 2\n", "s.txt:1: unknown button 'up'"},
               {"click left 1\n", "s.txt:1: 'click' needs Y"},
               {"drag left 1 2 3 4 0\n", "s.txt:1: 'drag' needs at least 1 frame"},
               {"scroll 1 2\n", "s.txt:1: unexpected '2' after 'scroll'"},
               {"screenshot\n", "s.txt:1: 'screenshot' needs a file name"},
               {"scroll inf\n", "s.txt:1: 'scroll': DY must be a finite number, got 'inf'"},
               {"resize 0 10\n", "s.txt:1: 'resize' needs whole numbers in 1..16384"}};
  for (const auto& c : cases) {
    try {
      parse_script(c.text, "s.txt");
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind(c.message, 0), 0u) << e.what();
    }
  }
  EXPECT_THROW(read_script("/no/such/script.txt"), std::runtime_error);
}

TEST(CameraPathFormat, PrintedKeysParseBackToTheSameCamera) {
  Scene scene;
  scene.cameras.push_back(test_camera());
  Object box;
  box.name = "box";
  scene.objects.push_back(box);
  Camera c = test_camera();
  c.eye = {0.1f, 1.0f / 3.0f, -7.25e-3f};
  c.yfov_degrees = 33.3f;
  const std::string text = render::format_camera_key(2.5, c) + "\n" + render::format_object_key(4, "box", {0.5f, 0.0f, 1.0f / 7.0f}) + "\n";
  const render::CameraPath path = render::parse_camera_path(text, "p.txt", scene);
  ASSERT_EQ(path.cameras.size(), 1u);
  EXPECT_EQ(path.cameras[0].frame, 2.5);
  EXPECT_EQ(path.cameras[0].camera.eye, c.eye);
  EXPECT_EQ(path.cameras[0].camera.target, c.target);
  EXPECT_EQ(path.cameras[0].camera.yfov_degrees, c.yfov_degrees);
  ASSERT_EQ(path.objects.size(), 1u);
  EXPECT_EQ(path.objects[0].translate, glm::vec3(0.5f, 0.0f, 1.0f / 7.0f));
}

}  // namespace
}  // namespace epi::viewer

// epi-viewer as a user meets it, in a real window on a virtual X server (Xvfb, Mesa llvmpipe):
// the still view equals `epi render`, orbit/pan/dolly move the printed camera and the image, a
// dragged object moves its pixels and its shadow edges, every stage view differs, a held shader
// never stalls the window, and bad input fails exactly as in the CLI, before any window.
//
// One Xvfb per test process, on a display number the server picks itself (-displayfd), so
// parallel ctest runs never collide. Without Xvfb the window tests are skipped with a message.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <poll.h>
#include <regex>
#include <set>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include <glm/glm.hpp>

#include "image_io.h"

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------------
// The X server.

struct XServer : ::testing::Environment {
  pid_t pid = -1;
  std::string display;  // ":N", empty when none could be started
  std::string why_not;

  void SetUp() override {
    int fds[2];
    if (::pipe(fds) != 0) {
      why_not = "pipe failed";
      return;
    }
    pid = ::fork();
    if (pid == 0) {
      ::close(fds[0]);
      const std::string fd = std::to_string(fds[1]);
      std::freopen("/dev/null", "w", stdout);
      std::freopen("/dev/null", "w", stderr);
      ::execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24", "-nolisten", "tcp", nullptr);
      ::_exit(127);
    }
    ::close(fds[1]);
    std::string number;
    pollfd p{fds[0], POLLIN, 0};
    char c;
    while (::poll(&p, 1, 20000) > 0 && ::read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    ::close(fds[0]);
    if (number.empty()) {
      why_not = "Xvfb could not be started (is the xvfb package installed?)";
      if (pid > 0) ::kill(pid, SIGTERM), ::waitpid(pid, nullptr, 0);
      pid = -1;
      return;
    }
    display = ":" + number;
  }
  void TearDown() override {
    if (pid > 0) ::kill(pid, SIGTERM), ::waitpid(pid, nullptr, 0);
  }
};
XServer* const kX = static_cast<XServer*>(::testing::AddGlobalTestEnvironment(new XServer));

#define REQUIRE_DISPLAY()                                                          \
  do {                                                                             \
    if (kX->display.empty()) GTEST_SKIP() << "no X server: " << kX->why_not;       \
  } while (0)

// ---------------------------------------------------------------------------------------------
// Running the programs.

struct ProgramRun {
  int exit_code = -1;
  int signal = 0;
  std::string out;  // stdout and stderr together
};

ProgramRun run(const std::string& command) {
  ProgramRun r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  if (WIFEXITED(status)) {
    r.exit_code = WEXITSTATUS(status);
    if (r.exit_code > 128 && r.exit_code < 128 + 64) r.signal = r.exit_code - 128, r.exit_code = -1;
  } else if (WIFSIGNALED(status)) {
    r.signal = WTERMSIG(status);
  }
  return r;
}

const std::string kBin = std::string(EPI_BINARY_DIR) + "/bin/";
const std::string kCornell = std::string(EPI_SOURCE_DIR) + "/scenes/cornell_box.gltf";

// epi-viewer in the test's X server (timeout: a hang fails instead of blocking the suite).
ProgramRun viewer(const std::string& args) {
  return run("DISPLAY=" + kX->display + " timeout 120 " + kBin + "epi-viewer " + args);
}
ProgramRun viewer_without_display(const std::string& args) { return run("env -u DISPLAY timeout 60 " + kBin + "epi-viewer " + args); }
ProgramRun epi(const std::string& args) { return run("timeout 120 " + kBin + "epi " + args); }

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("epi-viewer-test-" + std::to_string(::getpid())) / name;
  fs::create_directories(dir);
  return dir;
}
struct RemoveScratch : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(fs::temp_directory_path() / ("epi-viewer-test-" + std::to_string(::getpid())), ec);
  }
};
const auto* const kRemoveScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

void write_file(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

int count_lines(const std::string& text) { return int(std::count(text.begin(), text.end(), '\n')); }

double mean_abs_diff(const epi::RgbImage& a, const epi::RgbImage& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
  return sum / double(a.pixels.size());
}

struct PrintedCamera {
  glm::vec3 eye, target;
};
// Every "camera 0 eye X Y Z target X Y Z ..." line the viewer printed (key C).
std::vector<PrintedCamera> printed_cameras(const std::string& out) {
  std::vector<PrintedCamera> cams;
  const std::regex line(R"((?:^|\n)camera 0 eye (\S+) (\S+) (\S+) target (\S+) (\S+) (\S+) up)");
  for (auto it = std::sregex_iterator(out.begin(), out.end(), line); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    cams.push_back({{std::stof(m[1]), std::stof(m[2]), std::stof(m[3])}, {std::stof(m[4]), std::stof(m[5]), std::stof(m[6])}});
  }
  return cams;
}

const std::string kStill = " --eye 0.278,0.273,-0.8 --target 0.278,0.273,0.2 --size 96x72";

// ---------------------------------------------------------------------------------------------

// With --sync both programs run the same frame loop from the same seed: the tolerance is zero.
// Asynchronous, the viewer's image after enough frames is within 0.02 (mean absolute, linear)
// of the synchronous one: what differs is only which pixels the shader reached in time.
TEST(ViewerWindow, StillViewMatchesEpiRender) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("still");
  const ProgramRun r = epi("render " + kCornell + kStill + " --sync --frames 12 --quiet -o " + (dir / "r.exr").string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const ProgramRun v = viewer(kCornell + kStill + " --sync --frames 12 --screenshot " + (dir / "v.exr").string());
  ASSERT_EQ(v.exit_code, 0) << v.out;
  const epi::RgbImage a = epi::read_image(dir / "r.exr"), b = epi::read_image(dir / "v.exr");
  ASSERT_EQ(a.width, 96);
  ASSERT_EQ(b.width, 96);
  ASSERT_EQ(b.height, 72);
  EXPECT_EQ(a.pixels, b.pixels) << "mean difference " << mean_abs_diff(a, b);
  // PNG too: the same tone map and bytes as `epi render -o x.png`.
  ASSERT_EQ(epi("render " + kCornell + kStill + " --sync --frames 12 --quiet -o " + (dir / "r.png").string()).exit_code, 0);
  ASSERT_EQ(viewer(kCornell + kStill + " --sync --frames 12 --screenshot " + (dir / "v.png").string()).exit_code, 0);
  std::ifstream pa(dir / "r.png", std::ios::binary), pb(dir / "v.png", std::ios::binary);
  EXPECT_TRUE(std::equal(std::istreambuf_iterator<char>(pa), {}, std::istreambuf_iterator<char>(pb)));

  const ProgramRun sync60 = epi("render " + kCornell + kStill + " --sync --frames 120 --quiet -o " + (dir / "s.exr").string());
  ASSERT_EQ(sync60.exit_code, 0) << sync60.out;
  const ProgramRun async = viewer(kCornell + kStill + " --frames 120 --screenshot " + (dir / "a.exr").string());
  ASSERT_EQ(async.exit_code, 0) << async.out;
  EXPECT_LT(mean_abs_diff(epi::read_image(dir / "s.exr"), epi::read_image(dir / "a.exr")), 0.02);
}

// A camera path (camera and an object moving) plays frame by frame as in `epi render`.
TEST(ViewerWindow, CameraPathPlaysAsInEpiRender) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("path");
  write_file(dir / "p.txt", "camera 0 eye 0.278 0.273 -0.8 target 0.278 0.273 0.2\ncamera 9 eye 0.5 0.35 -0.7 target 0.278 0.273 0.2\n"
                            "object 0 short_block translate 0 0 0\nobject 9 short_block translate -0.1 0 0.05\n");
  std::vector<epi::RgbImage> frames;
  for (const std::string extra : {"", " --sparse-effort 4"}) {  // a flag of the frame loop reaches the window's too
    const std::string args = " --camera-path " + (dir / "p.txt").string() + " --size 96x72 --sync --frames 10" + extra;
    ASSERT_EQ(epi("render " + kCornell + args + " --quiet -o " + (dir / "r.exr").string()).exit_code, 0);
    const ProgramRun v = viewer(kCornell + args + " --screenshot " + (dir / "v.exr").string());
    ASSERT_EQ(v.exit_code, 0) << v.out;
    const epi::RgbImage a = epi::read_image(dir / "r.exr"), b = epi::read_image(dir / "v.exr");
    EXPECT_EQ(a.pixels, b.pixels) << extra << ": mean difference " << mean_abs_diff(a, b);
    frames.push_back(b);
  }
  EXPECT_NE(frames[0].pixels, frames[1].pixels);
}

// What the window shows is the rendered image: the frame thread's pixel buffer, uploaded and
// blitted the right way up, equals the screenshot file up to the display table's rounding.
TEST(ViewerWindow, TheWindowShowsTheRenderedImage) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("window");
  write_file(dir / "s.txt", "wait 20\nkey TAB\nwait 5\nscreenshot " + (dir / "image.png").string() + "\nwindow-screenshot " +
                                (dir / "window.png").string() + "\n");
  const ProgramRun v = viewer(kCornell + " --size 160x120 --sync --frames 6 --script " + (dir / "s.txt").string());
  ASSERT_EQ(v.exit_code, 0) << v.out;
  const epi::RgbImage image = epi::read_image(dir / "image.png"), window = epi::read_image(dir / "window.png");
  ASSERT_EQ(window.width, 160);
  ASSERT_EQ(window.height, 120);
  // Panel and overlay hidden (Tab): the whole window.
  float worst = 0.0f;
  double lit = 0.0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(image.at(x, y)[c] - window.at(x, y)[c]));
        lit += image.at(x, y)[c];
      }
  EXPECT_GT(lit, 1.0) << "the image is not black";
  EXPECT_LT(worst, 0.01f) << "linear: one 8-bit level at most (the display's sRGB table rounds)";
}

TEST(ViewerWindow, OrbitPanAndDollyMoveTheCameraAndTheImage) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("navigate");
  const std::string d = dir.string() + "/";
  write_file(dir / "s.txt", "wait 3\nkey C\nscreenshot " + d + "0.exr\n"
                            "drag left 40 36 70 36 5\nwait 3\nkey C\nscreenshot " + d + "1.exr\n"
                            "drag middle 48 36 48 56 5\nwait 3\nkey C\nscreenshot " + d + "2.exr\n"
                            "scroll 2\nwait 3\nkey C\nscreenshot " + d + "3.exr\n"
                            "key R\nwait 3\nkey C\n"
                            "key CTRL+1\ndrag left 40 36 60 50 4\nkey 1\nkey C\n"
                            "hold W 12\nwait 1\nkey C\n");
  const ProgramRun v = viewer(kCornell + kStill + " --sync --script " + (dir / "s.txt").string());
  ASSERT_EQ(v.exit_code, 0) << v.out;
  const std::vector<PrintedCamera> c = printed_cameras(v.out);
  ASSERT_EQ(c.size(), 7u) << v.out;
  // Orbit: 30 px of left drag turn the eye 9 degrees about the target; the target stays.
  EXPECT_LT(glm::distance(c[1].target, c[0].target), 1e-5f);
  EXPECT_NEAR(glm::distance(c[1].eye, c[1].target), glm::distance(c[0].eye, c[0].target), 1e-4f);
  const glm::vec3 before = glm::normalize(c[0].eye - c[0].target), after = glm::normalize(c[1].eye - c[1].target);
  EXPECT_NEAR(glm::degrees(std::acos(glm::dot(before, after))), 9.0f, 0.1f);
  // Pan: eye and target move together, by 20 px worth at the target's depth.
  const glm::vec3 move = c[2].target - c[1].target;
  EXPECT_LT(glm::length((c[2].eye - c[1].eye) - move), 1e-5f);
  const float expect = 20.0f / 72.0f * 2.0f * glm::distance(c[1].eye, c[1].target) * std::tan(glm::radians(0.5f * 39.3076477f));
  EXPECT_NEAR(glm::length(move), expect, 1e-3f);
  EXPECT_GT(move.y, 0.0f) << "dragging down moves the view up: the scene follows the mouse";
  // Dolly: two wheel steps towards the target.
  EXPECT_NEAR(glm::distance(c[3].eye, c[3].target), 0.81f * glm::distance(c[2].eye, c[2].target), 1e-4f);
  EXPECT_LT(glm::distance(c[3].target, c[2].target), 1e-5f);
  // Reset; a bookmark stored there (Ctrl+1) brings the camera back after an orbit (1).
  EXPECT_LT(glm::distance(c[4].eye, c[0].eye), 1e-5f);
  EXPECT_LT(glm::distance(c[5].eye, c[0].eye), 1e-5f);
  EXPECT_LT(glm::distance(c[5].target, c[0].target), 1e-5f);
  EXPECT_NE(v.out.find("bookmark 1: camera 0 eye"), std::string::npos);
  // Fly: W moves eye and target forward together.
  const glm::vec3 fly = c[6].eye - c[5].eye;
  EXPECT_GT(glm::length(fly), 1e-3f);
  EXPECT_LT(glm::length(fly - (c[6].target - c[5].target)), 1e-4f);
  EXPECT_GT(glm::dot(glm::normalize(fly), glm::normalize(c[5].target - c[5].eye)), 0.999f);
  // Each move changes the image.
  for (int k = 1; k <= 3; ++k)
    EXPECT_GT(mean_abs_diff(epi::read_image(dir / (std::to_string(k - 1) + ".exr")), epi::read_image(dir / (std::to_string(k) + ".exr"))), 0.005)
        << "move " << k;
}

// The edges view's pixels of one kind colour (linear, as session.cpp draws them).
std::set<size_t> pixels_of(const epi::RgbImage& image, glm::vec3 color) {
  std::set<size_t> out;
  for (size_t i = 0; i * 3 < image.pixels.size(); ++i)
    if (glm::distance(glm::vec3(image.pixels[3 * i], image.pixels[3 * i + 1], image.pixels[3 * i + 2]), color) < 1e-3f) out.insert(i);
  return out;
}

TEST(ViewerWindow, DraggingAnObjectMovesItsPixelsAndItsShadowEdges) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("drag");
  const std::string d = dir.string() + "/";
  // rooms.gltf: the vase on the table is near (203, 150) of the default 320x240 view; the floor
  // lamp casts its hard shadow edges on the table.
  const std::string rooms = std::string(EPI_SOURCE_DIR) + "/scenes/rooms.gltf";
  write_file(dir / "s.txt", "wait 10\nscreenshot " + d + "before.exr\nkey F3\nscreenshot " + d + "edges_before.exr\nkey F1\n"
                            "click left 203 150\nwait 2\ndrag left 203 150 163 150 6\nwait 20\nscreenshot " + d + "after.exr\n"
                            "key F3\nwait 2\nscreenshot " + d + "edges_after.exr\nkey C\n");
  const ProgramRun v = viewer(rooms + " --size 320x240 --sync --script " + (dir / "s.txt").string());
  ASSERT_EQ(v.exit_code, 0) << v.out;
  const epi::RgbImage before = epi::read_image(dir / "before.exr"), after = epi::read_image(dir / "after.exr");
  EXPECT_NE(v.out.find("\nobject 0 vase translate "), std::string::npos) << v.out;
  // The vase moved left: pixels where it was and where it went changed; the far corner did not.
  auto diff_in = [&](int x0, int y0, int x1, int y1) {
    double sum = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        for (int c = 0; c < 3; ++c) sum += std::abs(before.at(x, y)[c] - after.at(x, y)[c]);
    return sum / double((x1 - x0) * (y1 - y0) * 3);
  };
  EXPECT_GT(diff_in(150, 125, 215, 185), 0.01) << "the vase's footprint";
  EXPECT_LT(diff_in(0, 0, 20, 20), 0.5 * diff_in(150, 125, 215, 185)) << "the top left corner is (nearly) untouched";
  // Shadow edges (umbral, penumbral, shadow kinds) moved with their blocker: on the table top,
  // around the vase, many changed; elsewhere (other objects' shadows) a smaller share did.
  const epi::RgbImage eb = epi::read_image(dir / "edges_before.exr"), ea = epi::read_image(dir / "edges_after.exr");
  std::set<size_t> sb, sa;
  for (glm::vec3 color : {glm::vec3(1.0f, 0.1f, 0.05f), glm::vec3(1.0f, 0.45f, 0.0f), glm::vec3(0.25f, 0.35f, 1.0f)}) {
    const auto b = pixels_of(eb, color), a = pixels_of(ea, color);
    sb.insert(b.begin(), b.end()), sa.insert(a.begin(), a.end());
  }
  auto near_vase = [](size_t i) {
    const size_t x = i % 320, y = i / 320;
    return x >= 120 && x < 280 && y >= 120 && y < 240;
  };
  size_t changed[2] = {0, 0}, total[2] = {0, 0};  // [near the vase, elsewhere]
  for (size_t i = 0; i < 320 * 240; ++i) {
    const bool b = sb.count(i), a = sa.count(i);
    if (!a && !b) continue;
    const int where = near_vase(i) ? 0 : 1;
    ++total[where], changed[where] += a != b;
  }
  ASSERT_GT(total[0], 20u) << "shadow edges near the vase";
  EXPECT_GT(changed[0], 40u) << "shadow-edge pixels near the vase that changed";
  EXPECT_GT(double(changed[0]) / double(total[0]), 2.0 * double(changed[1]) / double(std::max<size_t>(total[1], 1)))
      << changed[0] << "/" << total[0] << " near the vase, " << changed[1] << "/" << total[1] << " elsewhere";
}

// A point light dragged by its marker moves (the printed key), its shadow edges follow, and the
// recording (K ... K) is a camera-path file `epi render` plays.
TEST(ViewerWindow, DraggingALightMovesItsShadowEdgesAndIsRecorded) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("light");
  const std::string d = dir.string() + "/";
  const std::string chains = std::string(EPI_SOURCE_DIR) + "/scenes/chains.gltf";
  const std::string view = " --size 320x240 --eye 4,3.5,4 --target 0,0.8,0 --sync";
  // Where the point light's marker is: C prints it.
  write_file(dir / "where.txt", "wait 2\nkey C\n");
  const ProgramRun where = viewer(chains + view + " --script " + d + "where.txt");
  ASSERT_EQ(where.exit_code, 0) << where.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(where.out, m, std::regex(R"(# light 'point' at \S+ \S+ \S+, marker at window pixel (\S+) (\S+))"))) << where.out;
  const int x = std::stoi(m[1]), y = std::stoi(m[2]);
  ASSERT_TRUE(x > 0 && y > 0 && x < 320 && y < 240) << where.out;
  write_file(dir / "s.txt", "wait 10\nkey F3\nscreenshot " + d + "e0.exr\nkey F1\nkey K\n"
                            "drag left " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(x + 40) + " " +
                            std::to_string(y) + " 6\nwait 20\nkey K\nkey C\nkey F3\nwait 5\nscreenshot " + d + "e1.exr\n");
  const ProgramRun v = viewer(chains + view + " --record " + d + "path.txt --script " + d + "s.txt");
  ASSERT_EQ(v.exit_code, 0) << v.out;
  ASSERT_TRUE(std::regex_search(v.out, m, std::regex(R"((?:^|\n)light 0 point translate (\S+) (\S+) (\S+))"))) << v.out;
  EXPECT_GT(glm::length(glm::vec3(std::stof(m[1]), std::stof(m[2]), std::stof(m[3]))), 0.05f) << v.out;
  // The shadow edges (umbral, penumbral, shadow kinds) changed.
  const epi::RgbImage e0 = epi::read_image(dir / "e0.exr"), e1 = epi::read_image(dir / "e1.exr");
  std::set<size_t> s0, s1;
  for (glm::vec3 color : {glm::vec3(1.0f, 0.1f, 0.05f), glm::vec3(1.0f, 0.45f, 0.0f), glm::vec3(0.25f, 0.35f, 1.0f)}) {
    const auto a = pixels_of(e0, color), b = pixels_of(e1, color);
    s0.insert(a.begin(), a.end()), s1.insert(b.begin(), b.end());
  }
  ASSERT_GT(s0.size(), 20u);
  ASSERT_GT(s1.size(), 20u);
  size_t common = 0;
  for (size_t i : s0) common += s1.count(i);
  EXPECT_LT(double(common), 0.8 * double(std::min(s0.size(), s1.size())));
  // The recording: camera keys and the light's keys, played by epi render.
  std::ifstream in(dir / "path.txt");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("\ncamera "), std::string::npos) << text;
  EXPECT_NE(text.find("\nlight "), std::string::npos) << text;
  const ProgramRun play = epi("render " + chains + " --camera-path " + d + "path.txt --frames 3 --size 32x24 --sync --quiet -o " + d + "p.png");
  EXPECT_EQ(play.exit_code, 0) << play.out << "\n" << text;
}

TEST(ViewerWindow, TheRendererFollowsTheWindowSize) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("resize");
  write_file(dir / "s.txt", "wait 3\nscreenshot " + (dir / "a.exr").string() + "\nresize 128 80\nwait 30\nscreenshot " +
                                (dir / "b.exr").string() + "\n");
  const ProgramRun v = viewer(kCornell + kStill + " --script " + (dir / "s.txt").string());
  ASSERT_EQ(v.exit_code, 0) << v.out;
  const epi::RgbImage a = epi::read_image(dir / "a.exr"), b = epi::read_image(dir / "b.exr");
  EXPECT_EQ(a.width, 96);
  EXPECT_EQ(a.height, 72);
  EXPECT_EQ(b.width, 128);
  EXPECT_EQ(b.height, 80);
}

// --render-scale 0.5: the renderer renders half the window's width and height (screenshots are that
// size, also after a resize), and the window shows the frame scaled up bilinearly: every window
// pixel lies between the four rendered pixels around its centre, and many strictly between
// (a nearest-neighbour blow-up would repeat one of them).
TEST(ViewerWindow, RenderScaleRendersFewerPixelsAndScalesThemUp) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("render-scale");
  write_file(dir / "s.txt", "wait 20\nkey TAB\nwait 5\nscreenshot " + (dir / "image.png").string() + "\nwindow-screenshot " +
                                (dir / "window.png").string() + "\n");
  const ProgramRun v = viewer(kCornell + " --size 160x120 --render-scale 0.5 --sync --frames 6 --script " + (dir / "s.txt").string());
  ASSERT_EQ(v.exit_code, 0) << v.out;
  const epi::RgbImage image = epi::read_image(dir / "image.png"), window = epi::read_image(dir / "window.png");
  ASSERT_EQ(image.width, 80);
  ASSERT_EQ(image.height, 60);
  ASSERT_EQ(window.width, 160);
  ASSERT_EQ(window.height, 120);
  float worst = 0.0f;
  int between = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      // The window pixel's centre in the image: (x + 0.5) / 2 - 0.5, between pixels x0 and x0 + 1.
      const float sx = std::clamp((float(x) + 0.5f) * 0.5f - 0.5f, 0.0f, 79.0f), sy = std::clamp((float(y) + 0.5f) * 0.5f - 0.5f, 0.0f, 59.0f);
      const int x0 = int(sx), y0 = int(sy), x1 = std::min(79, x0 + 1), y1 = std::min(59, y0 + 1);
      bool strictly = false;
      for (int c = 0; c < 3; ++c) {
        const float corners[4] = {image.at(x0, y0)[c], image.at(x1, y0)[c], image.at(x0, y1)[c], image.at(x1, y1)[c]};
        const float low = *std::min_element(corners, corners + 4), high = *std::max_element(corners, corners + 4);
        const float got = window.at(x, y)[c];
        worst = std::max({worst, low - got, got - high});
        strictly |= got > low + 0.005f && got < high - 0.005f && std::none_of(corners, corners + 4, [&](float k) { return std::abs(k - got) < 0.005f; });
      }
      between += strictly;
    }
  EXPECT_LT(worst, 0.01f) << "a window pixel outside the range of the rendered pixels around it";
  EXPECT_GT(between, 100) << "no bilinear scaling: window pixels repeat rendered ones";
  // A resize keeps the scale (without --frames: the renderer must go on to render the new size).
  write_file(dir / "r.txt", "wait 3\nresize 128 80\nwait 30\nscreenshot " + (dir / "resized.exr").string() + "\n");
  const ProgramRun r = viewer(kCornell + kStill + " --render-scale 0.5 --script " + (dir / "r.txt").string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const epi::RgbImage resized = epi::read_image(dir / "resized.exr");
  EXPECT_EQ(resized.width, 64);
  EXPECT_EQ(resized.height, 40);
}

TEST(ViewerWindow, EveryStageViewIsDistinctAndNonEmpty) {
  REQUIRE_DISPLAY();
  const fs::path dir = temp_dir("stages");
  std::string script = "wait 10\nmove 48 36\n";
  for (int k = 1; k <= 7; ++k) script += "key F" + std::to_string(k) + "\nscreenshot " + (dir / (std::to_string(k) + ".exr")).string() + "\n";
  write_file(dir / "s.txt", script);
  const ProgramRun v = viewer(kCornell + kStill + " --sync --script " + (dir / "s.txt").string());
  ASSERT_EQ(v.exit_code, 0) << v.out;
  std::vector<epi::RgbImage> views;
  for (int k = 1; k <= 7; ++k) {
    views.push_back(epi::read_image(dir / (std::to_string(k) + ".exr")));
    double sum = 0;
    for (float x : views.back().pixels) sum += x;
    EXPECT_GT(sum, 0.0) << "view F" << k << " is empty";
    for (int j = 1; j < k; ++j) EXPECT_GT(mean_abs_diff(views[size_t(j - 1)], views.back()), 1e-4) << "F" << j << " == F" << k;
  }
}

// The shader is held (it never returns a sample): the window still runs at its pace and the
// frame loop keeps delivering frames.
TEST(ViewerWindow, AHeldShaderNeverStallsTheWindow) {
  REQUIRE_DISPLAY();
  const ProgramRun v = viewer(kCornell + kStill + " --test-hold-shader --benchmark 60");
  ASSERT_EQ(v.exit_code, 0) << v.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(v.out, m, std::regex(R"(BENCHMARK_WINDOW_FPS (\S+))"))) << v.out;
  EXPECT_GT(std::stod(m[1]), 10.0) << v.out;
  ASSERT_TRUE(std::regex_search(v.out, m, std::regex(R"(frames shown (\d+))"))) << v.out;
  EXPECT_GE(std::stoi(m[1]), 10) << v.out;
  EXPECT_NE(v.out.find("BENCHMARK_LATENCY_MS"), std::string::npos);
  // The frames reach the texture from the frame thread's pixel buffers (Mesa has
  // GL_ARB_buffer_storage), not by copies on the window thread.
  ASSERT_TRUE(std::regex_search(v.out, m, std::regex(R"(BENCHMARK_DISPLAY_PATH (\d+) frames from the frame thread's pixel buffers, (\d+) copied)"))) << v.out;
  EXPECT_GT(std::stoi(m[1]), std::stoi(m[2])) << v.out;
}

// While the camera is dragged (--benchmark orbits it every window frame) the window redraws only
// for a new frame and the panel's quarter-second refresh, not at --ui-fps: under a software GL
// the redraws of an unchanged frame took most of a core from the renderer (docs/viewer.md,
// "Redraws"). The window runs at 120 a second, faster than the renderer at this size.
TEST(ViewerWindow, NavigationRedrawsOnlyForNewFrames) {
  REQUIRE_DISPLAY();
  const ProgramRun v = viewer(kCornell + " --size 960x540 --ui-fps 120 --benchmark 240");
  ASSERT_EQ(v.exit_code, 0) << v.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(v.out, m, std::regex(R"(window frames over (\S+) s)"))) << v.out;
  const double seconds = std::stod(m[1]);
  ASSERT_TRUE(std::regex_search(v.out, m, std::regex(R"(frames shown (\d+))"))) << v.out;
  const int frames = std::stoi(m[1]);
  ASSERT_TRUE(std::regex_search(v.out, m, std::regex(R"(BENCHMARK_REDRAWS \S+ a second \((\d+) window redraws)"))) << v.out;
  const int redraws = std::stoi(m[1]);
  EXPECT_GT(frames, 0) << v.out;
  EXPECT_GE(redraws, frames * 9 / 10) << v.out;  // every new frame is shown (frames landing in one window frame share it)
  EXPECT_LE(redraws, frames + int(4.0 * seconds) + 2) << v.out;
  EXPECT_LT(frames, int(100.0 * seconds)) << "the renderer kept up with the window: the test proves nothing\n" << v.out;
}

// ---------------------------------------------------------------------------------------------
// Bad input: the CLI's exit code and message, before any window (no display is given at all).

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

TEST(ViewerInput, EveryBadInputOfTheCliFailsTheSameWay) {
  const fs::path dir = temp_dir("bad");
  write_file(dir / "broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": 7}");
  write_file(dir / "path.txt", "camera 0 eye 0 1 3 target 0 1 3\n");
  const std::string out = " -o " + (dir / "o.png").string();
  const std::vector<std::string> cases = {
      kCornell + " --size 12", kCornell + " --spp 0", kCornell + " --mode fast", kCornell + " --eye 1,2,x",
      kCornell + " --fov 0", kCornell + " --area-light-samples 0", kCornell + " --gi-max-bounces -1",
      kCornell + " --exposure big", kCornell + " --bogus 3", kCornell + " --sample-budget 0",
      "/no/such/scene.gltf", (dir / "broken.gltf").string(), kCornell + " --camera-path " + (dir / "path.txt").string(),
      kCornell + " --camera-path " + (dir / "missing.txt").string(), kCornell + " --eye 1,1,1 --target 1,1,1"};
  for (const std::string& args : cases) {
    const ProgramRun c = epi("render " + args + out + " --quiet");
    const ProgramRun v = viewer_without_display(args);
    EXPECT_EQ(v.signal, 0) << args << "\n" << v.out;
    EXPECT_EQ(v.exit_code, c.exit_code) << args << "\n" << v.out << "\n" << c.out;
    EXPECT_NE(c.exit_code, 0) << args;
    ASSERT_EQ(c.out.rfind("epi: ", 0), 0u) << c.out;
    ASSERT_EQ(v.out.rfind("epi-viewer: ", 0), 0u) << v.out;
    EXPECT_EQ(first_line(v.out).substr(12), first_line(c.out).substr(5)) << args;
    if (c.exit_code == 1) {
      EXPECT_EQ(count_lines(v.out), 1) << v.out;
    }
    if (c.exit_code == 2) {
      EXPECT_NE(v.out.find("Usage:"), std::string::npos) << v.out;
    }
    EXPECT_FALSE(fs::exists(dir / "o.png"));
  }
}

TEST(ViewerInput, BadScriptsAndOutputsFailBeforeAnyWindow) {
  const fs::path dir = temp_dir("bad-script");
  write_file(dir / "s.txt", "wait 1\njump 3\n");
  write_file(dir / "t.txt", "screenshot /no/such/folder/x.png\n");
  struct Case {
    std::string args, expect;
  } cases[] = {{"--script " + (dir / "s.txt").string(), "s.txt:2: unknown command 'jump'"},
               {"--script " + (dir / "missing.txt").string(), "missing.txt: cannot open"},
               {"--script " + (dir / "t.txt").string(), "t.txt:1: /no/such/folder/x.png"},
               {"--frames 2 --screenshot " + (dir / "x.xyz").string(), "x.xyz"}};
  for (const Case& c : cases) {
    const ProgramRun v = viewer_without_display(kCornell + " " + c.args);
    EXPECT_EQ(v.exit_code, 1) << c.args << "\n" << v.out;
    EXPECT_EQ(count_lines(v.out), 1) << v.out;
    EXPECT_NE(v.out.find(c.expect), std::string::npos) << v.out;
  }
}

// The viewer's own numeric flags refuse what is out of range or not a number, before any window.
TEST(ViewerInput, BadViewerFlagsFailBeforeAnyWindow) {
  for (const std::string args : {"--render-scale 0", "--render-scale 1.5", "--render-scale nan", "--max-fps nan", "--max-fps -1",
                                 "--ui-fps inf", "--ui-fps 0", "--path-rate 10", "--path-rate -1", "--path-rate nan"}) {
    const ProgramRun v = viewer_without_display(kCornell + " " + args);
    EXPECT_EQ(v.signal, 0) << args << "\n" << v.out;
    EXPECT_EQ(v.exit_code, 2) << args << "\n" << v.out;
    EXPECT_EQ(v.out.rfind("epi-viewer: " + args.substr(0, args.find(' ')), 0), 0u) << args << "\n" << v.out;
    EXPECT_NE(v.out.find("Usage:"), std::string::npos) << v.out;
  }
}

TEST(ViewerInput, NoDisplayGivesOneClearLine) {
  const ProgramRun v = viewer_without_display(kCornell);
  EXPECT_EQ(v.signal, 0) << v.out;
  EXPECT_EQ(v.exit_code, 1) << v.out;
  EXPECT_EQ(count_lines(v.out), 1) << v.out;
  EXPECT_EQ(v.out.rfind("epi-viewer: cannot open a window: ", 0), 0u) << v.out;
  EXPECT_NE(v.out.find("xvfb-run"), std::string::npos) << v.out;
}

}  // namespace

// What a hostile user found (issue 14), end to end through the `epi` program: resource limits
// refused before the work with one line, bad values refused, large but finite coordinates named
// for what they are, messages in epi's words naming the file. docs/reliability.md.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "run_epi.h"

namespace fs = std::filesystem;

namespace {

const std::string kCornell = std::string(EPI_SOURCE_DIR) + "/scenes/cornell_box.gltf";

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("epi-reliability-cli-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

struct RemoveScratch : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(fs::temp_directory_path() / ("epi-reliability-cli-" + std::to_string(::getpid())), ec);
  }
};
const auto* const kRemoveScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

int count_lines(const std::string& text) { return int(std::count(text.begin(), text.end(), '\n')); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A failure of the work: exit 1, one line "epi: <start>...", nothing from a library.
void expect_one_line_failure(const EpiRun& run, const std::string& start) {
  EXPECT_EXIT_CODE(run, kFailed);
  EXPECT_EQ(count_lines(run.out), 1) << run.out;
  EXPECT_EQ(run.out.rfind("epi: " + start, 0), 0u) << run.out;
  for (const char* library_words : {"bad_alloc", "json.exception", "File not found", "Assertion"})
    EXPECT_FALSE(contains(run.out, library_words)) << run.out;
}

// The docs' Catmull-Clark cube (6 quads) at a given level, 12 * 4^level triangles.
fs::path subdivided_cube(int level) {
  const fs::path file = scratch("cube" + std::to_string(level) + ".gltf");
  std::ofstream(file)
      << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
  "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}],
             "extras":{"epi":{"subdivision":{"level":)"
      << level << R"(,"quads":true}}}}],
  "accessors":[{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3"},
               {"bufferView":1,"componentType":5125,"count":36,"type":"SCALAR"}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":96},{"buffer":0,"byteOffset":96,"byteLength":144}],
  "buffers":[{"byteLength":240,"uri":"data:application/octet-stream;base64,AAAAvwAAAL8AAAC/AAAAPwAAAL8AAAC/AAAAvwAAAD8AAAC/AAAAPwAAAD8AAAC/AAAAvwAAAL8AAAA/AAAAPwAAAL8AAAA/AAAAvwAAAD8AAAA/AAAAPwAAAD8AAAA/AQAAAAMAAAAHAAAAAQAAAAcAAAAFAAAAAAAAAAQAAAAGAAAAAAAAAAYAAAACAAAAAgAAAAYAAAAHAAAAAgAAAAcAAAADAAAAAAAAAAEAAAAFAAAAAAAAAAUAAAAEAAAABAAAAAUAAAAHAAAABAAAAAcAAAAGAAAAAAAAAAIAAAADAAAAAAAAAAMAAAABAAAA"}]})";
  return file;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Resource limits: estimated from the input's own numbers, refused before the work, one line.

TEST(Reliability, SubdivisionBeyondTheMemoryLimitIsRefusedAndTheFlagRaisesIt) {
  const fs::path cube = subdivided_cube(6);  // 49152 triangles, ~28 MiB estimated
  const EpiRun refused = run_epi("info " + cube.string() + " --memory-limit 0.01");
  expect_one_line_failure(refused, cube.string() + ": mesh 'mesh0' primitive 0: subdivision level 6");
  EXPECT_TRUE(contains(refused.out, "needs about 28.1 MiB (limit 10.2 MiB; --memory-limit GIB raises it)")) << refused.out;
  const EpiRun accepted = run_epi("info " + cube.string() + " --memory-limit 0.05");
  EXPECT_EXIT_CODE(accepted, 0);
}

TEST(Reliability, AHugeSubdivisionIsRefusedAtOnceByDefault) {
  // The issue's 13 KB file: 256 quads at level 8 took minutes and 7.8 GB; the docs' cube at level 8
  // is the same request in a smaller file (786,432 triangles, 0.44 GiB) and passes; level 8 over
  // 300 cubes' worth is what the default refuses. Here: a cube at level 8 under a 0.1 GiB limit.
  const fs::path cube = subdivided_cube(8);
  const EpiRun run = run_epi("info " + cube.string() + " --memory-limit 0.1");
  expect_one_line_failure(run, cube.string() + ": ");
  EXPECT_TRUE(contains(run.out, "subdivision level 8 (up to 786432 refined triangles in the scene) needs about")) << run.out;
}

TEST(Reliability, PatternAndImageSizesBeyondTheLimitAreRefusedBeforeAllocating) {
  const fs::path pattern = scratch("huge.json");
  std::ofstream(pattern) << R"({"width":16384,"height":16384})";
  const fs::path out = scratch("huge.exr");
  const EpiRun run = run_epi("reconstruct " + pattern.string() + " -o " + out.string());
  expect_one_line_failure(run, pattern.string() + ": a 16384x16384 pattern needs about 12.00 GiB (limit 4.00 GiB");
  EXPECT_FALSE(fs::exists(out));

  const EpiRun frames = run_epi("render " + kCornell + " --size 16384x16384 -o " + out.string());
  expect_one_line_failure(frames, "--size 16384x16384: the frame loop at this size needs about 40.00 GiB");
  const EpiRun reference = run_epi("render " + kCornell + " --mode raytrace --size 4096x4096 --memory-limit 0.2 -o " +
                                   out.string());
  expect_one_line_failure(reference, "--size 4096x4096: a raytrace image needs about 384.0 MiB (limit 204.8 MiB");
  EXPECT_FALSE(fs::exists(out));
}

// ---------------------------------------------------------------------------------------------
// Bad values refused; large but finite values are no "coincide".

TEST(Reliability, BadNumbersAreUsageErrors) {
  for (const char* args : {"--size 4294967328x32", "--size 32x-1", "--size +32x32", "--size 32x32x", "--exposure nan",
                           "--exposure inf", "--sample-budget nan", "--fov nan", "--memory-limit nan",
                           "--memory-limit 0", "--predict-share nan", "--predict-frames inf",
                           "--predict-stride 1e9"}) {
    SCOPED_TRACE(args);
    const EpiRun run = run_epi("render " + kCornell + " " + args + " -o " + scratch("x.png").string());
    EXPECT_EXIT_CODE(run, kUsage);
  }
  const EpiRun density = run_epi("reconstruct " + std::string(EPI_SOURCE_DIR) +
                                 "/tests/epi/patterns/wedges.json --density nan -o " + scratch("x.exr").string());
  EXPECT_EXIT_CODE(density, kUsage);
}

TEST(Reliability, AnUpVectorThatCannotOrientTheCameraIsRefused) {
  const std::string out = scratch("up.png").string();
  for (const char* up : {"0,0,0", "0,0,-3"}) {
    SCOPED_TRACE(up);
    const EpiRun run = run_epi("render " + kCornell + " --mode raytrace --size 8x8 --eye 0,0,5 --target 0,0,0 --up " +
                               up + " -o " + out);
    expect_one_line_failure(run, kCornell + ": camera '");
    EXPECT_TRUE(contains(run.out, "--up")) << run.out;
  }
  const EpiRun path = run_epi("edges " + kCornell + " --eye 0,5,0 --target 0,0,0 --up 0,1,0 -o " + scratch("e.json").string());
  expect_one_line_failure(path, kCornell + ": camera '");
  EXPECT_TRUE(contains(path.out, "up is parallel to the view direction")) << path.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST(Reliability, LargeFiniteCoordinatesAreNamedForWhatTheyAre) {
  const std::string out = scratch("far.png").string();
  // Within the ray tracer's range: renders (the scene is a speck; nothing overflows).
  const EpiRun near = run_epi("render " + kCornell + " --mode raytrace --size 8x8 --quiet --eye 0,0,1e17 --target 0,0,0 -o " + out);
  EXPECT_EXIT_CODE(near, 0);
  // Beyond it: said so, not "coincide or not finite", and no Embree assertion.
  for (const char* eye : {"0,0,1e30", "3e38,0,0"}) {
    SCOPED_TRACE(eye);
    const EpiRun run = run_epi("render " + kCornell + " --mode raytrace --size 8x8 --eye " + std::string(eye) +
                               " --target 0,0,0 -o " + out);
    expect_one_line_failure(run, "");
    EXPECT_TRUE(contains(run.out, "beyond the ray tracer's range")) << run.out;
    EXPECT_FALSE(contains(run.out, "coincide")) << run.out;
  }
}

// ---------------------------------------------------------------------------------------------
// Outputs checked before the work; messages that name the file.

TEST(Reliability, AnUnwritableStatsFolderFailsBeforeTheWork) {
  const std::string out = scratch("stats.png").string();
  const EpiRun run = run_epi("render " + kCornell + " --mode raytrace --size 8x8 --stats /proc/x.json -o " + out);
  expect_one_line_failure(run, "/proc/x.json: cannot create a file in folder '/proc'");
  EXPECT_FALSE(fs::exists(out));
}

TEST(Reliability, AnEmptyOutputNameIsSaidSo) {
  const EpiRun run = run_epi("render " + kCornell + " --mode raytrace --size 8x8 -o \"\"");
  expect_one_line_failure(run, "empty output file name");
}

TEST(Reliability, PatternProblemsNameTheFileInEpisWords) {
  const fs::path overflow = scratch("overflow.json");
  std::ofstream(overflow) << R"({"width":1e400,"height":3})";
  expect_one_line_failure(run_epi("reconstruct " + overflow.string() + " -o " + scratch("o.exr").string()),
                          overflow.string() + ": a number is too large for a double");
  const fs::path folder = scratch("a-folder");
  fs::create_directories(folder);
  expect_one_line_failure(run_epi("reconstruct " + folder.string() + " -o " + scratch("o.exr").string()),
                          folder.string() + ": is a folder, not a pattern file");
}

// ---------------------------------------------------------------------------------------------
// --sync: the same bytes across runs and thread counts, for every render mode.

TEST(Reliability, SyncRendersAreBitIdenticalAcrossRunsAndThreadCounts) {
  const std::string chains = std::string(EPI_SOURCE_DIR) + "/scenes/chains.gltf";
  const fs::path path = scratch("moving.txt");  // camera, object and light all move
  std::ofstream(path) << "camera 0 eye 0 1.5 4 target 0 0.4 0\ncamera 5 eye 2 1.2 3 target 0 0.4 0\n"
                         "object 0 red_chain_0 translate 0 0 0\nobject 5 red_chain_0 translate 0.3 0 0.1\n"
                         "light 0 point translate 0 0 0\nlight 5 point translate -0.4 0.1 0.3\n";
  struct Mode {
    const char* mode;
    std::string extra;
  };
  const Mode modes[] = {{"epi", " --frames 6 --camera-path " + path.string()},
                        {"rendercache", " --frames 6 --camera-path " + path.string()},
                        {"epi", " --frames 4 --shader glossy --glossy-samples 2"},
                        {"raytrace", ""},
                        {"reference", " --spp 2 --shader gi --gi-paths 1"}};
  for (const Mode& m : modes) {
    SCOPED_TRACE(std::string(m.mode) + m.extra);
    std::string first;
    int run_index = 0;
    for (const char* threads : {"1", "2", "3", "2"}) {  // 2 twice: the same thread count, run again
      const fs::path out = scratch("sync" + std::to_string(run_index++) + ".exr");
      const EpiRun run = run_epi("render " + chains + " --mode " + m.mode + m.extra +
                                 " --sync --seed 9 --size 40x32 --sample-budget 0.05 --area-light-samples 2 --quiet "
                                 "--threads " + threads + " -o " + out.string());
      ASSERT_EXIT_CODE(run, 0);
      std::ifstream in(out, std::ios::binary);
      const std::string bytes{std::istreambuf_iterator<char>(in), {}};
      ASSERT_GT(bytes.size(), 500u);
      if (first.empty()) first = bytes;
      else EXPECT_TRUE(bytes == first) << "--threads " << threads << " gives other bytes than --threads 1";
    }
  }
}

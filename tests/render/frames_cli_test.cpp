// `epi render --mode epi|rendercache` as a user meets it: reproducible --sync output, the stats
// JSON of the issue, --frames-out, camera path files, and clean one-line errors.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "render/frame_stages.h"
#include "run_epi.h"  // tests/cli
#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace {


fs::path temp_dir() {
  fs::path dir = fs::temp_directory_path() / ("epi-frames-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

const std::string kScene = std::string(EPI_SOURCE_DIR) + "/scenes/cornell_box.gltf";
const std::string kSmall = " --size 48x40 --frames 4 --sample-budget 0.05 --quiet";

TEST(FramesCli, SyncRunsGiveTheSameBytesAndTheStatsOfTheIssue) {
  const fs::path dir = temp_dir();
  for (const char* mode : {"epi", "rendercache"}) {
    const std::string base = "render " + kScene + " --mode " + mode + kSmall + " --sync --seed 5";
    const EpiRun a = run_epi(base + " -o " + (dir / "a.png").string() + " --stats " + (dir / "a.json").string() +
                          " --frames-out " + (dir / "f%03d.exr").string());
    ASSERT_EQ(a.exit_code, 0) << a.out;
    const EpiRun b = run_epi(base + " -o " + (dir / "b.png").string());
    ASSERT_EQ(b.exit_code, 0) << b.out;
    EXPECT_EQ(read_file(dir / "a.png"), read_file(dir / "b.png"));
    for (int f = 0; f < 4; ++f) {
      char name[16];
      std::snprintf(name, sizeof name, "f%03d.exr", f);
      EXPECT_TRUE(fs::exists(dir / name)) << name;
    }
    EXPECT_FALSE(fs::exists(dir / "f004.exr"));
    const nlohmann::json stats = nlohmann::json::parse(read_file(dir / "a.json"));
    // stages_ms: exactly the frame's stage table (core/render/frame_stages.h) and the total.
    EXPECT_EQ(stats["stages_ms"].size(), epi::render::kFrameStages.size() + 1);
    for (const epi::render::FrameStageInfo& i : epi::render::kFrameStages) EXPECT_TRUE(stats["stages_ms"].contains(i.name)) << i.name;
    EXPECT_TRUE(stats["stages_ms"].contains("total"));
    // The insert's share of the points stage: every frame integrates results (sync), within points.
    EXPECT_GT(stats["integrate_ms"].get<double>(), 0.0);
    EXPECT_LE(stats["integrate_ms"].get<double>(), stats["stages_ms"]["points"].get<double>());
    for (const char* kind : {"silhouette", "sharp", "border", "shadow", "culled"}) EXPECT_TRUE(stats["edges"].contains(kind));
    const double fractions = stats["pixels"]["empty"].get<double>() + stats["pixels"]["simple"].get<double>() +
                             stats["pixels"]["complex"].get<double>();
    EXPECT_NEAR(fractions, 1.0, 1e-9);
    EXPECT_NEAR(stats["samples_per_frame"].get<double>(), 96.0, 1e-9);  // 5% of 48x40
    EXPECT_NEAR(stats["sparseness"].get<double>(), 20.0, 1e-9);
    // Rays the shader traced: at least one per sample, and counted over its own working time.
    EXPECT_NEAR(stats["samples"].get<double>(), 4 * 96.0, 1e-9);
    EXPECT_GE(stats["rays"].get<double>(), stats["samples"].get<double>());
    EXPECT_GT(stats["shading_ms"].get<double>(), 0.0);
    EXPECT_NEAR(stats["mrays_per_s"].get<double>(),
                stats["rays"].get<double>() / (stats["shading_ms"].get<double>() * 1e-3) * 1e-6, 1e-6);
    if (std::string(mode) == "epi") {
      EXPECT_GT(stats["edges"]["border"].get<double>() + stats["edges"]["silhouette"].get<double>(), 0.0);
    } else {
      EXPECT_EQ(stats["edges"]["silhouette"].get<double>(), 0.0);
    }
  }
  fs::remove_all(dir);
}

// One asynchronous frame: its requests go out at the end of the frame, so no result has arrived
// yet. Sparseness (pixels per sample) is then undefined: null, not 0.
TEST(FramesCli, SparsenessIsNullWhenNoSampleArrived) {
  const fs::path dir = temp_dir();
  const EpiRun run = run_epi("render " + kScene + " --size 48x40 --frames 1 --quiet -o " + (dir / "a.png").string() +
                             " --stats " + (dir / "a.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const nlohmann::json stats = nlohmann::json::parse(read_file(dir / "a.json"));
  const double samples = stats["samples"].get<double>();
  if (samples == 0.0) {
    EXPECT_TRUE(stats["sparseness"].is_null()) << stats["sparseness"];
    EXPECT_NE(run.out.find("sparseness -"), std::string::npos) << run.out;
  } else {  // a shader fast enough to deliver within the frame
    EXPECT_NEAR(stats["sparseness"].get<double>(), 48.0 * 40.0 / samples, 1e-9);
  }
  EXPECT_GE(stats["rays"].get<double>(), samples);
  fs::remove_all(dir);
}

TEST(FramesCli, CameraPathFileWithAMovingObject) {
  const fs::path dir = temp_dir();
  std::ofstream(dir / "path.txt") << "camera 0 eye 0 1 3.5 target 0 1 0\ncamera 3 eye 0.5 1 3.4 target 0 1 0\n"
                                     "object 0 short_block translate 0 0 0\nobject 3 short_block translate 0.2 0 0\n";
  const EpiRun run = run_epi("render " + kScene + " --mode epi" + kSmall + " --sync --camera-path " + (dir / "path.txt").string() +
                          " -o " + (dir / "p.png").string() + " --stats " + (dir / "p.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_TRUE(fs::exists(dir / "p.png"));
  // The same path with asynchronous shading (the default).
  const EpiRun async = run_epi("render " + kScene + " --mode epi" + kSmall + " --camera-path " + (dir / "path.txt").string() +
                               " -o " + (dir / "q.png").string());
  ASSERT_EQ(async.exit_code, 0) << async.out;
  EXPECT_TRUE(fs::exists(dir / "q.png"));
  fs::remove_all(dir);
}

TEST(FramesCli, CameraPathFileWithAMovingLight) {
  const std::string chains = std::string(EPI_SOURCE_DIR) + "/scenes/chains.gltf";
  const fs::path dir = temp_dir();
  std::ofstream(dir / "path.txt") << "light 0 point translate 0 0 0\nlight 3 point translate -0.4 0.2 0.3\n"
                                     "light 1 spot translate 0 -0.2 0\n";
  for (const std::string mode : {" --sync", ""}) {
    const EpiRun run = run_epi("render " + chains + " --mode epi" + kSmall + mode + " --camera-path " +
                               (dir / "path.txt").string() + " -o " + (dir / "p.png").string());
    ASSERT_EQ(run.exit_code, 0) << run.out;
    EXPECT_TRUE(fs::exists(dir / "p.png"));
    fs::remove(dir / "p.png");
  }
  std::ofstream(dir / "bad.txt") << "light 0 point translate 0 0 0\nlight 2 point translate 1 x 0\n";
  std::ofstream(dir / "nolamp.txt") << "light 0 lamp translate 1 0 0\n";
  for (const auto& [file, expect] : {std::pair<std::string, std::string>{"bad.txt", "bad.txt:2: 'translate' needs three finite numbers"},
                                     {"nolamp.txt", "nolamp.txt:1: no point or spot light named 'lamp'"}}) {
    const EpiRun run = run_epi("render " + chains + " --mode epi" + kSmall + " --sync --camera-path " + (dir / file).string() +
                               " -o " + (dir / "o.png").string());
    EXPECT_EQ(run.exit_code, 1) << run.out;
    EXPECT_NE(run.out.find(expect), std::string::npos) << run.out;
    EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1) << run.out;
    EXPECT_FALSE(fs::exists(dir / "o.png"));
  }
  fs::remove_all(dir);
}

TEST(FramesCli, BadInputFailsWithOneLineAndNoOutput) {
  const fs::path dir = temp_dir();
  std::ofstream(dir / "bad.txt") << "# fine\ncamera 0 eye 0 1 3 target 0 1 3\n";
  std::ofstream(dir / "nobody.txt") << "object 0 nobody translate 1 0 0\n";
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"--camera-path " + (dir / "bad.txt").string(), "bad.txt:2: eye and target coincide"},
      {"--camera-path " + (dir / "nobody.txt").string(), "nobody.txt:1: no object named 'nobody'"},
      {"--camera-path " + (dir / "missing.txt").string(), "missing.txt: cannot open"},
      {"--frames-out " + (dir / "f%s.png").string(), "--frames-out"},
      {"--frames-out " + (dir / "f.png").string(), "exactly one %d"},
      {"--frames-out " + (dir / "no/such/dir/f%d.png").string(), "no"},
  };
  for (const Case& c : cases) {
    const EpiRun run = run_epi("render " + kScene + " --mode epi" + kSmall + " --sync -o " + (dir / "o.png").string() + " " + c.args);
    EXPECT_EQ(run.exit_code, 1) << c.args << "\n" << run.out;
    EXPECT_NE(run.out.find(c.expect), std::string::npos) << run.out;
    EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1) << run.out;
    EXPECT_FALSE(fs::exists(dir / "o.png"));
  }
  fs::remove_all(dir);
}

// An occlusion rule's radius as a user's knob: unset equals `default_value`, `off_value` turns the
// rule off and changes what a walk into rooms shows, `bad_value` is refused (exit 2, the flag named,
// no output).
void expect_radius_knob(const std::string& flag, int default_value, int off_value, int bad_value) {
  const fs::path dir = temp_dir();
  const std::string base = "render " + std::string(EPI_SOURCE_DIR) +
                           "/scenes/rooms.gltf --sync --size 64x48 --frames 20 --quiet --no-speedup";
  const std::string given = " " + flag + " " + std::to_string(default_value), off = " " + flag + " " + std::to_string(off_value);
  for (const auto& [args, name] : {std::pair{std::string(), "default.exr"}, {given, "given.exr"}, {off, "off.exr"}}) {
    const EpiRun run = run_epi(base + args + " -o " + (dir / name).string());
    ASSERT_EQ(run.exit_code, 0) << run.out;
  }
  EXPECT_EQ(read_file(dir / "default.exr"), read_file(dir / "given.exr")) << flag;
  EXPECT_NE(read_file(dir / "default.exr"), read_file(dir / "off.exr")) << flag;
  const EpiRun bad = run_epi(base + " " + flag + " " + std::to_string(bad_value) + " -o " + (dir / "bad.exr").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.out;
  EXPECT_NE(bad.out.find(flag), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(dir / "bad.exr"));
  fs::remove_all(dir);
}

// The sparse occlusion rule: default 4, 2 turns it off, 1 is refused.
TEST(FramesCli, SparseOcclusionRadiusIsAKnobWithTheRenderersDefault) {
  expect_radius_knob("--sparse-occlusion-radius", 4, 2, 1);
}

// The new-occluder rule: default 8, the sparse radius (4) turns it off, 16 is refused.
TEST(FramesCli, NewOccluderRadiusIsAKnobWithTheRenderersDefault) {
  expect_radius_knob("--new-occluder-radius", 8, 4, 16);
}

// The sparse-region blend: on by default along rooms' walk (the stats count the pixels it blended),
// --no-sparse-blend shows the EPI's own reconstruction (none blended, other bytes).
TEST(FramesCli, SparseBlendIsOnByDefaultAndCanBeTurnedOff) {
  const fs::path dir = temp_dir();
  const std::string base = "render " + std::string(EPI_SOURCE_DIR) +
                           "/scenes/rooms.gltf --sync --size 64x48 --frames 20 --quiet --no-speedup";
  for (const auto& [args, name] : {std::pair{"", "on"}, {" --no-sparse-blend", "off"}}) {
    const EpiRun run = run_epi(base + args + " -o " + (dir / name).string() + ".exr --stats " + (dir / name).string() + ".json");
    ASSERT_EQ(run.exit_code, 0) << run.out;
  }
  auto blended = [&](const char* name) {
    return nlohmann::json::parse(read_file(dir / (std::string(name) + ".json")))["points_per_frame"]["sparse_blended"].get<double>();
  };
  EXPECT_GT(blended("on"), 0.0);
  EXPECT_EQ(blended("off"), 0.0);
  EXPECT_NE(read_file(dir / "on.exr"), read_file(dir / "off.exr"));
  fs::remove_all(dir);
}

// --sparse-effort: off by default (every request effort 1, as the stats say); 4 along rooms' walk
// asks for more where the EPI is sparse and changes the image; 0 and 65 are refused by name.
TEST(FramesCli, SparseEffortIsOffByDefaultAndAsksForMoreWhereSamplesAreSparse) {
  const fs::path dir = temp_dir();
  const std::string base = "render " + std::string(EPI_SOURCE_DIR) +
                           "/scenes/rooms.gltf --sync --size 64x48 --frames 20 --quiet --no-speedup";
  for (const auto& [args, name] : {std::pair{"", "off"}, {" --sparse-effort 4", "on"}}) {
    const EpiRun run = run_epi(base + args + " -o " + (dir / name).string() + ".exr --stats " + (dir / name).string() + ".json");
    ASSERT_EQ(run.exit_code, 0) << run.out;
  }
  auto effort = [&](const char* name) {
    return nlohmann::json::parse(read_file(dir / (std::string(name) + ".json")))["effort_per_request"].get<double>();
  };
  EXPECT_EQ(effort("off"), 1.0);
  EXPECT_GT(effort("on"), 1.2);
  EXPECT_LE(effort("on"), 4.0);
  EXPECT_NE(read_file(dir / "on.exr"), read_file(dir / "off.exr"));
  for (const char* bad : {"0", "65"}) {
    const EpiRun run = run_epi(base + " --sparse-effort " + bad + " -o " + (dir / "bad.exr").string());
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.out.find("--sparse-effort"), std::string::npos) << run.out;
    EXPECT_FALSE(fs::exists(dir / "bad.exr"));
  }
  fs::remove_all(dir);
}

// --no-trace-ahead: a sync run integrates each frame's results in that frame (lag 0), so nothing
// is extrapolated and the bytes are the same; the asynchronous loop reports its lag (about 2),
// averaged over the frames that integrated results: at least one frame, however loaded the machine
// (the frames before the first results came back once pulled the mean below 1 in a loaded CI run).
TEST(FramesCli, TraceAheadLeavesSyncRunsAsTheyWereAndTheAsyncLoopReportsItsLag) {
  const fs::path dir = temp_dir();
  const std::string base = "render " + std::string(EPI_SOURCE_DIR) + "/scenes/rooms.gltf --size 64x48 --frames 40 --quiet --no-speedup";
  for (const auto& [args, name] : {std::pair{" --sync", "ahead"}, {" --sync --no-trace-ahead", "not"}, {"", "async"}}) {
    const EpiRun run = run_epi(base + args + " -o " + (dir / name).string() + ".exr --stats " + (dir / name).string() + ".json");
    ASSERT_EQ(run.exit_code, 0) << run.out;
  }
  EXPECT_EQ(read_file(dir / "ahead.exr"), read_file(dir / "not.exr"));
  EXPECT_EQ(nlohmann::json::parse(read_file(dir / "ahead.json"))["result_lag_frames"].get<double>(), 0.0);
  const double lag = nlohmann::json::parse(read_file(dir / "async.json"))["result_lag_frames"].get<double>();
  EXPECT_GE(lag, 1.0);
  EXPECT_LT(lag, 40.0);
  fs::remove_all(dir);
}

// --frames-at picks the frames --frames-out writes; with --path-rate the path runs on the loop's
// clock, each chosen key drawn (and written) once, exactly, and the run ends at the path's end.
TEST(FramesCli, ThePathOnTheClockWritesEachChosenKeyOnce) {
  const fs::path dir = temp_dir();
  const std::string base = "render " + kScene + " --size 48x40 --frames 30 --sample-budget 0.05 --quiet --no-speedup";
  auto written = [&] {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().rfind("f", 0) == 0) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  for (const std::string rate : {"", " --path-rate 1000"}) {
    for (const auto& e : fs::directory_iterator(dir)) fs::remove(e.path());
    const EpiRun run = run_epi(base + rate + " --frames-at 20,4 --frames-out " + (dir / "f%d.exr").string() + " -o " +
                               (dir / "last.exr").string() + " --stats " + (dir / "s.json").string());
    ASSERT_EQ(run.exit_code, 0) << rate << "\n" << run.out;
    EXPECT_EQ(written(), (std::vector<std::string>{"f20.exr", "f4.exr"})) << rate;
    const nlohmann::json stats = nlohmann::json::parse(read_file(dir / "s.json"));
    if (rate.empty()) {
      EXPECT_EQ(stats["loop_frames"].get<int>(), 30);
      EXPECT_EQ(stats["path_rate"].get<double>(), 0.0);
    } else {
      EXPECT_GE(stats["loop_frames"].get<int>(), 3);  // the two keys and the end, at least
      EXPECT_EQ(stats["path_rate"].get<double>(), 1000.0);
      EXPECT_NE(run.out.find("on the clock (1000 a second)"), std::string::npos) << run.out;
    }
  }
  struct Bad {
    std::string args, expect;
  } bad[] = {{" --frames-at 4,30", "--frames-at 30: beyond the path's last frame, 29"},
             {" --path-rate -1", "--path-rate"},
             {" --path-rate 5 --mode raytrace", "--path-rate needs the frame loop"},
             {" --frames-at 3 --mode reference --spp 1", "--frames-at needs the frame loop"}};
  for (const Bad& b : bad) {
    const EpiRun run = run_epi(base + b.args + " -o " + (dir / "bad.exr").string());
    EXPECT_NE(run.exit_code, 0) << b.args;
    EXPECT_NE(run.out.find(b.expect), std::string::npos) << run.out;
    EXPECT_FALSE(fs::exists(dir / "bad.exr"));
  }
  fs::remove_all(dir);
}

TEST(FramesCli, EveryFrameNameIsCheckedBeforeAnyWork) {
  // Middle frames, not only the first and last: one named like -o, one in a missing folder.
  const fs::path dir = temp_dir();
  fs::create_directories(dir / "d0");
  fs::create_directories(dir / "d3");
  struct Case {
    std::string args, expect, stray;
  } cases[] = {
      {"-o " + (dir / "f2.png").string() + " --frames-out " + (dir / "f%d.png").string(), "given for two outputs", "f0.png"},
      {"-o " + (dir / "o.png").string() + " --frames-out " + (dir / "d%d/x.png").string(), "d1", "o.png"},
  };
  for (const Case& c : cases) {
    const EpiRun run = run_epi("render " + kScene + " --mode epi --size 16x12 --frames 4 --sync --quiet " + c.args);
    EXPECT_EQ(run.exit_code, 1) << c.args << "\n" << run.out;
    EXPECT_NE(run.out.find(c.expect), std::string::npos) << run.out;
    EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1) << run.out;
    EXPECT_FALSE(fs::exists(dir / c.stray));
    EXPECT_FALSE(fs::exists(dir / "d0" / "x.png"));
  }
  fs::remove_all(dir);
}

// The image modes render the view the frame loop ends on (the end of the scene's own path here,
// which is not the scene's camera): a 1-spp ray trace (`--mode raytrace`) is the one the epi run
// of the same options measures its speed-up with, so against it that ray trace has no error.
TEST(FramesCli, ImageModesRenderTheLastFramesView) {
  const fs::path dir = temp_dir();
  const std::string rooms = std::string(EPI_SOURCE_DIR) + "/scenes/rooms.gltf";
  const std::string common = " --size 40x30 --seed 3 --frames 20 --quiet";
  ASSERT_EQ(run_epi("render " + rooms + common + " --mode raytrace -o " + (dir / "end.exr").string()).exit_code, 0);
  ASSERT_EQ(run_epi("render " + rooms + " --size 40x30 --seed 3 --quiet --fov 40 --mode raytrace -o " +
                    (dir / "camera.exr").string()).exit_code, 0);
  EXPECT_TRUE(read_file(dir / "end.exr") != read_file(dir / "camera.exr"));  // another view
  const EpiRun run = run_epi("render " + rooms + common + " --sync -o " + (dir / "e.exr").string() + " --reference " +
                             (dir / "end.exr").string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_NE(run.out.find("the 1-spp ray trace against it: display RMSE 0.0000"), std::string::npos) << run.out;
}

// --reference: the written frame's metrics are those `epi compare` gives for the written file;
// the speed-up over a 1-spp ray trace is measured unless --no-speedup; a bad reference fails
// before any work.
TEST(FramesCli, ReferenceMetricsAndSpeedUp) {
  const fs::path dir = temp_dir();
  const std::string still = " --fov 40";  // the scene camera, still: one view for the reference and every run
  const std::string base = "render " + kScene + kSmall + still + " --sync --seed 3";
  const EpiRun reference = run_epi("render " + kScene + " --mode raytrace --size 48x40 --quiet -o " + (dir / "ref.exr").string() +
                                   " --reference " + (dir / "missing.exr").string());
  EXPECT_EQ(reference.exit_code, 1) << reference.out;  // a missing reference: before any work
  EXPECT_NE(reference.out.find("missing.exr: no such file"), std::string::npos) << reference.out;
  EXPECT_FALSE(fs::exists(dir / "ref.exr"));
  ASSERT_EQ(run_epi("render " + kScene + still + " --mode raytrace --size 48x40 --seed 3 --quiet -o " + (dir / "ref.exr").string()).exit_code, 0);

  for (const char* mode : {"epi", "rendercache", "raytrace"}) {
    const EpiRun run = run_epi(base + " --mode " + mode + " -o " + (dir / "a.exr").string() + " --stats " +
                               (dir / "a.json").string() + " --reference " + (dir / "ref.exr").string());
    ASSERT_EQ(run.exit_code, 0) << run.out;
    EXPECT_NE(run.out.find("against " + (dir / "ref.exr").string() + ": display RMSE "), std::string::npos) << run.out;
    const nlohmann::json stats = nlohmann::json::parse(read_file(dir / "a.json"));
    const EpiRun compare = run_epi("compare " + (dir / "a.exr").string() + " " + (dir / "ref.exr").string() + " --json " +
                                   (dir / "c.json").string());
    ASSERT_EQ(compare.exit_code, 0) << compare.out;
    const nlohmann::json c = nlohmann::json::parse(read_file(dir / "c.json"));
    for (const char* key : {"display_rmse", "relative_mse", "over_0_1", "over_0_2", "max_display_error"})
      EXPECT_DOUBLE_EQ(stats["reference"][key].get<double>(), c[key].get<double>()) << mode << " " << key;
    EXPECT_EQ(stats["reference"]["file"], (dir / "ref.exr").string());
    if (std::string(mode) == "raytrace") {
      EXPECT_EQ(stats["reference"]["display_rmse"].get<double>(), 0.0);  // the same ray trace
      continue;
    }
    EXPECT_GT(stats["reference"]["display_rmse"].get<double>(), 0.0) << mode;
    EXPECT_GT(stats["raytrace_1spp_ms"].get<double>(), 0.0) << mode;
    EXPECT_NEAR(stats["speedup"].get<double>(),
                stats["raytrace_1spp_ms"].get<double>() / stats["stages_ms"]["total"].get<double>(), 1e-9);
    EXPECT_NE(run.out.find("speed-up over a 1-spp ray trace of the last view (direct shader): "), std::string::npos) << run.out;
    // The timed ray trace is the reference itself (same view, shader and seed): no error.
    EXPECT_NE(run.out.find("the 1-spp ray trace against it: display RMSE 0.0000"), std::string::npos) << run.out;
    EXPECT_EQ(stats["raytrace_reference"]["display_rmse"].get<double>(), 0.0) << mode;
  }
  const EpiRun skipped = run_epi(base + " --no-speedup -o " + (dir / "b.png").string() + " --stats " + (dir / "b.json").string());
  ASSERT_EQ(skipped.exit_code, 0) << skipped.out;
  EXPECT_EQ(skipped.out.find("speed-up"), std::string::npos) << skipped.out;
  const nlohmann::json stats = nlohmann::json::parse(read_file(dir / "b.json"));
  EXPECT_TRUE(stats["speedup"].is_null());
  EXPECT_TRUE(stats["raytrace_1spp_ms"].is_null());
  EXPECT_FALSE(stats.contains("reference"));

  // The output may not overwrite the reference.
  const EpiRun onto = run_epi(base + " -o " + (dir / "ref.exr").string() + " --reference " + (dir / "ref.exr").string());
  EXPECT_EQ(onto.exit_code, 1) << onto.out;
  EXPECT_NE(onto.out.find("ref.exr: names an input"), std::string::npos) << onto.out;

  // A reference of another size: one line naming it and both sizes, nothing written.
  const EpiRun mismatch = run_epi("render " + kScene + " --size 32x40 --frames 2 --sync --quiet -o " + (dir / "m.png").string() +
                                  " --reference " + (dir / "ref.exr").string());
  EXPECT_EQ(mismatch.exit_code, 1) << mismatch.out;
  EXPECT_NE(mismatch.out.find("ref.exr: the reference is 48x40, the image 32x40"), std::string::npos) << mismatch.out;
  EXPECT_EQ(std::count(mismatch.out.begin(), mismatch.out.end(), '\n'), 1) << mismatch.out;
  EXPECT_FALSE(fs::exists(dir / "m.png"));
  fs::remove_all(dir);
}

}  // namespace

// The `epi` program as a user meets it: exit codes, error messages, files written or not, and
// what each flag changes in the output.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>
#include <sys/wait.h>

#include "gltf_builder.h"
#include "test_meshes.h"
#include "image_io.h"
#include "run_epi.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path temp_root() { return fs::temp_directory_path() / ("epi-cli-test-" + std::to_string(::getpid())); }

fs::path temp_dir(const std::string& name = "") {
  fs::path dir = temp_root() / name;
  fs::create_directories(dir);
  return dir;
}

// Removes this process's scratch folder after the last test.
struct RemoveScratch : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(temp_root(), ec);
  }
};
const auto* const kRemoveScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

std::string scene_path(const std::string& name) { return std::string(EPI_SOURCE_DIR) + "/scenes/" + name; }
const std::string kCornell = scene_path("cornell_box.gltf");

void write_file(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

json read_json(const fs::path& file) { return json::parse(read_file(file)); }

int count_lines(const std::string& text) { return int(std::count(text.begin(), text.end(), '\n')); }

std::vector<std::string> folder_entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

double mean_value(const epi::RgbImage& image) {
  double sum = 0.0;
  for (float v : image.pixels) sum += v;
  return sum / double(image.pixels.size());
}

// The number after `label` in `text` (e.g. "triangles: " -> 36); -1 if absent.
long long number_after(const std::string& text, const std::string& label) {
  const size_t at = text.find(label);
  if (at == std::string::npos) return -1;
  return std::stoll(text.substr(at + label.size()));
}

// A tiny, fast reference render of the Cornell box.
const std::string kTinyReference = " --mode reference --size 16x12 --spp 1 --area-light-samples 4 --quiet";

}  // namespace

// ---------------------------------------------------------------------------------------------
// Parsing: usage on every command line that does not parse, exit code 2.

TEST(Cli, NoSubcommandPrintsUsageAndFails) {
  const EpiRun run = run_epi("");
  EXPECT_EXIT_CODE(run, kUsage);
  EXPECT_NE(run.out.find("A subcommand is required"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("Usage:"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("render"), std::string::npos) << run.out;  // the subcommands are listed
}

TEST(Cli, HelpSucceedsAndNamesTheDefaultMode) {
  const EpiRun run = run_epi("render --help");
  EXPECT_EXIT_CODE(run, 0);
  for (const char* text : {"--spp", "--shader", "default: --mode epi", "=epi", "--area-light-samples", "--glossy-samples",
                           "--gi-paths", "--gi-max-bounces", "--exposure", "--sync"})
    EXPECT_NE(run.out.find(text), std::string::npos) << text;
}

TEST(Cli, UnknownFlagPrintsTheUsageOfItsSubcommand) {
  const EpiRun run = run_epi("render " + kCornell + " --bogus 3");
  EXPECT_EXIT_CODE(run, kUsage);
  EXPECT_EQ(run.out.rfind("epi: ", 0), 0u) << run.out;
  EXPECT_NE(run.out.find("--bogus"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("Usage:"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("render [OPTIONS] scene"), std::string::npos) << run.out;
}

TEST(Cli, BadOptionValuesAreRejectedWithUsage) {
  for (const char* args : {"--size 12", "--spp 0", "--mode fast", "--eye 1,2,x", "--fov 0", "--area-light-samples 0",
                           "--gi-max-bounces -1", "--exposure big", "--predict-share 1.5", "--predict-frames -1",
                           "--predict-stride 0", "--predict-splat 16"}) {
    const EpiRun run = run_epi("render " + kCornell + " " + args);
    EXPECT_EXIT_CODE(run, kUsage);
    EXPECT_NE(run.out.find("Usage:"), std::string::npos) << args << "\n" << run.out;
  }
}

// ---------------------------------------------------------------------------------------------
// Failures of the work itself: one line, exit code 1, nothing written.

TEST(Cli, MissingSceneNamesTheFile) {
  const EpiRun run = run_epi("info /no/such/scene.gltf");
  EXPECT_EXIT_CODE(run, kFailed);
  EXPECT_NE(run.out.find("/no/such/scene.gltf"), std::string::npos) << run.out;
  EXPECT_EQ(count_lines(run.out), 1) << run.out;
}

TEST(Cli, MalformedSceneGivesOneLineError) {
  const fs::path file = temp_dir() / "broken.gltf";
  write_file(file, "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": 7}");
  const EpiRun run = run_epi("info " + file.string());
  EXPECT_EXIT_CODE(run, kFailed);
  EXPECT_EQ(run.out.rfind("epi: " + file.string(), 0), 0u) << run.out;
  EXPECT_EQ(count_lines(run.out), 1) << run.out;
}

TEST(Cli, BadOutputFailsBeforeRenderingAndWritesNothing) {
  const fs::path dir = temp_dir("bad-output");
  const EpiRun run = run_epi("render " + kCornell + " --mode reference --spp 4096 --size 2048x2048 -o " +
                             (dir / "image.xyz").string());
  EXPECT_EXIT_CODE(run, kFailed);
  EXPECT_NE(run.out.find("image.xyz"), std::string::npos) << run.out;
  EXPECT_TRUE(fs::is_empty(dir));
  const EpiRun missing_folder = run_epi("render " + kCornell + " -o /no/such/folder/a.png");
  EXPECT_EXIT_CODE(missing_folder, kFailed);
  EXPECT_NE(missing_folder.out.find("/no/such/folder/a.png"), std::string::npos) << missing_folder.out;
}

// Every subcommand validates every output path before any work: a bad --stats (or --svg, or
// frames pattern) fails with one line naming it and leaves no file at all.
TEST(Cli, BadSecondaryOutputLeavesNoOutputAtAll) {
  const fs::path dir = temp_dir("bad-stats");
  const fs::path folder = dir / "a_folder";  // an existing folder where a file is expected
  fs::create_directories(folder);
  const std::string pattern = std::string(EPI_SOURCE_DIR) + "/tests/epi/patterns/checker.json";
  const std::string image = (dir / "image.png").string(), edges = (dir / "edges.json").string();
  struct Case {
    std::string args, named;
  } cases[] = {
      {"render " + kCornell + kTinyReference + " -o " + image + " --stats " + folder.string(), folder.string()},
      {"render " + kCornell + " --mode raytrace --size 16x12 --quiet -o " + image + " --stats " + folder.string(), folder.string()},
      {"render " + kCornell + " --size 16x12 --frames 2 --sync --quiet -o " + image + " --frames-out " +
           (dir / "f%d.png").string() + " --stats " + folder.string(), folder.string()},
      {"render " + kCornell + " --mode rendercache --size 16x12 --frames 2 --quiet -o " + image + " --stats " +
           folder.string(), folder.string()},
      {"render " + kCornell + kTinyReference + " -o " + image + " --stats " + (dir / "nope" / "s.json").string(),
       (dir / "nope" / "s.json").string()},
      {"reconstruct " + pattern + " --quiet -o " + image + " --stats " + folder.string(), folder.string()},
      {"edges " + kCornell + " -o " + edges + " --stats " + folder.string(), folder.string()},
      {"edges " + kCornell + " -o " + edges + " --svg " + folder.string(), folder.string()},
      {"edges " + kCornell + " -o " + folder.string(), folder.string()},
      {"edges " + kCornell + " -o " + edges + " --stats " + (dir / "." / "edges.json").string(), (dir / "." / "edges.json").string()},
      {"render " + kCornell + " --mode raytrace --size 16x12 --quiet -o " + image + " --stats " + image, image},
  };
  for (const Case& c : cases) {
    const EpiRun run = run_epi(c.args);
    EXPECT_EXIT_CODE(run, kFailed);
    EXPECT_EQ(count_lines(run.out), 1) << c.args << "\n" << run.out;
    EXPECT_EQ(run.out.rfind("epi: " + c.named + ": ", 0), 0u) << c.args << "\n" << run.out;
    EXPECT_EQ(folder_entries(dir), std::vector<std::string>{"a_folder"}) << c.args;
    EXPECT_TRUE(fs::is_empty(folder));
  }
}

// ---------------------------------------------------------------------------------------------
// epi info

TEST(Cli, InfoCountsTheDefaultScene) {
  const EpiRun run = run_epi("info " + kCornell);
  ASSERT_EXIT_CODE(run, 0);
  for (const char* field : {"objects: ", "triangles: ", "unique edges: ", "lights: ", "cameras: ", "memory:"})
    EXPECT_NE(run.out.find(field), std::string::npos) << field;
  EXPECT_NE(run.out.find("area 1"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("camera path keys: 60"), std::string::npos) << run.out;
  EXPECT_GT(number_after(run.out, "ray scene, embree (BVH + buffers): "), 1000) << run.out;
  EXPECT_GT(number_after(run.out, "edge finder (edge meshes and trees): "), 100) << run.out;
}

// A cube mesh placed by two nodes, with one degenerate triangle: the file holds 13 triangles,
// 12 after the repair, 24 as rendered.
fs::path instanced_cube_with_a_degenerate_triangle(const fs::path& dir) {
  epi::test::GltfBuilder b;
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  epi::test::unit_cube(positions, indices);
  indices.insert(indices.end(), {0, 1, 1});  // degenerate
  const int mesh = b.add_mesh("cube", positions, indices);
  const int a = b.add_node({{"name", "left"}, {"mesh", mesh}, {"translation", {-1.0, 0.0, 0.0}}});
  const int c = b.add_node({{"name", "right"}, {"mesh", mesh}, {"translation", {1.0, 0.0, 0.0}}});
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "point"}, {"intensity", 50.0}}});
  b.doc["extensionsUsed"] = json::array({"KHR_lights_punctual"});
  const int light = b.add_node({{"name", "lamp"}, {"translation", {0.0, 2.0, 3.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.set_scene({a, c, light});
  return b.write_gltf(dir / "cubes.gltf");
}

TEST(Cli, InfoGivesTheFileAndTheInstancedTriangleCounts) {
  const fs::path scene = instanced_cube_with_a_degenerate_triangle(temp_dir("instanced"));
  const EpiRun run = run_epi("info " + scene.string());
  ASSERT_EXIT_CODE(run, 0);
  EXPECT_EQ(number_after(run.out, "\ntriangles: "), 13) << run.out;
  EXPECT_NE(run.out.find("12 after dropping 1 degenerate"), std::string::npos) << run.out;
  EXPECT_EQ(number_after(run.out, "\ninstanced triangles: "), 24) << run.out;
  EXPECT_GT(number_after(run.out, "ray scene, embree (BVH + buffers): "), 0) << run.out;
}

TEST(Cli, RenderReportsRepairsOnOneLineUnlessQuiet) {
  const fs::path dir = temp_dir("repairs");
  const fs::path scene = instanced_cube_with_a_degenerate_triangle(dir);
  const std::string args = "render " + scene.string() +
                           " --mode reference --size 8x8 --spp 1 --eye 0,0,5 --target 0,0,0 -o " + (dir / "r.exr").string();
  const EpiRun loud = run_epi(args);
  ASSERT_EXIT_CODE(loud, 0);
  const std::string line = "epi: " + scene.string() + ": repaired while loading: mesh 'cube': dropped 1 degenerate triangles\n";
  EXPECT_NE(loud.out.find(line), std::string::npos) << loud.out;
  EXPECT_EQ(loud.out.find("repaired"), loud.out.rfind("repaired")) << "one line only";
  const EpiRun quiet = run_epi(args + " --quiet");
  ASSERT_EXIT_CODE(quiet, 0);
  EXPECT_EQ(quiet.out.find("repaired"), std::string::npos) << quiet.out;
  const EpiRun edges = run_epi("edges " + scene.string() + " --eye 0,0,5 --target 0,0,0 -o " + (dir / "e.json").string());
  ASSERT_EXIT_CODE(edges, 0);
  EXPECT_NE(edges.out.find(line), std::string::npos) << edges.out;
}

// The torus of issue 9 as exporters write it: seam copies from cos/sin of 0 and 2 pi (not
// bit-identical). An exact weld reported 144 border edges and `epi edges` drew the seam as one.
TEST(Cli, ExporterTorusIsWeldedWithoutBorders) {
  const fs::path dir = temp_dir("exporter-torus");
  const epi::Mesh torus = epi::edges::test::exporter_torus(48, 24);
  std::vector<uint32_t> indices;
  for (const glm::uvec3& t : torus.triangles) indices.insert(indices.end(), {t.x, t.y, t.z});
  epi::test::GltfBuilder b;
  const int mesh = b.add_mesh("torus", torus.positions, indices);
  b.set_scene({b.add_node({{"name", "torus"}, {"mesh", mesh}})});
  const fs::path scene = b.write_gltf(dir / "torus.gltf");
  const EpiRun info = run_epi("info " + scene.string());
  ASSERT_EXIT_CODE(info, 0);
  EXPECT_NE(info.out.find("welded vertices: 1152 (of 1225: 73 copies welded, 73 of them within the tolerance"),
            std::string::npos) << info.out;
  EXPECT_EQ(number_after(info.out, "\nborder edges: "), 0) << info.out;
  EXPECT_NE(info.out.find("object 'torus': mesh 'torus', 2304 triangles, 0 border and 0 non-manifold edges"),
            std::string::npos) << info.out;
  const EpiRun edges = run_epi("edges " + scene.string() + " --eye 0,3,2 --target 0,0,0 -o " + (dir / "e.json").string());
  ASSERT_EXIT_CODE(edges, 0);
  const json found = read_json(dir / "e.json");
  size_t silhouettes = 0;
  for (const json& e : found["edges"]) {
    EXPECT_NE(e["kind"], "border");
    silhouettes += e["kind"] == "silhouette";
  }
  EXPECT_GT(silhouettes, 0u);
}

// ---------------------------------------------------------------------------------------------
// epi render

TEST(Cli, TheDefaultModeIsTheEdgeAndPointRenderer) {
  const fs::path dir = temp_dir("default-mode");
  const EpiRun run = run_epi("render " + kCornell + " --size 32x24 --frames 2 --sync --quiet -o " + (dir / "d.png").string() +
                             " --stats " + (dir / "d.json").string());
  ASSERT_EXIT_CODE(run, 0);
  EXPECT_NE(run.out.find("32x24, epi, 2 frames (sync shading)"), std::string::npos) << run.out;
  const json stats = read_json(dir / "d.json");
  EXPECT_EQ(stats["mode"], "epi");
  EXPECT_GT(stats["edges"]["border"].get<double>() + stats["edges"]["silhouette"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(dir / "d.png"));
}

// --predict-share, --predict-frames, --predict-stride and --predict-splat reach the frame loop:
// along the Cornell box's path a share of 0.25 sends part of each frame's budget to predicted
// gaps; the default (off), or extrapolating 0 frames ahead (the predicted view is the current
// one: no gap outside it), sends none. With the whole budget allowed, every point projected as a
// 15-pixel square covers more of the view ahead than 1 point in 64 does, or every point as one
// pixel: fewer gaps.
TEST(Cli, PredictiveSamplingFlagsReachTheRenderer) {
  const fs::path dir = temp_dir("predict");
  auto predicted = [&](const std::string& flags) {
    const fs::path stats = dir / "p.json";
    const EpiRun run = run_epi("render " + kCornell + " --size 64x48 --frames 12 --sync --quiet --no-speedup" + flags +
                               " -o " + (dir / "p.png").string() + " --stats " + stats.string());
    EXPECT_EXIT_CODE(run, 0);
    return read_json(stats)["predicted_per_frame"].get<double>();
  };
  EXPECT_EQ(predicted(""), 0.0);  // off by default
  EXPECT_GT(predicted(" --predict-share 0.25"), 0.0);
  EXPECT_EQ(predicted(" --predict-share 0.25 --predict-frames 0"), 0.0);
  const double covered = predicted(" --predict-share 1 --predict-stride 1 --predict-splat 15");
  EXPECT_LT(covered, predicted(" --predict-share 1 --predict-stride 64 --predict-splat 15"));
  EXPECT_LT(covered, predicted(" --predict-share 1 --predict-stride 1 --predict-splat 1"));
}

TEST(Cli, RenderWritesImageAndStats) {
  const fs::path dir = temp_dir();
  const fs::path image = dir / "small.exr";
  const fs::path stats = dir / "small.json";
  const EpiRun run = run_epi("render " + kCornell + " --mode reference --size 24x16 --spp 2 --quiet -o " + image.string() +
                             " --stats " + stats.string());
  ASSERT_EXIT_CODE(run, 0);
  ASSERT_TRUE(fs::exists(image));
  const json json = read_json(stats);
  EXPECT_GT(json["stages_ms"]["total"].get<double>(), 0.0);
  EXPECT_GT(json["rays"].get<double>(), 24.0 * 16.0 * 2.0);
  EXPECT_GT(json["mrays_per_s"].get<double>(), 0.0);
  EXPECT_EQ(json["width"].get<int>(), 24);
}

TEST(Cli, RenderIsDeterministicAcrossThreadCounts) {
  const fs::path dir = temp_dir();
  const std::string common = "render " + kCornell + " --mode reference --size 20x20 --spp 3 --seed 7 --quiet -o ";
  ASSERT_EXIT_CODE(run_epi(common + (dir / "t1.exr").string() + " --threads 1"), 0);
  ASSERT_EXIT_CODE(run_epi(common + (dir / "t2.exr").string() + " --threads 2"), 0);
  const std::string bytes_a = read_file(dir / "t1.exr"), bytes_b = read_file(dir / "t2.exr");
  EXPECT_GT(bytes_a.size(), 1000u);  // compressed EXR of 20x20 float RGB
  EXPECT_TRUE(bytes_a == bytes_b) << "renders with 1 and 2 threads differ";
}

TEST(Cli, RaytraceModeShadesOneSamplePerPixel) {
  const fs::path dir = temp_dir("raytrace");
  const EpiRun run = run_epi("render " + kCornell + " --mode raytrace --spp 64 --size 16x12 --quiet -o " +
                             (dir / "r.exr").string() + " --stats " + (dir / "r.json").string());
  ASSERT_EXIT_CODE(run, 0);
  const json stats = read_json(dir / "r.json");
  EXPECT_EQ(stats["mode"], "raytrace");
  EXPECT_EQ(stats["spp"].get<int>(), 1);  // --spp is for reference only
  EXPECT_GE(stats["rays"].get<double>(), 16.0 * 12.0);
  EXPECT_GT(mean_value(epi::read_image(dir / "r.exr")), 0.0);
}

TEST(Cli, GlossyAndGiShadersChangeTheImage) {
  const fs::path dir = temp_dir("shaders");
  double mean[3];
  std::string bytes[3];
  const char* shaders[] = {"direct", "glossy", "gi"};
  for (int i = 0; i < 3; ++i) {
    const fs::path image = dir / (std::string(shaders[i]) + ".exr");
    const EpiRun run = run_epi("render " + kCornell + kTinyReference + " --gi-paths 4 --seed 3 --shader " +
                               shaders[i] + " -o " + image.string());
    ASSERT_EXIT_CODE(run, 0);
    mean[i] = mean_value(epi::read_image(image));
    bytes[i] = read_file(image);
  }
  EXPECT_GT(mean[0], 0.0);
  EXPECT_NE(bytes[1], bytes[0]) << "glossy reflection changed nothing";
  EXPECT_GT(mean[2], 1.1 * mean[0]) << "indirect light must add energy in a closed box";
}

TEST(Cli, ShaderSampleCountsChangeTheImageDeterministically) {
  const fs::path dir = temp_dir("counts");
  const std::string base = "render " + kCornell + " --mode reference --size 16x12 --spp 1 --seed 4 --quiet";
  ASSERT_EXIT_CODE(run_epi(base + " -o " + (dir / "default.exr").string() + " --stats " + (dir / "default.json").string()), 0);
  ASSERT_EXIT_CODE(run_epi(base + " --area-light-samples 1 -o " + (dir / "one.exr").string() + " --stats " +
                           (dir / "one.json").string()), 0);
  ASSERT_EXIT_CODE(run_epi(base + " --area-light-samples 1 --threads 1 -o " + (dir / "one_again.exr").string()), 0);
  EXPECT_NE(read_file(dir / "default.exr"), read_file(dir / "one.exr"));
  EXPECT_EQ(read_file(dir / "one.exr"), read_file(dir / "one_again.exr"));
  // Fewer shadow rays per hit: fewer rays in all.
  EXPECT_LT(read_json(dir / "one.json")["rays"].get<double>(), read_json(dir / "default.json")["rays"].get<double>());
  // Longer indirect paths carry more light.
  const std::string gi = base + " --shader gi --area-light-samples 2 --gi-paths 2";
  ASSERT_EXIT_CODE(run_epi(gi + " --gi-max-bounces 1 -o " + (dir / "b1.exr").string()), 0);
  ASSERT_EXIT_CODE(run_epi(gi + " --gi-max-bounces 4 -o " + (dir / "b4.exr").string()), 0);
  EXPECT_LT(mean_value(epi::read_image(dir / "b1.exr")), mean_value(epi::read_image(dir / "b4.exr")));
}

TEST(Cli, CameraFlagsMoveTheCamera) {
  const fs::path dir = temp_dir("camera");
  const std::string base = "render " + kCornell + kTinyReference;
  // The box spans [0, 0.56]^3, open towards -z where the scene's camera stands. Looking out of
  // it into empty space: nothing is hit, the image is black.
  const std::string eye = " --eye 0.278,0.273,-0.8";
  ASSERT_EXIT_CODE(run_epi(base + eye + " --target 0.278,0.273,-2 --up 0,1,0 --fov 30 -o " + (dir / "away.exr").string()), 0);
  // Looking in, the same eye, with a narrower and a wider field of view.
  const std::string in = eye + " --target 0.278,0.273,0.3";
  ASSERT_EXIT_CODE(run_epi(base + in + " --fov 20 -o " + (dir / "narrow.exr").string()), 0);
  ASSERT_EXIT_CODE(run_epi(base + in + " --fov 60 -o " + (dir / "wide.exr").string()), 0);
  EXPECT_GT(mean_value(epi::read_image(dir / "wide.exr")), 0.0);
  EXPECT_EQ(mean_value(epi::read_image(dir / "away.exr")), 0.0);
  EXPECT_NE(read_file(dir / "narrow.exr"), read_file(dir / "wide.exr"));
  // Upside down: the light (top of the box) moves to the bottom rows.
  ASSERT_EXIT_CODE(run_epi(base + in + " --up 0,-1,0 --fov 60 -o " + (dir / "flipped.exr").string()), 0);
  const epi::RgbImage wide = epi::read_image(dir / "wide.exr"), flipped = epi::read_image(dir / "flipped.exr");
  auto brightest_row = [](const epi::RgbImage& image) {
    int best = 0;
    double best_sum = -1.0;
    for (int y = 0; y < image.height; ++y) {
      double sum = 0.0;
      for (int x = 0; x < image.width; ++x) sum += image.at(x, y)[0] + image.at(x, y)[1] + image.at(x, y)[2];
      if (sum > best_sum) best_sum = sum, best = y;
    }
    return best;
  };
  EXPECT_LT(brightest_row(wide), wide.height / 2);
  EXPECT_GE(brightest_row(flipped), flipped.height / 2);
}

TEST(Cli, SubdivLevelSetsTheTessellation) {
  const fs::path dir = temp_dir("subdiv");
  size_t triangles[2];
  for (int level : {0, 1}) {
    const std::string level_text = std::to_string(level);
    const fs::path stats = dir / ("s" + level_text + ".json");
    const EpiRun run = run_epi("render " + scene_path("chains.gltf") + " --mode reference --size 8x8 --spp 1 --quiet" +
                               " --area-light-samples 1 --subdiv-level " + level_text + " -o " +
                               (dir / "s.exr").string() + " --stats " + stats.string());
    ASSERT_EXIT_CODE(run, 0);
    triangles[level] = read_json(stats)["triangles"].get<size_t>();
  }
  // Catmull-Clark splits each quad of the chains into four; the ground (2 triangles) is not subdivided.
  EXPECT_EQ(triangles[1] - 2, 4 * (triangles[0] - 2)) << triangles[0] << " " << triangles[1];
  const EpiRun info = run_epi("info " + scene_path("chains.gltf") + " --subdiv-level 1");
  EXPECT_EQ(number_after(info.out, "\ninstanced triangles: "), (long long)triangles[1]) << info.out;
}

TEST(Cli, PngIsTheToneMappedExr) {
  const fs::path dir = temp_dir("png");
  const std::string base = "render " + kCornell + kTinyReference + " --seed 9 -o ";
  ASSERT_EXIT_CODE(run_epi(base + (dir / "linear.exr").string()), 0);
  ASSERT_EXIT_CODE(run_epi(base + (dir / "plain.png").string()), 0);
  ASSERT_EXIT_CODE(run_epi(base + (dir / "bright.png").string() + " --exposure 1"), 0);
  const epi::RgbImage linear = epi::read_image(dir / "linear.exr");
  for (const auto& [file, stops] : {std::pair{"plain.png", 0.0f}, std::pair{"bright.png", 1.0f}}) {
    const epi::RgbImage png = epi::read_image(dir / file);
    ASSERT_EQ(png.width, 16);
    ASSERT_EQ(png.height, 12);
    for (size_t i = 0; i < linear.pixels.size(); i += 3) {
      float expected[3];
      epi::tone_map(&linear.pixels[i], stops, expected);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(png.pixels[i + c], expected[c], 0.006f) << file << " pixel " << i / 3;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// epi reconstruct

TEST(Cli, ReconstructFlagsChangeTheOutput) {
  const fs::path dir = temp_dir("reconstruct");
  const std::string base = "reconstruct " + std::string(EPI_SOURCE_DIR) + "/tests/epi/patterns/wedges.json --density 0.1 --quiet";
  auto run = [&](const std::string& name, const std::string& flags) {
    const EpiRun r = run_epi(base + " " + flags + " -o " + (dir / (name + ".exr")).string() + " --stats " +
                             (dir / (name + ".json")).string());
    EXPECT_EXIT_CODE(r, 0);
    return read_json(dir / (name + ".json"));
  };
  const json base_stats = run("base", ""), again = run("again", "--seed 1");
  const json no_aa = run("no_aa", "--no-aa"), no_complex = run("no_complex", "--no-complex"), seed = run("seed", "--seed 2");
  EXPECT_EQ(read_file(dir / "base.exr"), read_file(dir / "again.exr"));  // --seed 1 is the default
  EXPECT_TRUE(base_stats["antialias"].get<bool>());
  EXPECT_FALSE(no_aa["antialias"].get<bool>());
  EXPECT_NE(read_file(dir / "base.exr"), read_file(dir / "no_aa.exr"));
  EXPECT_TRUE(base_stats["complex_filter"].get<bool>());
  EXPECT_FALSE(no_complex["complex_filter"].get<bool>());
  EXPECT_GT(base_stats["pixels"]["complex"].get<long long>(), 0);
  EXPECT_NE(read_file(dir / "base.exr"), read_file(dir / "no_complex.exr"));
  EXPECT_EQ(seed["seed"].get<int>(), 2);
  EXPECT_NE(read_file(dir / "base.exr"), read_file(dir / "seed.exr"));
}

// ---------------------------------------------------------------------------------------------
// epi edges: the JSON of issue 4, the SVG, the stats

TEST(Cli, EdgesWritesTheJsonOfTheIssueTheSvgAndStats) {
  const fs::path dir = temp_dir("edges");
  const EpiRun run = run_epi("edges " + kCornell + " --size 64x48 -o " + (dir / "e.json").string() + " --svg " +
                             (dir / "e.svg").string() + " --stats " + (dir / "s.json").string());
  ASSERT_EXIT_CODE(run, 0);
  // {"edges":[{"kind":..., "object":..., "a":[x,y,z], "b":[x,y,z]} (+ "blocker", "light" for shadows)]}
  const json doc = read_json(dir / "e.json");
  ASSERT_TRUE(doc.is_object());
  ASSERT_EQ(doc.size(), 1u);
  ASSERT_TRUE(doc["edges"].is_array());
  const std::set<std::string> kinds = {"silhouette", "sharp", "border", "umbral", "penumbral", "shadow"};
  const std::set<std::string> shadow_kinds = {"umbral", "penumbral", "shadow"};
  const std::set<std::string> objects = {"white_walls", "red_wall", "green_wall", "short_block", "tall_block", "ceiling_light"};
  std::map<std::string, size_t> counts;
  for (const json& e : doc["edges"]) {
    ASSERT_TRUE(e.is_object());
    const std::string kind = e.at("kind").get<std::string>();
    ASSERT_TRUE(kinds.count(kind)) << kind;
    ++counts[kind];
    EXPECT_TRUE(objects.count(e.at("object").get<std::string>())) << e;
    for (const char* end : {"a", "b"}) {
      ASSERT_TRUE(e.at(end).is_array() && e.at(end).size() == 3) << e;
      for (const json& v : e.at(end)) EXPECT_TRUE(v.is_number() && std::isfinite(v.get<double>())) << e;
    }
    const bool shadow = shadow_kinds.count(kind) > 0;
    EXPECT_EQ(e.size(), shadow ? 6u : 4u) << e;
    if (shadow) {
      EXPECT_TRUE(objects.count(e.at("blocker").get<std::string>())) << e;
      EXPECT_TRUE(e.at("light").is_string()) << e;
    }
  }
  EXPECT_GT(counts["border"] + counts["silhouette"], 0u);
  EXPECT_GT(counts["umbral"] + counts["penumbral"] + counts["shadow"], 0u) << "the blocks cast shadows";

  // The SVG: one element per line, one path per kind with only M/L commands, as many segments as edges.
  const std::string svg = read_file(dir / "e.svg");
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"64\" height=\"48\"", 0), 0u) << svg.substr(0, 200);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
  const std::regex path_line("<path id=\"([a-z]+)\" fill=\"none\" stroke=\"#[0-9a-f]{6}\" stroke-width=\"[0-9.]+\" "
                             "d=\"((M-?[0-9.e+-]+ -?[0-9.e+-]+L-?[0-9.e+-]+ -?[0-9.e+-]+)+)\"/>");
  std::istringstream lines(svg);
  std::string line;
  size_t paths = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("<path", 0) != 0) continue;
    std::smatch m;
    ASSERT_TRUE(std::regex_match(line, m, path_line)) << line.substr(0, 300);
    ++paths;
    const std::string d = m[2];
    EXPECT_EQ(size_t(std::count(d.begin(), d.end(), 'M')), counts[m[1]]) << m[1];
  }
  size_t kinds_found = 0;
  for (const auto& [kind, n] : counts) kinds_found += n > 0;
  EXPECT_EQ(paths, kinds_found);

  const json stats = read_json(dir / "s.json");
  for (const std::string& kind : kinds) EXPECT_EQ(stats["counts"][kind].get<size_t>(), counts[kind]) << kind;
  for (const char* stage : {"load", "tree_build", "view_edges", "tree_query", "brute_force", "shadows", "write", "total"})
    EXPECT_TRUE(stats["stages_ms"].contains(stage)) << stage;
  EXPECT_GT(stats["memory_bytes"].get<double>(), 0.0);
  EXPECT_EQ(stats["meshes"].size(), 6u);
  EXPECT_EQ(stats["triangles"].get<int>(), 36);
}

// ---------------------------------------------------------------------------------------------
// epi compare

// A 10x10 grey reference and an image differing in two pixels by known display amounts: pixel 3
// by 38/255 (> 0.1) in green, pixel 57 by 64/255 (> 0.2) in red. Display values are k/255 and the
// linear values stay under the tone map's knee, so EXR and PNG files hold the same display values.
struct KnownDifference {
  epi::RgbImage image{10, 10}, reference{10, 10};
  KnownDifference() {
    const float grey = epi::srgb_to_linear(128.0f / 255.0f);
    std::fill(image.pixels.begin(), image.pixels.end(), grey);
    std::fill(reference.pixels.begin(), reference.pixels.end(), grey);
    image.pixels[3 * 3 + 1] = epi::srgb_to_linear(166.0f / 255.0f);
    image.pixels[57 * 3 + 0] = epi::srgb_to_linear(192.0f / 255.0f);
  }
  double rmse() const { return std::sqrt((38.0 * 38.0 + 64.0 * 64.0) / (255.0 * 255.0) / 300.0); }
  double relative_mse() const {  // the documented definition, on linear values
    double sum = 0.0;
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      const double x = image.pixels[i], r = reference.pixels[i];
      sum += (x - r) * (x - r) / (r * r + 0.01);
    }
    return sum / double(image.pixels.size());
  }
};

TEST(Cli, CompareGivesTheKnownDifferences) {
  const fs::path dir = temp_dir("compare");
  const KnownDifference known;
  for (const char* ext : {".exr", ".png"}) {
    const fs::path image = dir / (std::string("image") + ext), reference = dir / (std::string("reference") + ext);
    epi::write_image(image, known.image);
    epi::write_image(reference, known.reference);
    const EpiRun run = run_epi("compare " + image.string() + " " + reference.string() + " --json " + (dir / "c.json").string());
    ASSERT_EXIT_CODE(run, 0);
    EXPECT_NE(run.out.find("10x10"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("by > 0.1: 2.00 %, by > 0.2: 1.00 %"), std::string::npos) << run.out;
    const json c = read_json(dir / "c.json");
    const double tolerance = std::string(ext) == ".png" ? 1e-4 : 1e-6;  // 8-bit decoding round trip
    EXPECT_NEAR(c["display_rmse"].get<double>(), known.rmse(), tolerance) << ext;
    EXPECT_NEAR(c["max_display_error"].get<double>(), 64.0 / 255.0, tolerance) << ext;
    EXPECT_DOUBLE_EQ(c["over_0_1"].get<double>(), 0.02) << ext;
    EXPECT_DOUBLE_EQ(c["over_0_2"].get<double>(), 0.01) << ext;
    EXPECT_NEAR(c["relative_mse"].get<double>(), known.relative_mse(), 1e-3 * known.relative_mse()) << ext;
    EXPECT_EQ(c["width"].get<int>(), 10);
    EXPECT_EQ(c["image"].get<std::string>(), image.string());
    // An image against itself: all zero.
    const EpiRun same = run_epi("compare " + image.string() + " " + image.string() + " --json " + (dir / "s.json").string());
    ASSERT_EXIT_CODE(same, 0);
    const json s = read_json(dir / "s.json");
    for (const char* key : {"display_rmse", "relative_mse", "over_0_1", "over_0_2", "max_display_error"})
      EXPECT_EQ(s[key].get<double>(), 0.0) << key;
  }
  // The difference image: display difference times --diff-scale, as linear values for EXR.
  const EpiRun diff = run_epi("compare " + (dir / "image.exr").string() + " " + (dir / "reference.exr").string() +
                              " --diff " + (dir / "d.exr").string() + " --diff-scale 2");
  ASSERT_EXIT_CODE(diff, 0);
  const epi::RgbImage d = epi::read_image(dir / "d.exr");
  EXPECT_NEAR(epi::linear_to_srgb(d.pixels[3 * 3 + 1]), 2.0 * 38.0 / 255.0, 1e-5);
  EXPECT_NEAR(epi::linear_to_srgb(d.pixels[57 * 3 + 0]), 2.0 * 64.0 / 255.0, 1e-5);
  EXPECT_EQ(std::count(d.pixels.begin(), d.pixels.end(), 0.0f), long(d.pixels.size()) - 2);
  EXPECT_EXIT_CODE(run_epi("compare " + (dir / "image.exr").string() + " " + (dir / "reference.exr").string() +
                           " --diff " + (dir / "image.exr").string()),
                   kFailed);  // an input is never overwritten
  // A linear image against its display-referred copy: display space is where they meet.
  const EpiRun mixed = run_epi("compare " + (dir / "image.exr").string() + " " + (dir / "image.png").string() +
                               " --json " + (dir / "m.json").string());
  ASSERT_EXIT_CODE(mixed, 0);
  EXPECT_LT(read_json(dir / "m.json")["display_rmse"].get<double>(), 1e-3);
  // Exposure applies to linear images: one stop brighter is far from the reference.
  const EpiRun brighter = run_epi("compare " + (dir / "image.exr").string() + " " + (dir / "image.png").string() +
                                  " --exposure 1 --json " + (dir / "b.json").string());
  ASSERT_EXIT_CODE(brighter, 0);
  EXPECT_GT(read_json(dir / "b.json")["over_0_1"].get<double>(), 0.9);  // grey 0.50 -> 0.69
}

TEST(Cli, CompareRefusesMissingUnreadableAndMismatchedImages) {
  const fs::path dir = temp_dir("compare-errors");
  const KnownDifference known;
  epi::write_image(dir / "a.exr", known.image);
  epi::write_image(dir / "small.exr", epi::RgbImage(5, 10));
  write_file(dir / "text.png", "not an image");
  const fs::path json_out = dir / "c.json";
  struct Case {
    std::string args, file, problem;
  };
  const std::vector<Case> cases = {
      {(dir / "missing.exr").string() + " " + (dir / "a.exr").string(), (dir / "missing.exr").string(), "no such file"},
      {(dir / "a.exr").string() + " " + (dir / "missing.exr").string(), (dir / "missing.exr").string(), "no such file"},
      {(dir / "a.exr").string() + " " + (dir / "small.exr").string(), (dir / "small.exr").string(),
       "the reference is 5x10, the image 10x10"},
      {(dir / "text.png").string() + " " + (dir / "a.exr").string(), (dir / "text.png").string(), ""},
      {(dir / "a.exr").string() + " " + dir.string(), dir.string(), "is a folder"},
  };
  for (const Case& c : cases) {
    const EpiRun run = run_epi("compare " + c.args + " --json " + json_out.string());
    EXPECT_EXIT_CODE(run, kFailed);
    EXPECT_EQ(run.out.rfind("epi: " + c.file + ": " + c.problem, 0), 0u) << run.out;
    EXPECT_EQ(count_lines(run.out), 1) << run.out;
    EXPECT_FALSE(fs::exists(json_out)) << c.args;
  }
  const EpiRun bad_json = run_epi("compare " + (dir / "a.exr").string() + " " + (dir / "a.exr").string() + " --json " +
                                  (dir / "no-folder" / "c.json").string());
  EXPECT_EXIT_CODE(bad_json, kFailed);
  EXPECT_NE(bad_json.out.find("no-folder"), std::string::npos) << bad_json.out;
  EXPECT_EXIT_CODE(run_epi("compare " + (dir / "a.exr").string()), kUsage);
}

// The `epi` program as a user meets it: exit codes, error messages, files written or not.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

struct EpiRun {
  int exit_code = -1;
  std::string out;  // stdout and stderr together
};

EpiRun run_epi(const std::string& args) {
  const std::string command = std::string(EPI_BINARY_DIR) + "/bin/epi " + args + " 2>&1";
  EpiRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

fs::path temp_dir() {
  fs::path dir = fs::temp_directory_path() / ("epi-cli-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string scene_path(const std::string& name) { return std::string(EPI_SOURCE_DIR) + "/scenes/" + name; }

void write_file(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

int count_lines(const std::string& text) {
  int lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

}  // namespace

TEST(Cli, NoSubcommandPrintsUsageAndFails) {
  const EpiRun run = run_epi("");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("subcommand"), std::string::npos) << run.out;
}

TEST(Cli, HelpSucceeds) {
  const EpiRun run = run_epi("render --help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.out.find("--spp"), std::string::npos);
  EXPECT_NE(run.out.find("--shader"), std::string::npos);
}

TEST(Cli, UnknownFlagIsRejected) {
  const EpiRun run = run_epi("render " + scene_path("cornell_box.gltf") + " --bogus 3");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("--bogus"), std::string::npos) << run.out;
}

TEST(Cli, BadOptionValuesAreRejected) {
  for (const char* args : {"--size 0x5", "--size 12", "--spp 0", "--shader phong", "--mode fast", "--eye 1,2",
                           "--eye 1,2,x", "--fov 0"}) {
    const EpiRun run = run_epi("render " + scene_path("cornell_box.gltf") + " " + args);
    EXPECT_NE(run.exit_code, 0) << args;
  }
}

TEST(Cli, MissingSceneNamesTheFile) {
  const EpiRun run = run_epi("info /no/such/scene.gltf");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.out.find("/no/such/scene.gltf"), std::string::npos) << run.out;
  EXPECT_EQ(count_lines(run.out), 1) << run.out;
}

TEST(Cli, MalformedSceneGivesOneLineError) {
  const fs::path file = temp_dir() / "broken.gltf";
  write_file(file, "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": 7}");
  const EpiRun run = run_epi("info " + file.string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(run.out.rfind("epi: " + file.string(), 0), 0u) << run.out;
  EXPECT_EQ(count_lines(run.out), 1) << run.out;
}

TEST(Cli, BadOutputFailsBeforeRenderingAndWritesNothing) {
  const fs::path dir = temp_dir() / "bad-output";
  fs::create_directories(dir);
  const EpiRun run = run_epi("render " + scene_path("cornell_box.gltf") + " --spp 4096 --size 2048x2048 -o " +
                          (dir / "image.xyz").string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.out.find("image.xyz"), std::string::npos) << run.out;
  EXPECT_TRUE(fs::is_empty(dir));
  const EpiRun missing_folder = run_epi("render " + scene_path("cornell_box.gltf") + " -o /no/such/folder/a.png");
  EXPECT_EQ(missing_folder.exit_code, 1);
}

TEST(Cli, InfoCountsTheDefaultScene) {
  const EpiRun run = run_epi("info " + scene_path("cornell_box.gltf"));
  ASSERT_EQ(run.exit_code, 0) << run.out;
  for (const char* field : {"objects: ", "triangles: ", "unique edges: ", "lights: ", "cameras: ", "memory:"})
    EXPECT_NE(run.out.find(field), std::string::npos) << field;
  EXPECT_NE(run.out.find("area 1"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("camera path keys: 60"), std::string::npos) << run.out;
}

TEST(Cli, RenderWritesImageAndStats) {
  const fs::path dir = temp_dir();
  const fs::path image = dir / "small.exr";
  const fs::path stats = dir / "small.json";
  const EpiRun run = run_epi("render " + scene_path("cornell_box.gltf") + " --size 24x16 --spp 2 --quiet -o " +
                          image.string() + " --stats " + stats.string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  ASSERT_TRUE(fs::exists(image));
  std::ifstream in(stats);
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_GT(json["stages_ms"]["total"].get<double>(), 0.0);
  EXPECT_GT(json["rays"].get<double>(), 24.0 * 16.0 * 2.0);
  EXPECT_GT(json["mrays_per_s"].get<double>(), 0.0);
  EXPECT_EQ(json["width"].get<int>(), 24);
}

TEST(Cli, RenderIsDeterministicAcrossThreadCounts) {
  const fs::path dir = temp_dir();
  const std::string common = "render " + scene_path("cornell_box.gltf") + " --size 20x20 --spp 3 --seed 7 --quiet -o ";
  ASSERT_EQ(run_epi(common + (dir / "t1.exr").string() + " --threads 1").exit_code, 0);
  ASSERT_EQ(run_epi(common + (dir / "t2.exr").string() + " --threads 2").exit_code, 0);
  std::ifstream a(dir / "t1.exr", std::ios::binary), b(dir / "t2.exr", std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), {}), bytes_b((std::istreambuf_iterator<char>(b)), {});
  EXPECT_GT(bytes_a.size(), 1000u);  // compressed EXR of 20x20 float RGB
  EXPECT_TRUE(bytes_a == bytes_b) << "renders with 1 and 2 threads differ";
}

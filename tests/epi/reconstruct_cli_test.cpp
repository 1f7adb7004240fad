// `epi reconstruct` end to end through run_reconstruct (cli/reconstruct.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "image_io.h"

namespace epi::cli {
namespace {

namespace fs = std::filesystem;

std::string pattern(const std::string& name) { return std::string(EPI_SOURCE_DIR) + "/tests/epi/patterns/" + name; }

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(EPI_BINARY_DIR) / "epi_cli_test";
  fs::create_directories(dir);
  fs::remove(dir / name);
  return dir / name;
}

TEST(ReconstructCli, WritesTheImageAndStats) {
  for (const char* filter : {"epi", "rendercache"}) {
    ReconstructOptions o;
    o.pattern = pattern("checker.json");
    o.density = 0.2;
    o.filter = filter;
    o.output = scratch(std::string(filter) + ".exr").string();
    o.stats = scratch(std::string(filter) + ".json").string();
    o.quiet = true;
    ASSERT_EQ(run_reconstruct(o), 0);
    const RgbImage image = read_image(o.output);
    EXPECT_EQ(image.width, 128);
    EXPECT_EQ(image.height, 128);
    std::ifstream in(o.stats);
    const nlohmann::json stats = nlohmann::json::parse(in);
    EXPECT_EQ(stats["filter"], filter);
    EXPECT_GT(stats["samples"].get<int>(), 2500);
    EXPECT_LT(stats["samples"].get<int>(), 4000);
    EXPECT_GT(stats["pixels"]["simple"].get<int>(), 100);
    EXPECT_LT(stats["mean_abs_error"]["all_pixels"].get<double>(), 0.1);
  }
}

TEST(ReconstructCli, SameSeedSameImage) {
  ReconstructOptions o;
  o.pattern = pattern("discs.json");
  o.quiet = true;
  o.output = scratch("a.exr").string();
  run_reconstruct(o);
  const RgbImage a = read_image(o.output);
  o.output = scratch("b.exr").string();
  o.threads = 1;
  run_reconstruct(o);
  EXPECT_EQ(a.pixels, read_image(o.output).pixels);
}

TEST(ReconstructCli, BadInputFailsCleanlyWithoutOutput) {
  const fs::path bad = scratch("bad.json");
  std::ofstream(bad) << R"({"width":4,"height":4,"polygons":[{"color":[1,0,0],"points":[[0,0],[1,0]]}]})";
  const fs::path out = scratch("never.exr");
  auto expect_failure = [&](ReconstructOptions o, const std::string& fragment) {
    o.output = o.output.empty() ? out.string() : o.output;
    o.quiet = true;
    try {
      run_reconstruct(o);
      FAIL() << "accepted";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
    EXPECT_FALSE(fs::exists(out));
  };
  ReconstructOptions o;
  o.pattern = bad.string();
  expect_failure(o, "bad.json: polygons[0].points");
  o.pattern = pattern("checker.json");
  o.density = 1.5;
  expect_failure(o, "--density");
  o.density = 0.1;
  o.filter = "nearest";
  expect_failure(o, "--filter");
  o.filter = "epi";
  o.pattern = "/nonexistent.json";
  expect_failure(o, "/nonexistent.json");
  o.pattern = pattern("checker.json");
  o.output = "/nonexistent/dir/out.exr";
  expect_failure(o, "/nonexistent/dir");
}

}  // namespace
}  // namespace epi::cli

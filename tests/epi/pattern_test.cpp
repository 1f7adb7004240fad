// PATTERN.json parsing, seeded sampling and the exact reference image.
#include <gtest/gtest.h>

#include "epi/pattern.h"
#include "test_util.h"

namespace epi {
namespace {

void expect_error(const std::string& json, const std::string& fragment) {
  try {
    parse_pattern(json, "p.json");
    FAIL() << "accepted: " << json;
  } catch (const PatternError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("p.json: ", 0), 0u) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
}

TEST(Pattern, BadInputGivesOneLineErrors) {
  expect_error("{", "not valid JSON");
  expect_error("[1,2]", "object");
  expect_error(R"({"height":4})", "'width'");
  expect_error(R"({"width":0,"height":4})", "'width'");
  expect_error(R"({"width":4,"height":1e9})", "'height'");
  expect_error(R"({"width":4,"height":4,"background":[1,2]})", "background");
  expect_error(R"({"width":4,"height":4,"background":[0,0,2]})", "[0,1]");
  expect_error(R"({"width":4,"height":4,"polygons":{}})", "'polygons'");
  expect_error(R"({"width":4,"height":4,"polygons":[{"points":[[0,0],[1,0],[0,1]]}]})", "polygons[0]: missing 'color'");
  expect_error(R"({"width":4,"height":4,"polygons":[{"color":[1,1,1],"points":[[0,0],[1,0]]}]})", "at least 3");
  expect_error(R"({"width":4,"height":4,"polygons":[{"color":[1,1,1],"points":[[0,0],[1,"a"],[0,1]]}]})",
               "points[1]");
  expect_error(R"({"width":4,"height":4,"polygons":[{"color":[1,1,1],"points":[[0,0],[1,1e300],[0,1]]}]})",
               "within 1e7");
  EXPECT_THROW(load_pattern("/nonexistent/p.json"), PatternError);
}

TEST(Pattern, ShippedPatternsLoad) {
  for (const char* name : {"wedges.json", "slivers.json", "checker.json", "discs.json", "closed.json"}) {
    const Pattern p = load_pattern(test::pattern_path(name));
    EXPECT_GT(p.polygons.size(), 0u) << name;
    EXPECT_GT(pattern_edges(p).size(), 3u) << name;
  }
}

TEST(Pattern, SamplingIsSeededAndHasTheRequestedDensity) {
  Pattern p = test::random_pattern(200, 100, 10, 5);
  EpiImage a(200, 100), b(200, 100), c(200, 100);
  const int64_t na = sample_pattern(p, 0.1, 42, a);
  const int64_t nb = sample_pattern(p, 0.1, 42, b);
  sample_pattern(p, 0.1, 43, c);
  EXPECT_EQ(na, nb);
  EXPECT_EQ(a.edge, b.edge);
  EXPECT_EQ(a.color, b.color);
  EXPECT_NE(a.edge, c.edge);
  EXPECT_NEAR(double(na) / 20000.0, 0.1, 0.01);
  EpiImage full(200, 100);
  EXPECT_EQ(sample_pattern(p, 1.0, 1, full), 20000);
}

TEST(Pattern, ExactImageOfKnownCoverage) {
  // A square covering the right half of pixel (1,1) and all of pixel (2,1), later a
  // triangle covering half of pixel (3,2) (under the diagonal).
  Pattern p = parse_pattern(R"({"width":5,"height":4,"background":[0,0,0],"polygons":[
      {"color":[1,0,0],"points":[[1.5,1],[3,1],[3,2],[1.5,2]]},
      {"color":[0,1,0],"points":[[3,2],[4,3],[3,3]]}]})", "p.json");
  const RgbImage e = exact_image(p);
  EXPECT_NEAR(e.at(1, 1)[0], 0.5f, 1e-6);
  EXPECT_NEAR(e.at(2, 1)[0], 1.0f, 1e-6);
  EXPECT_NEAR(e.at(3, 2)[1], 0.5f, 1.0 / 16);
  EXPECT_NEAR(e.at(0, 0)[0], 0.0f, 1e-6);
}

}  // namespace
}  // namespace epi

// The study's pieces (bench/study/study.h): reference cache keys and files, the Pareto front, the CSV.
#include "study.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <functional>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace epi::study {
namespace {

ReferenceKey base_key() {
  ReferenceKey k;
  k.scene_hash = 0x1234, k.width = 64, k.height = 48, k.spp = 16;
  k.camera.eye = {1, 2, 3};
  return k;
}

// Every field of the key changes the file name; equal keys give the same name.
TEST(ReferenceKey, EveryFieldChangesTheFile) {
  const std::filesystem::path dir = "cache";
  const std::filesystem::path base = reference_file(dir, "s", base_key());
  EXPECT_EQ(base, reference_file(dir, "s", base_key()));
  std::vector<std::function<void(ReferenceKey&)>> edits = {
      [](ReferenceKey& k) { k.scene_hash ^= 1; },
      [](ReferenceKey& k) { k.subdiv_level = 2; },
      [](ReferenceKey& k) { k.camera.eye.x = std::nextafter(1.0f, 2.0f); },  // one ulp
      [](ReferenceKey& k) { k.camera.target.z = 1e-30f; },
      [](ReferenceKey& k) { k.camera.up = {0, 0, 1}; },
      [](ReferenceKey& k) { k.camera.yfov_degrees = 60; },
      [](ReferenceKey& k) { k.camera.znear = 0.1f; },
      [](ReferenceKey& k) { k.shader.kind = ShaderKind::gi; },
      [](ReferenceKey& k) { k.shader.area_light_samples = 4; },
      [](ReferenceKey& k) { k.shader.glossy_samples = 2; },
      [](ReferenceKey& k) { k.shader.gi_paths = 2; },
      [](ReferenceKey& k) { k.shader.gi_max_bounces = 2; },
      [](ReferenceKey& k) { k.shader.gi_path_clamp = 5; },
      [](ReferenceKey& k) { k.shader.specular = false; },
      [](ReferenceKey& k) { k.shader.seed = 2; },
      [](ReferenceKey& k) { k.shader.ray_offset = 1e-3f; },
      [](ReferenceKey& k) { k.width = 48, k.height = 64; },  // same pixel count, transposed
      [](ReferenceKey& k) { k.spp = 64; },
  };
  std::set<std::filesystem::path> names = {base};
  for (size_t e = 0; e < edits.size(); ++e) {
    ReferenceKey k = base_key();
    edits[e](k);
    const std::filesystem::path file = reference_file(dir, "s", k);
    EXPECT_NE(file, base) << "edit " << e;
    EXPECT_TRUE(names.insert(file).second) << "edit " << e << " collides";
    EXPECT_EQ(file.parent_path(), dir);
    EXPECT_EQ(file.extension(), ".exr");  // linear floats: the reference keeps its values
  }
}

RgbImage flat(int w, int h, float v) {
  RgbImage image;
  image.width = w, image.height = h, image.pixels.assign(size_t(w) * size_t(h) * 3, v);
  return image;
}

TEST(ReferenceCache, RendersOnceThenReadsAndRerendersWhenTheFileIsBad) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "study_reference_cache";
  std::filesystem::remove_all(dir);
  const ReferenceKey key = base_key();
  int renders = 0;
  auto render = [&] { return ++renders, flat(key.width, key.height, 0.25f + 1.0f * float(renders)); };
  bool rendered = false;
  RgbImage a = cached_reference(dir, "s", key, render, &rendered);
  EXPECT_TRUE(rendered);
  EXPECT_EQ(renders, 1);
  RgbImage b = cached_reference(dir, "s", key, render, &rendered);
  EXPECT_FALSE(rendered);
  EXPECT_EQ(renders, 1);
  EXPECT_EQ(a.pixels, b.pixels);  // exact: the cache keeps linear floats (1.25 is no 8-bit value)
  EXPECT_FLOAT_EQ(b.pixels[0], 1.25f);

  // Another key (a different spp) is another file: rendered.
  ReferenceKey other = key;
  other.spp = 4;
  cached_reference(dir, "s", other, render, &rendered);
  EXPECT_TRUE(rendered);
  EXPECT_EQ(renders, 2);

  // A truncated file is rendered again and replaced.
  const std::filesystem::path file = reference_file(dir, "s", key);
  std::filesystem::resize_file(file, 20);
  RgbImage c = cached_reference(dir, "s", key, render, &rendered);
  EXPECT_TRUE(rendered);
  EXPECT_EQ(renders, 3);
  RgbImage d = cached_reference(dir, "s", key, render, &rendered);
  EXPECT_FALSE(rendered);
  EXPECT_EQ(c.pixels, d.pixels);
  std::filesystem::remove_all(dir);
}

TEST(FileHash, FollowsTheBytesAndNamesAMissingFile) {
  const std::filesystem::path file = std::filesystem::path(testing::TempDir()) / "study_hash.txt";
  { std::ofstream(file) << "scene a"; }
  const uint64_t a = file_hash(file);
  { std::ofstream(file) << "scene b"; }
  EXPECT_NE(a, file_hash(file));
  EXPECT_EQ(file_hash(file), fnv1a("scene b"));
  std::filesystem::remove(file);
  try {
    file_hash(file);
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("study_hash.txt"), std::string::npos);
  }
}

TEST(Pareto, SmallCases) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // (1, 5) (2, 3) (3, 4) (4, 1) (2, 3) : (3, 4) is dominated by (2, 3); the duplicate stays.
  std::vector<double> t = {1, 2, 3, 4, 2}, e = {5, 3, 4, 1, 3};
  EXPECT_EQ(pareto_front(t, e), (std::vector<bool>{true, true, false, true, true}));
  // Same time, more error: dominated; same error, more time: dominated.
  t = {1, 1, 2}, e = {2, 3, 2};
  EXPECT_EQ(pareto_front(t, e), (std::vector<bool>{true, false, false}));
  // Non-finite points are off the front and dominate nothing.
  t = {nan, 1, 2, std::numeric_limits<double>::infinity()}, e = {0, 5, 1, 0};
  EXPECT_EQ(pareto_front(t, e), (std::vector<bool>{false, true, true, false}));
  EXPECT_TRUE(pareto_front({}, {}).empty());
  EXPECT_THROW(pareto_front(std::vector<double>{1}, std::vector<double>{}), std::invalid_argument);
}

// Against the definition on random clouds: a point is on the front iff nothing dominates it, and
// the front sorted by time has strictly falling error.
TEST(Pareto, RandomCloudsAgainstTheDefinition) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> v(0, 9);  // small range: many ties
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> t(size_t(1 + trial % 30)), e(t.size());
    for (size_t i = 0; i < t.size(); ++i) t[i] = v(rng), e[i] = v(rng);
    const std::vector<bool> front = pareto_front(t, e);
    std::vector<std::pair<double, double>> on;
    for (size_t i = 0; i < t.size(); ++i) {
      bool dominated = false;
      for (size_t j = 0; j < t.size(); ++j)
        dominated |= t[j] <= t[i] && e[j] <= e[i] && (t[j] < t[i] || e[j] < e[i]);
      ASSERT_EQ(front[i], !dominated) << "trial " << trial << " point " << i;
      if (front[i]) on.push_back({t[i], e[i]});
    }
    ASSERT_FALSE(on.empty());
    std::sort(on.begin(), on.end());
    for (size_t k = 1; k < on.size(); ++k)
      ASSERT_TRUE(on[k] == on[k - 1] || (on[k].first > on[k - 1].first && on[k].second < on[k - 1].second));
  }
}

SummaryRow row(std::string scene, std::string knob, std::string setting, double ms, double rmse) {
  SummaryRow r;
  r.scene = scene, r.camera = "path", r.knob = knob, r.setting = setting, r.cpu_ms = ms, r.rmse = rmse;
  r.ms = 1000 - ms;  // wall time, not the front's axis: reversed, so a front on it would differ
  r.is_default = knob == "default";
  return r;
}

TEST(Pareto, MarkGroupsByScenePerKnobWithTheDefault) {
  std::vector<SummaryRow> rows = {
      row("a", "default", "default", 10, 0.10),
      row("a", "budget", "0.01", 5, 0.20),   // faster, worse: on both fronts
      row("a", "budget", "0.05", 20, 0.12),  // slower and worse than the default: off both
      row("a", "antialias", "off", 9, 0.25),  // beaten by budget 0.01 (5 ms, 0.20), not by the default
      row("a", "baseline", "raytrace", 4, 0.30),
      row("b", "default", "default", 100, 1.0),  // another scene: its own group
      row("b", "budget", "0.01", 50, 2.0),
      row("a", "budget", "0.01", 1, 0.01),  // a at another size: its own group, beats nothing above
  };
  rows.back().width = 1920;
  mark_pareto(rows);
  EXPECT_TRUE(rows[0].pareto_all && rows[0].pareto_knob);
  EXPECT_TRUE(rows[1].pareto_all && rows[1].pareto_knob);
  EXPECT_FALSE(rows[2].pareto_all || rows[2].pareto_knob);
  EXPECT_FALSE(rows[3].pareto_all);
  EXPECT_TRUE(rows[3].pareto_knob);  // within {antialias off, default} it is the faster one
  EXPECT_TRUE(rows[4].pareto_all && rows[4].pareto_knob);  // the baseline: as the scene's front
  EXPECT_TRUE(rows[5].pareto_all && rows[6].pareto_all);  // b's rows do not compete with a's
  EXPECT_TRUE(rows[7].pareto_all);
}

TEST(Csv, HeaderMatchesRowsAndQuotes) {
  SummaryRow s = row("scene, with \"comma\"", "edges", "+hard+soft shadows", 1.5, 0.01);
  s.ms_no_shade = std::numeric_limits<double>::quiet_NaN();
  s.frames = 7, s.evaluated = 3, s.pareto_all = true, s.width = 640, s.height = 480;
  const std::vector<std::string> fields = split_csv_line(csv_line(s));
  ASSERT_EQ(fields.size(), summary_columns().size());
  EXPECT_EQ(split_csv_line(csv_header(summary_columns())), summary_columns());
  auto at = [&](const std::string& column) {
    const auto it = std::find(summary_columns().begin(), summary_columns().end(), column);
    EXPECT_NE(it, summary_columns().end()) << column;
    return fields[size_t(it - summary_columns().begin())];
  };
  EXPECT_EQ(at("scene"), "scene, with \"comma\"");
  EXPECT_EQ(at("setting"), "+hard+soft shadows");
  EXPECT_EQ(at("cpu_ms"), "1.5");
  EXPECT_EQ(at("ms"), "998.5");
  EXPECT_EQ(at("ms_no_shade"), "");  // not separable: empty, not "nan"
  EXPECT_EQ(at("frames"), "7");
  EXPECT_EQ(at("evaluated"), "3");
  EXPECT_EQ(at("width"), "640");
  EXPECT_EQ(at("height"), "480");
  EXPECT_EQ(at("pareto_all"), "1");
  EXPECT_EQ(at("pareto_knob"), "0");
  EXPECT_EQ(at("is_default"), "0");

  FrameRow f;
  f.scene = "s", f.camera = "still", f.knob = "k", f.setting = "v", f.frame = 12, f.ms = 3, f.evaluated = true, f.rmse = 0.5;
  const std::vector<std::string> ff = split_csv_line(csv_line(f));
  ASSERT_EQ(ff.size(), frame_columns().size());
  EXPECT_EQ(ff[4], "12");
  EXPECT_EQ(ff[9], "0.5");
  EXPECT_EQ(split_csv_line(csv_header(frame_columns())), frame_columns());
}

TEST(Csv, SummaryRoundTripsAndBadFilesAreNamed) {
  const std::filesystem::path file = std::filesystem::path(testing::TempDir()) / "study_roundtrip.csv";
  SummaryRow a = row("a, \"quoted\"", "budget", "0.01", 5.5, 0.125);
  a.width = 256, a.height = 128, a.frames = 60, a.evaluated = 4, a.ms_no_shade = std::numeric_limits<double>::quiet_NaN();
  a.relative_mse = 0.25, a.over_0_1 = 0.5, a.over_0_2 = 0.0625, a.rmse_last = 0.375, a.pareto_knob = true;
  SummaryRow b = row("b", "default", "default", 7, 0.5);
  write_summary(file, {a, b});
  const std::vector<SummaryRow> back = read_summary(file);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(csv_line(back[0]), csv_line(a));
  EXPECT_EQ(csv_line(back[1]), csv_line(b));
  EXPECT_TRUE(std::isnan(back[0].ms_no_shade));
  EXPECT_TRUE(back[1].is_default);

  std::ofstream(file) << "scene,camera\nx,y\n";
  EXPECT_THROW(read_summary(file), std::runtime_error);
  {
    std::ofstream out(file);
    out << csv_header(summary_columns()) << "\n" << csv_line(a) << "\n";
    out << "b,path,budget,0.1,64,64,0,1,1,abc,1,1,1,1,1,1,1,0,0\n";
  }
  try {
    read_summary(file);
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":3: ms 'abc'"), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace epi::study

// The stepper: every stage has steps for pixels of every class, stepping back then forward gives
// identical frames, every preset exports headless (PNG, SVG, trace.json, GIF), and EPI snapshots
// round-trip exactly (from a pattern and from a rendered frame) and reject bad files.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <gif_lib.h>

#include "draw.h"
#include "export.h"
#include "model.h"
#include "presets.h"
#include "epi/interpolate.h"
#include "render/hole_fill.h"
#include "render/sparse_blend.h"
#include "render/renderer.h"
#include "snapshot.h"
#include "steps.h"
#include "test_scenes.h"

namespace epi::vis {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("epi-visualizer-test-" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir;
}

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// A pixel of each class in the model, or -1.
std::array<std::pair<int, int>, 3> pixel_per_class(const Model& m) {
  std::array<std::pair<int, int>, 3> found{{{-1, -1}, {-1, -1}, {-1, -1}}};
  for (int y = 0; y < m.height(); ++y)
    for (int x = 0; x < m.width(); ++x) {
      const int type = m.type_at(x, y), k = type == kTypeEmpty ? 0 : type == kTypeComplex ? 2 : 1;
      if (found[size_t(k)].first < 0) found[size_t(k)] = {x, y};
    }
  return found;
}

TEST(Steps, EveryStageHasStepsForEveryPixelClass) {
  int checked = 0;
  for (const Preset& preset : presets()) {
    for (double density : {0.05, 0.5}) {
      const Model model(pattern_source(preset.pattern, preset.name, density, 3));
      for (const auto& [x, y] : pixel_per_class(model)) {
        if (x < 0) continue;
        const PixelTrace trace = model.tracer().trace(x, y);
        const std::vector<Step> steps = build_steps(model, trace);
        std::set<int> stages;
        int previous = 1;
        for (const Step& s : steps) {
          SCOPED_TRACE(preset.name + " (" + std::to_string(x) + ", " + std::to_string(y) + ") stage " + std::to_string(s.stage));
          EXPECT_GE(s.stage, previous);  // stages in order
          previous = s.stage;
          stages.insert(s.stage);
          EXPECT_FALSE(s.caption.empty());
          EXPECT_FALSE(s.section.empty());
          EXPECT_EQ(s.caption.find('\n'), std::string::npos);
        }
        EXPECT_EQ(stages.size(), size_t(kStageCount)) << preset.name;
        // The reachability stage animates all 24 offsets unless the 5x5 is all empty.
        int reach_steps = 0;
        for (const Step& s : steps) reach_steps += s.stage == 4;
        EXPECT_EQ(reach_steps, trace.reach_fast_path ? 2 : 26) << preset.name;
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 30);  // the presets hold pixels of all three classes
}

// The Cornell lamp's corner (docs/render.md, "Bright colours"): two crossings on different
// sides, complex because the centre lines show the corner; the step says so and shows them.
TEST(Steps, ACornerPixelSaysWhyItIsComplex) {
  Pattern p;
  p.width = 16, p.height = 10;
  p.background = {0.1f, 0.1f, 0.1f};
  p.polygons.push_back({{17.0f, 12.0f, 4.0f}, {{4.494, 2.038}, {16.0, 2.038}, {16.0, 9.0}, {6.0, 9.0}}});
  const Model model(pattern_source(p, "lamp corner", 0.5, 3));
  ASSERT_EQ(model.type_at(4, 2), kTypeComplex);
  bool said = false;
  for (const Step& s : build_steps(model, model.tracer().trace(4, 2)))
    if (s.section == "4.2 Edge representation" && s.values.contains("edge code")) {
      EXPECT_NE(s.caption.find("corner"), std::string::npos) << s.caption;
      EXPECT_EQ(s.view.crossings, 2);  // with the centre lines
      said = true;
    }
  EXPECT_TRUE(said);
}

TEST(Steps, BackThenForwardGivesIdenticalFrames) {
  const Preset& preset = *find_preset("checkerboard");
  const Model model(pattern_source(preset.pattern, preset.name, 0.25, 1));
  const PixelTrace trace = model.tracer().trace(preset.pixel_x, preset.pixel_y);
  const std::vector<Step> steps = build_steps(model, trace);
  std::vector<std::vector<uint8_t>> forward;
  for (int i = 0; i < int(steps.size()); ++i) forward.push_back(render_rgb(model, trace, steps, i));
  for (int i = int(steps.size()) - 1; i >= 0; --i) ASSERT_EQ(render_rgb(model, trace, steps, i), forward[size_t(i)]) << i;
  for (int i = 1; i < int(steps.size()); ++i) {
    EXPECT_NE(forward[size_t(i)], forward[size_t(i - 1)]) << "step " << i + 1 << " looks like the one before";
  }
  // And a re-traced pixel (the window re-traces on a click) gives the same frames.
  const PixelTrace again = model.tracer().trace(preset.pixel_x, preset.pixel_y);
  EXPECT_EQ(render_rgb(model, again, build_steps(model, again), 20), forward[20]);
}

TEST(Export, EveryPresetExportsHeadless) {
  for (const Preset& preset : presets()) {
    const Model model(pattern_source(preset.pattern, preset.name, 0.25, 1));
    const PixelTrace trace = model.tracer().trace(preset.pixel_x, preset.pixel_y);
    const std::vector<Step> steps = build_steps(model, trace);
    const fs::path dir = temp_dir(preset.name);
    export_steps(model, trace, steps, dir.string(), 0.5);
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
    EXPECT_EQ(files, 2 * steps.size() + 2) << preset.name;
    const nlohmann::json j = nlohmann::json::parse(read_file(dir / "trace.json"));
    ASSERT_EQ(j["steps"].size(), steps.size());
    EXPECT_EQ(j["pixel"][0], preset.pixel_x);
    EXPECT_EQ(j["steps"][0]["stage"], 1);
    EXPECT_EQ(j["steps"].back()["stage"], kStageCount);
    EXPECT_EQ(j["final"]["result"][0].get<float>(), trace.result[0]);
    EXPECT_EQ(read_file(dir / "step_001.png").substr(1, 3), "PNG");
    EXPECT_NE(read_file(dir / "step_001.svg").find("<svg"), std::string::npos);
    // The animation decodes (giflib) to one frame per step; the first frame is the first PNG's
    // drawing within the palette's precision.
    int error = 0;
    GifFileType* gif = DGifOpenFileName((dir / "animation.gif").c_str(), &error);
    ASSERT_NE(gif, nullptr);
    ASSERT_EQ(DGifSlurp(gif), GIF_OK);
    EXPECT_EQ(size_t(gif->ImageCount), steps.size());
    EXPECT_EQ(gif->SWidth, kCanvasWidth);
    EXPECT_EQ(gif->SHeight, kCanvasHeight);
    const std::vector<uint8_t> first = render_rgb(model, trace, steps, 0);
    const GifColorType* palette = gif->SColorMap->Colors;
    size_t far = 0;
    for (size_t i = 0; i < size_t(kCanvasWidth) * kCanvasHeight; ++i) {
      const GifColorType c = palette[gif->SavedImages[0].RasterBits[i]];
      far += std::abs(c.Red - first[3 * i]) > 24 || std::abs(c.Green - first[3 * i + 1]) > 24 || std::abs(c.Blue - first[3 * i + 2]) > 24;
    }
    EXPECT_LT(far, first.size() / 3 / 100) << preset.name;  // under 1 % of pixels off by more than 24 levels
    DGifCloseFile(gif, &error);
    EXPECT_FALSE(fs::exists(dir.string() + ".partial"));
  }
}

TEST(Export, RefusesAFolderThatIsNotEmptyAndLeavesNothing) {
  const Preset& preset = *find_preset("wedges");
  const Model model(pattern_source(preset.pattern, preset.name, 0.25, 1));
  const PixelTrace trace = model.tracer().trace(1, 1);
  const std::vector<Step> steps = build_steps(model, trace);
  const fs::path dir = temp_dir("busy");
  fs::create_directories(dir);
  std::ofstream(dir / "keep.txt") << "mine";
  EXPECT_THROW(export_steps(model, trace, steps, dir.string()), std::runtime_error);
  EXPECT_EQ(read_file(dir / "keep.txt"), "mine");
  EXPECT_THROW(export_steps(model, trace, steps, (dir / "no" / "such" / "parent").string()), std::runtime_error);
}

void expect_same_reconstruction(const Snapshot& a, const Snapshot& b) {
  EpiImage ea = a.epi, eb = b.epi;
  const Reconstruction ra = reconstruct_oracle(ea, a.masks, a.settings);
  const Reconstruction rb = reconstruct_oracle(eb, b.masks, b.settings);
  EXPECT_EQ(ra.image.pixels, rb.image.pixels);
  EXPECT_EQ(ra.priority, rb.priority);
}

TEST(Snapshot, PatternRoundTripIsExact) {
  const Source src = pattern_source(find_preset("tangent")->pattern, "tangent", 0.3, 5);
  Snapshot snap{src.epi, src.masks, src.segments, src.settings};
  snap.settings.fill = false;
  const fs::path file = temp_dir("snap") += ".epis";
  save_snapshot(snap, file.string());
  const Snapshot back = load_snapshot(file.string());
  EXPECT_EQ(back.epi.edge, snap.epi.edge);
  EXPECT_EQ(back.epi.color, snap.epi.color);
  EXPECT_EQ(back.masks.top, snap.masks.top);
  EXPECT_EQ(back.masks.left, snap.masks.left);
  EXPECT_EQ(back.masks.centre_h, snap.masks.centre_h);
  EXPECT_EQ(back.masks.centre_v, snap.masks.centre_v);
  ASSERT_EQ(back.segments.size(), snap.segments.size());
  for (size_t i = 0; i < snap.segments.size(); ++i) EXPECT_EQ(back.segments[i].x1, snap.segments[i].x1);
  EXPECT_FALSE(back.settings.fill);
  EXPECT_TRUE(back.settings.antialias);
  expect_same_reconstruction(snap, back);
  EXPECT_TRUE(is_snapshot_file(file.string()));
}

// The frame loop's settings of the snapshot tests: epi mode, 64x48, sync, seed 3.
render::FrameSettings snapshot_frame_settings(double sample_budget) {
  render::FrameSettings settings;
  settings.mode = render::RenderMode::epi, settings.width = 64, settings.height = 48;
  settings.sample_budget = sample_budget, settings.sync = true, settings.seed = 3;
  return settings;
}

TEST(Snapshot, RenderedFrameRoundTripGivesTheFrameExactly) {
  const Scene scene = test::plane_and_box();
  RayScene ray_scene(scene);
  const Shader shader(ray_scene, ShaderSettings{});
  render::FrameSettings settings = snapshot_frame_settings(0.08);
  settings.fill_holes = false;    // the frame loop's hole filling and sparse blend come after the
  settings.sparse_blend = false;  // EPI (core/render), not in it
  render::FrameRenderer renderer(scene, ray_scene, shader, settings);
  const RgbImage* frame = nullptr;
  for (int k = 0; k < 4; ++k) frame = &renderer.render(scene.cameras[0]);
  const fs::path file = temp_dir("frame") += ".epis";
  save_snapshot({renderer.epi(), renderer.masks(), renderer.segments(), renderer.reconstruct_settings()}, file.string());
  const Snapshot back = load_snapshot(file.string());
  EpiImage epi = back.epi;
  const Reconstruction r = reconstruct_oracle(epi, back.masks, back.settings);
  EXPECT_EQ(r.image.pixels, frame->pixels);  // bit for bit the frame the renderer showed
  EXPECT_EQ(r.priority, renderer.priority());
  EXPECT_GT(back.segments.size(), 0u);
  // And the visualizer follows it like a pattern.
  const Model model(load_source(file.string(), 0.25, 1));
  EXPECT_FALSE(model.source().pattern.has_value());
  const PixelTrace t = model.tracer().trace(32, 24);
  EXPECT_EQ(build_steps(model, t).back().stage, kStageCount);
}

// With the frame loop's hole fill on (the default), the renderer reconstructs with
// blend_unreached_near_edges off; its snapshot must say so, or the visualizer shows blends the
// frame never had. The snapshot's reconstruction, sparse-blended and hole-filled as the renderer
// does, is the frame.
TEST(Snapshot, RenderedFrameWithHoleFillCarriesTheRenderersReconstructSettings) {
  const Scene scene = test::plane_and_box();
  RayScene ray_scene(scene);
  const Shader shader(ray_scene, ShaderSettings{});
  const render::FrameSettings settings = snapshot_frame_settings(0.02);
  ASSERT_TRUE(settings.fill_holes);
  render::FrameRenderer renderer(scene, ray_scene, shader, settings);
  const RgbImage* frame = nullptr;
  for (int k = 0; k < 2; ++k) frame = &renderer.render(scene.cameras[0]);
  const fs::path file = temp_dir("holes") += ".epis";
  save_snapshot({renderer.epi(), renderer.masks(), renderer.segments(), renderer.reconstruct_settings()}, file.string());
  const Snapshot back = load_snapshot(file.string());
  EXPECT_FALSE(back.settings.blend_unreached_near_edges);
  EpiImage epi = back.epi;
  Reconstruction r = reconstruct_oracle(epi, back.masks, back.settings);
  EXPECT_EQ(r.priority, renderer.priority());
  const RgbImage unfilled = r.image;
  // The sparse blend and the hole fill as the renderer applies them (core/render/renderer.cpp).
  ASSERT_TRUE(settings.sparse_blend);
  render::SparseBlendScratch scratch;
  render::sparse_blend(r.image, back.epi, renderer.edge_pixels(), settings.sparse, scratch);
  const size_t n = r.priority.size();
  std::vector<uint8_t> holes(n), barrier(n);
  for (size_t i = 0; i < n; ++i) {
    const float* c = &r.image.pixels[3 * i];
    holes[i] = r.priority[i] >= kMaxPriority && c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f;
    barrier[i] = (renderer.edge_pixels()[i] & (render::kDepthEdge | render::kSharpEdge)) != 0;
  }
  render::fill_holes(r.image, holes, barrier);
  EXPECT_EQ(r.image.pixels, frame->pixels);
  // The setting matters in this frame: with the blend on, some unreached pixel beside an edge
  // takes a colour the frame does not show.
  ReconstructSettings blend = back.settings;
  blend.blend_unreached_near_edges = true;
  epi = back.epi;
  const Reconstruction b = reconstruct_oracle(epi, back.masks, blend);
  EXPECT_NE(b.image.pixels, unfilled.pixels);
  // An older file (bit 4 clear) keeps the blend on.
  Snapshot old = back;
  old.settings.blend_unreached_near_edges = true;
  save_snapshot(old, file.string());
  EXPECT_TRUE(load_snapshot(file.string()).settings.blend_unreached_near_edges);
}

TEST(Snapshot, BadFilesGetOneClearLine) {
  const Source src = pattern_source(find_preset("corners")->pattern, "corners", 0.3, 5);
  const std::string good = snapshot_bytes({src.epi, src.masks, src.segments, src.settings});
  const fs::path file = temp_dir("bad") += ".epis";
  auto expect_error = [&](const std::string& bytes, const std::string& words) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    try {
      load_snapshot(file.string());
      ADD_FAILURE() << "no error for " << words;
    } catch (const SnapshotError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  };
  expect_error(good.substr(0, 5), "truncated");
  expect_error(good.substr(0, good.size() / 2), "truncated");
  expect_error(good.substr(0, good.size() - 3), "truncated");
  expect_error(good + "x", "unexpected bytes");
  expect_error("NOTASNAP" + good.substr(8), "not an EPI snapshot");
  std::string huge = good;
  huge[8] = huge[9] = huge[10] = huge[11] = char(0xff);
  expect_error(huge, "image size");
  std::string zero = good;
  zero[8] = zero[9] = zero[10] = zero[11] = 0;
  expect_error(zero, "image size");
  std::string flags = good;
  flags[16] = char(0x40);
  expect_error(flags, "unknown flags");
  std::string nan = good;
  const double bad = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&nan[nan.size() - 8], &bad, 8);
  expect_error(nan, "not finite");
  std::string count = good;
  const uint64_t many = uint64_t(1) << 60;
  std::memcpy(&count[good.size() - 8 - 32 * src.segments.size()], &many, 8);
  expect_error(count, "segment count");
  EXPECT_THROW(load_snapshot((file.string() + ".missing")), SnapshotError);
}

}  // namespace
}  // namespace epi::vis

// The speed/accuracy study (issue 15, docs/tradeoff.md): for each bundled scene, along its camera
// path and at a still view, renders with each setting of each knob (one knob varied at a time from
// the defaults) and with the baselines (1-spp ray tracing, progressive ray tracing at equal time,
// the render cache), and records each frame's time (with and without shading; frames run in sync
// mode, so shading is inside the frame and timed apart) and its error against a converged reference
// of that view (io/image/image_compare: display RMSE, relative MSE, outlier shares, as `epi compare`).
// References are cached on disk (study.h, cached_reference), so re-runs are cheap.
//   epi_study [--quick] [--scenes a,b] [--knobs k,l] [--cameras path,still] [--size N|WxH]
//             [--path-frames N] [--frames N] [--ref-spp N] [--shader direct|glossy|gi]
//             [--out DIR] [--cache DIR] [--list]
//   epi_study --mark study.csv     (marks the Pareto fronts again, e.g. after concatenating runs)
// Writes DIR/study.csv (one row per scene, camera and setting) and DIR/study_frames.csv (per frame);
// bench/study/plot_study.py draws the plots.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>

#include "image_compare.h"
#include "load_scene.h"
#include "render/camera_path.h"
#include "render/renderer.h"
#include "simd/row_kernels.h"
#include "shade/render_image.h"
#include "study.h"

namespace {

using namespace epi;
using namespace epi::render;
using namespace epi::study;
using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }
// Process CPU time (all threads), ms: what a frame costs whatever else the machine runs.
double cpu_ms() { return double(std::clock()) * 1000.0 / CLOCKS_PER_SEC; }

// The median (NaN if any is NaN): frame times on a loaded machine have spikes a mean would follow.
double median(std::vector<double> v) {
  if (v.empty() || std::any_of(v.begin(), v.end(), [](double x) { return std::isnan(x); })) return kNaN;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

enum class Baseline { none, raytrace, progressive, rendercache };

// One run's settings: the frame loop's, the shader's, the scene's subdivision, the thread count.
struct Config {
  FrameSettings frame;
  ShaderSettings shader;
  int subdiv = -1;   // -1: as the file says
  int threads = 0;   // 0: all cores
  Baseline baseline = Baseline::none;
};

struct Setting {
  std::string knob, name;
  std::function<void(Config&)> apply;
};

struct Options {
  std::vector<std::string> scenes = {"cornell_box", "torus_capsule", "chains", "rooms", "grid_dragon"};
  std::vector<std::string> knobs;  // empty: all
  std::vector<std::string> cameras = {"path", "still"};
  int width = 256, height = 256, path_frames = 120, frames = 4, ref_spp = 32;
  ShaderKind shader = ShaderKind::direct;
  std::string out = "build/study", cache = "build/study-cache";
};

// A whole number for option `what`, or a clear error.
int parse_int(const std::string& what, const std::string& text) {
  size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw std::invalid_argument(what + " " + text + ": not a whole number");
  return v;
}

int hardware_threads() { return int(std::max(1u, std::thread::hardware_concurrency())); }

// Every knob and its settings other than the default (which runs once, as knob "default").
std::vector<Setting> all_settings() {
  std::vector<Setting> s;
  for (double b : {0.005, 0.01, 0.05, 0.1}) {
    char name[32];
    std::snprintf(name, sizeof name, "%g", b);
    s.push_back({"budget", name, [b](Config& c) { c.frame.sample_budget = b; }});
  }
  s.push_back({"antialias", "off", [](Config& c) { c.frame.antialias = false; }});
  s.push_back({"complex_filter", "off", [](Config& c) { c.frame.complex_filter = false; }});
  s.push_back({"edges", "none", [](Config& c) { c.frame.view_edges = false, c.frame.shadow_edges = false; }});
  s.push_back({"edges", "silhouettes", [](Config& c) { c.frame.sharp_border_edges = false, c.frame.shadow_edges = false; }});
  s.push_back({"edges", "+sharp+border", [](Config& c) { c.frame.shadow_edges = false; }});
  s.push_back({"edges", "+hard+soft shadows", [](Config& c) { c.frame.soft_shadow_edges = true; }});
  s.push_back({"punctual_highlights", "off", [](Config& c) { c.frame.cache.punctual_highlight_share = render::PointCacheSettings::kNoPunctualHighlights; }});
  s.push_back({"edge_finder", "tree", [](Config& c) { c.frame.edge_finder.force = 1; }});
  s.push_back({"edge_finder", "brute force", [](Config& c) { c.frame.edge_finder.force = -1; }});
  for (int level : {1, 2, 3})
    s.push_back({"subdivision", "level " + std::to_string(level), [level](Config& c) { c.subdiv = level; }});
  for (double f : {1.0 / 16, 0.25, 4.0}) {
    char name[32];
    std::snprintf(name, sizeof name, "x%g", f);
    s.push_back({"shader_samples", name, [f](Config& c) {
                   auto scale = [f](int& n) { n = std::max(1, int(std::lround(n * f))); };
                   scale(c.shader.area_light_samples), scale(c.shader.glossy_samples), scale(c.shader.glossy_light_samples);
                   scale(c.shader.gi_paths);
                 }});
  }
  for (double f : {1.0, 2.0, 4.0}) {  // below 1 the cache clamps to 1 (point_cache.cpp)
    char name[32];
    std::snprintf(name, sizeof name, "x%g pixels", f);
    s.push_back({"cache_size", name, [f](Config& c) { c.frame.cache.capacity_factor = f; }});
  }
  s.push_back({"refine", "off", [](Config& c) { c.frame.cache.refine = false; }});
  for (int most : {2, 4, 8})
    s.push_back({"sparse_effort", std::to_string(most), [most](Config& c) { c.frame.sparse_effort = most; }});
  s.push_back({"schedule", "tiled (fused)", [](Config& c) { c.frame.stage_timings = false; }});
  s.push_back({"simd", "oracle", [](Config& c) { c.frame.kernels.oracle = true; }});
  for (int64_t t : simd::compiled_targets())
    s.push_back({"simd", simd::row_kernels(t).target_name, [t](Config& c) { c.frame.kernels.target = t; }});
  for (int n = 1; n < hardware_threads(); n *= 2)
    s.push_back({"threads", std::to_string(n), [n](Config& c) { c.threads = n; }});
  s.push_back({"baseline", "raytrace 1spp", [](Config& c) { c.baseline = Baseline::raytrace; }});
  s.push_back({"baseline", "progressive (equal time)", [](Config& c) { c.baseline = Baseline::progressive; }});
  s.push_back({"baseline", "render cache", [](Config& c) { c.baseline = Baseline::rendercache; }});
  return s;
}

// A scene loaded at one subdivision level, with its ray scene.
struct Loaded {
  Loaded(const std::string& file, int subdiv)
      : scene(load_scene(file, LoadOptions{.subdiv_level_override = subdiv})), ray_scene(scene) {}
  Scene scene;
  RayScene ray_scene;
};

// The views of one camera ("path" or "still") and the frames compared with a reference.
struct Views {
  std::string camera;
  std::vector<Camera> cameras;  // one per frame
  std::vector<int> evaluated;   // frame indices, ascending
  std::vector<RgbImage> references;  // one per evaluated frame
};

struct Result {
  std::vector<FrameRow> frames;
  SummaryRow summary;
};

class Study {
 public:
  Study(const Options& o, const std::string& name) : o_(o), name_(name), file_(scene_file(name)) {
    scene_hash_ = file_hash(file_);
  }

  static std::string scene_file(const std::string& name) {
    if (name.find('/') != std::string::npos || name.ends_with(".gltf")) return name;
    return std::string(EPI_SOURCE_DIR) + "/scenes/" + name + ".gltf";
  }

  Loaded& loaded(int subdiv) {
    auto& slot = loaded_[subdiv];
    if (!slot) slot = std::make_unique<Loaded>(file_, subdiv);
    return *slot;
  }

  bool has_subdivision() {
    for (const Mesh& m : loaded(-1).scene.meshes)
      if (m.subdivided) return true;
    return false;
  }

  Views views(const std::string& camera) {
    const Scene& scene = loaded(-1).scene;
    Views v;
    v.camera = camera;
    const CameraPath path = scene_camera_path(scene, o_.path_frames);
    const Camera still = scene.cameras.empty() ? Camera{} : scene.cameras[0];
    for (int f = 0; f < o_.path_frames; ++f) v.cameras.push_back(camera == "path" ? path.camera_at(f) : still);
    const int n = std::min(o_.frames, o_.path_frames);
    for (int k = 0; k < n; ++k) v.evaluated.push_back((k + 1) * o_.path_frames / n - 1);
    ShaderSettings reference_shader;
    reference_shader.kind = o_.shader;
    for (int f : v.evaluated) {
      ReferenceKey key{scene_hash_, -1, v.cameras[size_t(f)], reference_shader, o_.width, o_.height, o_.ref_spp};
      const std::string label = name_ + "_" + camera + "_" + std::to_string(f);
      bool rendered = false;
      const auto t = Clock::now();
      v.references.push_back(cached_reference(o_.cache, label, key, [&] {
        const Shader shader(loaded(-1).ray_scene, reference_shader);
        return render_image(shader, View{key.camera, o_.width, o_.height}, o_.ref_spp);
      }, &rendered));
      if (rendered) std::printf("  reference %s: %d spp, %.1f s\n", label.c_str(), o_.ref_spp, ms_since(t) * 1e-3);
    }
    return v;
  }

  Result run(const Setting& setting, const Views& views, double equal_time_ms) {
    Config c;
    c.frame.width = o_.width, c.frame.height = o_.height, c.frame.sync = true, c.frame.seed = 5;
    c.shader.kind = o_.shader;
    if (setting.apply) setting.apply(c);
    if (c.baseline == Baseline::rendercache) c.frame.mode = RenderMode::rendercache;
    std::unique_ptr<tbb::global_control> threads;
    if (c.threads > 0) threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, c.threads);
    Loaded& l = loaded(c.subdiv);
    const Shader shader(l.ray_scene, c.shader);

    Result r;
    r.summary = {name_, views.camera, setting.knob, setting.name};
    r.summary.is_default = setting.knob == "default";
    r.summary.width = o_.width, r.summary.height = o_.height;
    auto record = [&](int f, double ms, double ms_no_shade, double cpu, const RgbImage* image) {
      FrameRow row{name_, views.camera, setting.knob, setting.name, f, ms, ms_no_shade, cpu};
      row.rmse = row.relative_mse = row.over_0_1 = row.over_0_2 = kNaN;
      const auto it = std::find(views.evaluated.begin(), views.evaluated.end(), f);
      if (image && it != views.evaluated.end()) {
        const ImageDifference d = compare_images(*image, ImageEncoding::linear, views.references[size_t(it - views.evaluated.begin())],
                                                 ImageEncoding::linear);
        row.evaluated = true, row.rmse = d.display_rmse, row.relative_mse = d.relative_mse;
        row.over_0_1 = d.over_0_1, row.over_0_2 = d.over_0_2;
      }
      r.frames.push_back(row);
    };

    if (c.baseline == Baseline::raytrace) {
      // Each frame stands alone: only the evaluated ones are rendered.
      for (int f : views.evaluated) {
        const auto t = Clock::now();
        const double c0 = cpu_ms();
        const RgbImage image = render_image(shader, View{views.cameras[size_t(f)], o_.width, o_.height}, 1);
        record(f, ms_since(t), kNaN, cpu_ms() - c0, &image);
      }
    } else if (c.baseline == Baseline::progressive) {
      progressive(shader, views, equal_time_ms, record);
    } else {
      FrameRenderer renderer(l.scene, l.ray_scene, shader, c.frame);
      for (size_t f = 0; f < views.cameras.size(); ++f) {
        const double c0 = cpu_ms();
        const RgbImage& image = renderer.render(views.cameras[f]);
        const double cpu = cpu_ms() - c0;
        const StageTimes& ms = renderer.stats().ms;
        record(int(f), ms.total, ms.loop_ms(), cpu, &image);
      }
    }

    SummaryRow& s = r.summary;
    s.rmse = s.relative_mse = s.over_0_1 = s.over_0_2 = 0;
    std::vector<double> ms, ms_no_shade, cpu;
    for (const FrameRow& row : r.frames) ms.push_back(row.ms), ms_no_shade.push_back(row.ms_no_shade), cpu.push_back(row.cpu_ms);
    s.ms = median(ms), s.ms_no_shade = median(ms_no_shade), s.cpu_ms = median(cpu);
    for (const FrameRow& row : r.frames) {
      ++s.frames;
      if (!row.evaluated) continue;
      ++s.evaluated, s.rmse += row.rmse, s.relative_mse += row.relative_mse, s.over_0_1 += row.over_0_1;
      s.over_0_2 += row.over_0_2, s.rmse_last = row.rmse;
    }
    s.rmse /= s.evaluated, s.relative_mse /= s.evaluated, s.over_0_1 /= s.evaluated, s.over_0_2 /= s.evaluated;
    if (c.subdiv != -1) loaded_.erase(c.subdiv);  // one other level in memory at a time (grid_dragon)
    return r;
  }

 private:
  // Progressive ray tracing without reprojection (frameless rendering): each frame traces jittered
  // samples at pixels in a fixed random order for as much CPU time as `budget_ms` (the default
  // run's median CPU time per frame: the plots' axis); a pixel's samples
  // are averaged while the camera holds still and restart when it has moved; pixels not reached
  // this frame show what they last showed.
  template <typename Record>
  void progressive(const Shader& shader, const Views& views, double budget_ms, Record& record) {
    const size_t pixels = size_t(o_.width) * size_t(o_.height);
    std::vector<uint32_t> order(pixels);
    std::iota(order.begin(), order.end(), 0u);
    std::mt19937_64 rng(7);
    std::shuffle(order.begin(), order.end(), rng);
    std::uniform_real_distribution<float> jitter(0.0f, 1.0f);
    std::vector<glm::dvec3> sum(pixels, glm::dvec3(0.0));
    std::vector<uint32_t> count(pixels, 0), view_of(pixels, 0);
    RgbImage image;
    image.width = o_.width, image.height = o_.height, image.pixels.assign(pixels * 3, 0.0f);
    size_t cursor = 0;
    uint32_t view_id = 0;
    const size_t chunk = std::max<size_t>(64, pixels / 256);
    std::vector<ShadeRequest> requests;
    ShadeBatch batch;
    for (size_t f = 0; f < views.cameras.size(); ++f) {
      const Camera& cam = views.cameras[f];
      if (f > 0) {
        const Camera& prev = views.cameras[f - 1];
        if (cam.eye != prev.eye || cam.target != prev.target || cam.up != prev.up || cam.yfov_degrees != prev.yfov_degrees) ++view_id;
      }
      const View view{cam, o_.width, o_.height};
      const auto t = Clock::now();
      const double c0 = cpu_ms();
      double chunk_ms = 0.0;  // the last chunk's CPU time: no chunk starts that would end past the budget
      do {
        const double tc = cpu_ms();
        requests.clear();
        for (size_t k = 0; k < chunk; ++k, cursor = (cursor + 1) % pixels) {
          const uint32_t p = order[cursor];
          requests.push_back({p, float(p % uint32_t(o_.width)) + jitter(rng), float(p / uint32_t(o_.width)) + jitter(rng)});
        }
        batch.clear();
        shader.shade(view, requests, batch);
        for (const ShadeResult& res : batch.results) {
          const size_t p = res.id;
          if (view_of[p] != view_id) sum[p] = glm::dvec3(0.0), count[p] = 0, view_of[p] = view_id;
          sum[p] += glm::dvec3(res.color), ++count[p];
          const glm::dvec3 mean = sum[p] / double(count[p]);
          for (int ch = 0; ch < 3; ++ch) image.pixels[p * 3 + size_t(ch)] = float(mean[ch]);
        }
        chunk_ms = cpu_ms() - tc;
      } while (cpu_ms() - c0 + chunk_ms <= budget_ms);
      record(int(f), ms_since(t), kNaN, cpu_ms() - c0, &image);
    }
  }

  const Options& o_;
  std::string name_, file_;
  uint64_t scene_hash_ = 0;
  std::map<int, std::unique_ptr<Loaded>> loaded_;
};

int usage() {
  std::fprintf(stderr,
               "usage: epi_study [--quick] [--scenes a,b] [--knobs k,l] [--cameras path,still] [--size N|WxH] [--path-frames N]\n"
               "                 [--frames N] [--ref-spp N] [--shader direct|glossy|gi] [--out DIR] [--cache DIR] [--list]\n"
               "       epi_study --mark study.csv\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) try {
  Options o;
  bool list = false;
  for (int k = 1; k < argc; ++k)
    if (std::string(argv[k]) == "--quick")
      o.scenes = {"cornell_box", "torus_capsule", "rooms"}, o.width = o.height = 128, o.path_frames = 40, o.frames = 3, o.ref_spp = 16;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    auto value = [&] {
      if (k + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return std::string(argv[++k]);
    };
    if (a == "--quick") {
      // applied before the loop: other options override it wherever they stand
    } else if (a == "--scenes") o.scenes = split(value());
    else if (a == "--knobs") o.knobs = split(value());
    else if (a == "--cameras") o.cameras = split(value());
    else if (a == "--size") {
      const std::string v = value();  // N or WxH
      const size_t x = v.find('x');
      o.width = parse_int(a, v.substr(0, x)), o.height = x == std::string::npos ? o.width : parse_int(a, v.substr(x + 1));
    }
    else if (a == "--path-frames") o.path_frames = parse_int(a, value());
    else if (a == "--frames") o.frames = parse_int(a, value());
    else if (a == "--ref-spp") o.ref_spp = parse_int(a, value());
    else if (a == "--out") o.out = value();
    else if (a == "--cache") o.cache = value();
    else if (a == "--list") list = true;
    else if (a == "--mark") {  // re-mark the fronts of a study.csv (e.g. rows of several runs concatenated)
      const std::string file = value();
      std::vector<SummaryRow> rows = read_summary(file);
      mark_pareto(rows);
      write_summary(file, rows);
      std::printf("epi_study: fronts of %zu rows marked in %s\n", rows.size(), file.c_str());
      return 0;
    }
    else if (a == "--shader") {
      const std::string s = value();
      if (s == "direct") o.shader = ShaderKind::direct;
      else if (s == "glossy") o.shader = ShaderKind::glossy;
      else if (s == "gi") o.shader = ShaderKind::gi;
      else throw std::invalid_argument("--shader " + s + ": expected direct, glossy or gi");
    } else {
      std::fprintf(stderr, "epi_study: unknown argument %s\n", a.c_str());
      return usage();
    }
  }
  if (o.width < 8 || o.height < 8 || o.path_frames < 1 || o.frames < 1 || o.ref_spp < 1 || o.scenes.empty()) return usage();
  for (const std::string& c : o.cameras)
    if (c != "path" && c != "still") throw std::invalid_argument("--cameras " + c + ": expected path or still");

  std::vector<Setting> settings = {{"default", "default", {}}};
  std::set<std::string> known;
  for (const Setting& s : all_settings()) {
    known.insert(s.knob);
    if (o.knobs.empty() || std::find(o.knobs.begin(), o.knobs.end(), s.knob) != o.knobs.end()) settings.push_back(s);
  }
  for (const std::string& k : o.knobs)
    if (!known.count(k)) throw std::invalid_argument("--knobs " + k + ": no such knob");
  if (list) {
    for (const Setting& s : settings) std::printf("%s\t%s\n", s.knob.c_str(), s.name.c_str());
    return 0;
  }

  std::filesystem::create_directories(o.out);
  const std::filesystem::path summary_file = std::filesystem::path(o.out) / "study.csv";
  const std::filesystem::path frames_file = std::filesystem::path(o.out) / "study_frames.csv";
  std::ofstream frames_out(frames_file.string() + ".tmp");
  frames_out << csv_header(frame_columns()) << "\n";
  std::vector<SummaryRow> summary;
  const auto start = Clock::now();
  std::printf("epi_study: %dx%d, %d frames per camera (%d compared), references %d spp, %zu settings, %d cores\n", o.width,
              o.height, o.path_frames, std::min(o.frames, o.path_frames), o.ref_spp, settings.size(), hardware_threads());
  for (const std::string& name : o.scenes) {
    Study study(o, name);
    for (const std::string& camera : o.cameras) {
      const Views views = study.views(camera);
      double default_ms = 0.0;
      for (const Setting& s : settings) {
        if (s.knob == "subdivision" && !study.has_subdivision()) continue;
        const Result r = study.run(s, views, default_ms);
        if (s.knob == "default") default_ms = r.summary.cpu_ms;
        for (const FrameRow& row : r.frames) frames_out << csv_line(row) << "\n";
        summary.push_back(r.summary);
        std::printf("%-14s %-5s %-15s %-26s %8.2f ms %8.2f ms  rmse %.4f  >0.1 %.4f\n", name.c_str(), camera.c_str(),
                    s.knob.c_str(), s.name.c_str(), r.summary.ms, r.summary.ms_no_shade, r.summary.rmse, r.summary.over_0_1);
        std::fflush(stdout);
      }
    }
  }
  mark_pareto(summary);
  frames_out.close();
  std::filesystem::rename(frames_file.string() + ".tmp", frames_file);
  write_summary(summary_file, summary);
  std::printf("epi_study: %zu rows in %s, %.0f s\n", summary.size(), summary_file.c_str(), ms_since(start) * 1e-3);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "epi_study: %s\n", e.what());
  return 1;
}

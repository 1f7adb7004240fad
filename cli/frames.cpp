// `epi render --mode epi|rendercache`: the frame loop (core/render) over a camera path, with
// per-stage timings as in the paper's table 2, and optional frames and JSON stats.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "commands.h"
#include "image_io.h"
#include "load_scene.h"
#include "output.h"
#include "render/camera_path.h"
#include "render/renderer.h"
#include "shade/render_image.h"
#include "snapshot.h"

namespace epi::cli {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The file name of frame n from a printf-style pattern with exactly one integer conversion
// (%d, %4d, %04d); "%%" is a literal percent sign. Anything else is an error.
std::string frame_file(const std::string& pattern, int n) {
  std::string out;
  int conversions = 0;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%', ++i;
      continue;
    }
    size_t j = i + 1;
    const bool zero = j < pattern.size() && pattern[j] == '0';
    if (zero) ++j;
    int width = 0;
    while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9' && width < 100) width = width * 10 + (pattern[j++] - '0');
    if (j >= pattern.size() || pattern[j] != 'd' || width > 12)
      throw std::invalid_argument("--frames-out '" + pattern + "': only one %d (or %04d) conversion is allowed");
    std::string number = std::to_string(n);
    if (int(number.size()) < width) number.insert(0, size_t(width) - number.size(), zero ? '0' : ' ');
    out += number;
    ++conversions;
    i = j;
  }
  if (conversions != 1) throw std::invalid_argument("--frames-out '" + pattern + "' needs exactly one %d conversion");
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / double(v.size());
}

// The frame loop's memory per pixel (point cache, edge-and-point image, masks, priority, images):
// ~139 bytes measured as the peak RSS of `epi render --size 2048x2048` less 512x512 (Cornell box);
// scenes with punctual lights keep 14 more for the punctual highlights (docs/performance.md).
constexpr double kFrameLoopBytesPerPixel = 160.0;

// The path: a file, else a still camera from --eye/--target/..., else the scene's own path.
render::CameraPath command_camera_path(const RenderOptions& options, const Scene& scene) {
  render::CameraPath path;
  if (!options.camera_path.empty()) {
    path = render::read_camera_path(options.camera_path, scene);
  } else if (options.camera.any()) {
    path.cameras.push_back({0, apply_camera_override(scene, options.camera)});
  } else {
    path = render::scene_camera_path(scene, options.frames);
  }
  return path;
}

// --frames-at, sorted, each checked against the path's length.
std::vector<int> path_frames_at(const RenderOptions& options) {
  std::vector<int> at = options.frames_at;
  std::sort(at.begin(), at.end());
  at.erase(std::unique(at.begin(), at.end()), at.end());
  if (!at.empty() && at.back() >= options.frames)
    throw std::invalid_argument("--frames-at " + std::to_string(at.back()) + ": beyond the path's last frame, " +
                                std::to_string(options.frames - 1) + " (--frames " + std::to_string(options.frames) + ")");
  return at;
}

}  // namespace

Camera last_frame_camera(const RenderOptions& options, const Scene& scene) {
  return command_camera_path(options, scene).camera_at(options.frames - 1);
}

int run_render_frames(const RenderOptions& options) {
  const auto start = Clock::now();
  check_output_image(options.output);
  if (!options.stats.empty()) check_output_file(options.stats);
  // Every output, each frame's included, checked before any work: writable, and no two alike.
  std::vector<std::string> outputs_named = {options.output, options.stats};
  const std::vector<int> frames_at = path_frames_at(options);
  if (!options.frames_out.empty())
    for (int f = 0; f < options.frames; ++f)
      if (frames_at.empty() || std::binary_search(frames_at.begin(), frames_at.end(), f)) {
        outputs_named.push_back(frame_file(options.frames_out, f));
        check_output_image(outputs_named.back());
      }
  if (!options.save_epi.empty()) {
    if (options.mode != "epi") throw std::invalid_argument("--save-epi needs --mode epi");
    check_output_file(options.save_epi);
    outputs_named.push_back(options.save_epi);
  }
  check_distinct_outputs(outputs_named);
  check_not_input(outputs_named, options.reference);
  const ShaderSettings shader_settings_ = shader_settings(options);
  check_memory_estimate("--size " + std::to_string(options.width) + "x" + std::to_string(options.height),
                        "the frame loop at this size", kFrameLoopBytesPerPixel * options.width * options.height,
                        options.memory_limit);
  std::optional<ReferenceImage> reference;  // read and its size checked before work
  if (!options.reference.empty()) reference = read_reference(options.reference, options.width, options.height);
  check_sample_budget(options);

  std::unique_ptr<tbb::global_control> thread_limit;
  if (options.threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, options.threads);
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();

  auto stage = Clock::now();
  LoadOptions load_options;
  load_options.subdiv_level_override = options.subdiv_level;
  load_options.memory_limit = options.memory_limit;
  const Scene scene = load_scene(options.scene, load_options);
  const double load_ms = ms_since(stage);
  report_repairs(scene, options.quiet);

  const render::CameraPath path = command_camera_path(options, scene);
  for (int f : {0, options.frames - 1}) {  // validate the cameras before long work
    View v;
    v.camera = path.camera_at(f), v.width = options.width, v.height = options.height;
    const ViewFrame check(v);
  }

  stage = Clock::now();
  RayScene ray_scene(scene);
  const Shader shader(ray_scene, shader_settings_);
  render::FrameSettings settings;
  settings.mode = options.mode == "rendercache" ? render::RenderMode::rendercache : render::RenderMode::epi;
  settings.width = options.width, settings.height = options.height;
  settings.sample_budget = options.sample_budget;
  settings.sync = options.sync;
  settings.seed = options.seed;
  settings.soft_shadow_edges = options.soft_shadow_edges;
  settings.sparse_blend = options.sparse_blend;
  settings.sparse_effort = options.sparse_effort;
  if (!options.punctual_highlights) settings.cache.punctual_highlight_share = render::PointCacheSettings::kNoPunctualHighlights;
  settings.trace_ahead = options.trace_ahead;
  settings.rest_sample_budget = options.rest_sample_budget;
  settings.motion_sample_budget = options.motion_sample_budget;
  if (options.sparse_occlusion_radius) settings.cache.sparse_occlusion_radius = *options.sparse_occlusion_radius;
  if (options.new_occluder_radius) settings.cache.new_occluder_radius = *options.new_occluder_radius;
  if (options.predict_share) settings.predict_share = *options.predict_share;
  if (options.predict_frames) settings.predict_frames = *options.predict_frames;
  if (options.predict_stride) settings.predict_stride = *options.predict_stride;
  if (options.predict_splat) settings.predict_splat = *options.predict_splat;
  std::optional<render::FrameRenderer> renderer;  // reset before the ray trace that measures the speed-up
  renderer.emplace(scene, ray_scene, shader, settings);
  const double build_ms = ms_since(stage);

  // The loop.
  struct Series {
    std::array<std::vector<double>, render::kFrameStageCount> stages;  // per render::kFrameStages
    std::vector<double> total, empty, simple, complex_pixels, silhouette, sharp, border, shadow, culled, samples, requested,
        predicted, effort, points_culled, points_occluded, holes_filled, sparse_blended, result_lag, integrate;
  } series;
  stage = Clock::now();
  double write_frames_ms = 0.0;
  const RgbImage* image = nullptr;
  StagedOutputs outputs;  // frames, image and stats move into place together at the end
  int loop_frames = 0;     // frames rendered (with --path-rate, as many as the clock allowed)
  const uint64_t rays_before = shader.rays_traced();
  const double shading_seconds_before = shader.shading_seconds();
  {
    ProgressBar bar("frames", options.quiet);
    render::PathClock clock(options.path_rate, options.frames - 1, frames_at);
    const auto loop_start = Clock::now();
    while (!clock.done()) {
      const double f = clock.next(ms_since(loop_start));
      const Camera camera = path.camera_at(f);
      const std::vector<glm::mat4> transforms =
          path.moves_objects() ? path.object_transforms_at(scene, f) : std::vector<glm::mat4>{};
      const std::vector<glm::vec3> lights = path.moves_lights() ? path.light_positions_at(scene, f) : std::vector<glm::vec3>{};
      image = &renderer->render(camera, transforms, lights);
      const render::FrameStats& s = renderer->stats();
      for (size_t k = 0; k < s.ms.ms.size(); ++k) series.stages[k].push_back(s.ms.ms[k]);
      series.total.push_back(s.ms.total);
      const double pixels = double(options.width) * double(options.height);
      series.empty.push_back(double(s.pixels.empty) / pixels), series.simple.push_back(double(s.pixels.simple) / pixels);
      series.complex_pixels.push_back(double(s.pixels.complex) / pixels);
      series.silhouette.push_back(double(s.edges.silhouette)), series.sharp.push_back(double(s.edges.sharp));
      series.border.push_back(double(s.edges.border)), series.shadow.push_back(double(s.edges.shadow));
      series.culled.push_back(double(s.edges.culled));
      series.samples.push_back(double(s.samples)), series.requested.push_back(double(s.requested));
      series.predicted.push_back(double(s.predicted)), series.effort.push_back(double(s.effort));
      series.points_culled.push_back(double(s.points.culled)), series.points_occluded.push_back(double(s.points.occluded));
      series.holes_filled.push_back(double(s.holes_filled));
      series.sparse_blended.push_back(double(s.sparse_blended));
      series.integrate.push_back(s.integrate_ms);
      if (s.samples > 0) series.result_lag.push_back(s.result_lag);  // frames that integrated results
      if (!options.frames_out.empty() && clock.exact()) {
        const auto t = Clock::now();
        outputs.add_image(frame_file(options.frames_out, int(f)), *image, options.exposure);
        write_frames_ms += ms_since(t);
        clock.pause(ms_since(t));
      }
      bar.update(options.frames > 1 ? f / double(options.frames - 1) : 1.0);
    }
    loop_frames = clock.frames();
  }
  const double run_ms = ms_since(stage) - write_frames_ms;
  // Rays the shader traced during the run (async: up to the last frame; work still in flight
  // when the renderer stops is not counted), and its rate while shading.
  const uint64_t rays = shader.rays_traced() - rays_before;
  const double shading_seconds = shader.shading_seconds() - shading_seconds_before;
  const double mrays_per_s = shading_seconds > 0.0 ? double(rays) / shading_seconds * 1e-6 : 0.0;

  stage = Clock::now();
  outputs.add_image(options.output, *image, options.exposure);
  if (!options.save_epi.empty()) {
    outputs.add_text(options.save_epi, snapshot_bytes({renderer->epi(), renderer->masks(), renderer->segments(),
                                                        renderer->reconstruct_settings()}));
  }
  const double write_ms = ms_since(stage) + write_frames_ms;
  const double total_ms = ms_since(start);

  // The written frame against the reference, in display space at the output's exposure.
  std::optional<ImageDifference> difference;
  if (reference)
    difference = compare_images(*image, ImageEncoding::linear, reference->image, reference->encoding, options.exposure);
  // The speed-up: a 1-spp ray trace of the last view with the same shader, once the frame loop
  // (and its asynchronous shading) has stopped, against the median frame time.
  image = nullptr;
  const size_t refined = renderer->cache().refined();
  renderer.reset();
  std::optional<double> raytrace_ms;
  std::optional<ImageDifference> raytrace_difference;  // the ray trace's own error, for comparison
  if (options.speedup) {
    View last;
    last.camera = path.camera_at(options.frames - 1), last.width = options.width, last.height = options.height;
    const auto t = Clock::now();
    const RgbImage traced = render_image(shader, last, 1);
    raytrace_ms = ms_since(t);
    if (reference)
      raytrace_difference =
          compare_images(traced, ImageEncoding::linear, reference->image, reference->encoding, options.exposure);
  }

  const double frame_ms = median(series.total);
  const double samples_per_frame = mean(series.samples);
  // Pixels per new sample; none when no sample arrived (JSON null).
  const bool sampled = samples_per_frame > 0.0;
  const double sparseness = sampled ? double(options.width) * double(options.height) / samples_per_frame : 0.0;
  const std::string sparseness_text = sampled ? std::to_string(int64_t(std::lround(sparseness))) : "-";
  double total_samples = 0.0;
  for (double n : series.samples) total_samples += n;
  char on_clock[96] = "";
  if (options.path_rate > 0.0)
    std::snprintf(on_clock, sizeof on_clock, " on the clock (%g a second): %d rendered", options.path_rate, loop_frames);
  std::printf("%s: %dx%d, %s, %d frames%s (%s shading), budget %.3f, %s shader, %d threads, %zu triangles\n",
              options.scene.c_str(), options.width, options.height, options.mode.c_str(), options.frames, on_clock,
              options.sync ? "sync" : "async", options.sample_budget, options.shader.c_str(), threads,
              scene.triangle_count());
  std::printf("  per frame (median, ms):");
  for (const render::FrameStageInfo& i : render::kFrameStages)
    if (i.loop || options.sync) std::printf(" %s %.1f |", i.label, median(series.stages[size_t(i.stage)]));
  std::printf(" total %.1f ms (%.1f fps)\n", frame_ms, frame_ms > 0.0 ? 1000.0 / frame_ms : 0.0);
  std::printf("  %.0f samples per frame (sparseness %s, drawn %.1f frames after their request) | pixels %.1f%% empty, "
              "%.1f%% simple, %.1f%% complex\n",
              samples_per_frame, sparseness_text.c_str(), mean(series.result_lag),
              100.0 * mean(series.empty), 100.0 * mean(series.simple), 100.0 * mean(series.complex_pixels));
  std::printf("  shader: %llu rays, %.1f Mrays/s over %.0f ms of shading\n", (unsigned long long)rays, mrays_per_s,
              shading_seconds * 1e3);
  std::printf("  load %.0f ms | build %.0f ms | frames %.0f ms | write %.0f ms | total %.0f ms\n", load_ms, build_ms, run_ms,
              write_ms, total_ms);
  if (raytrace_ms)
    std::printf("  speed-up over a 1-spp ray trace of the last view (%s shader): %.1f ms / %.1f ms per frame%s = %.1fx\n",
                options.shader.c_str(), *raytrace_ms, frame_ms, options.sync ? "" : " (shading asynchronous)",
                frame_ms > 0.0 ? *raytrace_ms / frame_ms : 0.0);
  if (difference) std::printf("  against %s: %s\n", options.reference.c_str(), difference_line(*difference).c_str());
  if (raytrace_difference)
    std::printf("  the 1-spp ray trace against it: %s\n", difference_line(*raytrace_difference).c_str());

  if (!options.stats.empty()) {
    nlohmann::json stages_ms = nlohmann::json::object();
    for (const render::FrameStageInfo& i : render::kFrameStages) stages_ms[i.name] = median(series.stages[size_t(i.stage)]);
    stages_ms["total"] = frame_ms;
    nlohmann::json stats = {
        {"scene", options.scene},
        {"mode", options.mode},
        {"shader", options.shader},
        {"width", options.width},
        {"height", options.height},
        {"frames", options.frames},
        {"loop_frames", loop_frames},  // frames rendered: `frames` unless on the clock (path_rate)
        {"path_rate", options.path_rate},
        {"sync", options.sync},
        {"sample_budget", options.sample_budget},
        {"seed", options.seed},
        {"threads", threads},
        {"triangles", scene.triangle_count()},
        {"camera_path", !options.camera_path.empty()            ? options.camera_path
                        : options.camera.any() || scene.camera_path.empty() ? std::string("still")
                                                                                          : std::string("scene")},
        {"stages_ms", stages_ms},
        {"integrate_ms", median(series.integrate)},  // of stages_ms.points: new results into the cache
        {"fps", frame_ms > 0.0 ? 1000.0 / frame_ms : 0.0},
        {"pixels", {{"empty", mean(series.empty)}, {"simple", mean(series.simple)}, {"complex", mean(series.complex_pixels)}}},
        {"edges",
         {{"silhouette", median(series.silhouette)},
          {"sharp", median(series.sharp)},
          {"border", median(series.border)},
          {"shadow", median(series.shadow)},
          {"culled", median(series.culled)}}},
        {"samples_per_frame", samples_per_frame},
        {"requests_per_frame", mean(series.requested)},
        {"predicted_per_frame", mean(series.predicted)},
        // mean ShadeRequest::effort of the requests (docs/render.md, "Effort where samples are sparse")
        {"effort_per_request", mean(series.requested) > 0.0 ? mean(series.effort) / mean(series.requested) : 1.0},
        {"result_lag_frames", mean(series.result_lag)},
        {"points_per_frame",
         {{"depth_culled", mean(series.points_culled)},
          {"occluded", mean(series.points_occluded)},
          {"holes_filled", mean(series.holes_filled)},
          {"sparse_blended", mean(series.sparse_blended)}}},
        {"refined", refined},
        {"sparseness", sampled ? nlohmann::json(sparseness) : nlohmann::json(nullptr)},
        {"samples", total_samples},
        {"rays", rays},
        {"mrays_per_s", mrays_per_s},
        {"shading_ms", shading_seconds * 1e3},
        {"setup_ms", {{"load", load_ms}, {"build", build_ms}, {"frames", run_ms}, {"write", write_ms}, {"total", total_ms}}},
        {"raytrace_1spp_ms", raytrace_ms ? nlohmann::json(*raytrace_ms) : nlohmann::json(nullptr)},
        {"speedup", raytrace_ms && frame_ms > 0.0 ? nlohmann::json(*raytrace_ms / frame_ms) : nlohmann::json(nullptr)},
    };
    if (difference) {
      stats["reference"] = difference_json(*difference);
      stats["reference"]["file"] = options.reference;
    }
    if (raytrace_difference) stats["raytrace_reference"] = difference_json(*raytrace_difference);
    outputs.add_json(options.stats, stats);
  }
  outputs.commit();
  std::printf("  wrote %s%s%s\n", options.output.c_str(), options.stats.empty() ? "" : " and ", options.stats.c_str());
  return 0;
}

}  // namespace epi::cli

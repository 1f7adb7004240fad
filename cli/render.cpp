// `epi render`: a scene to an image file, with a timing summary and optional JSON stats.
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "commands.h"
#include "image_io.h"
#include "load_scene.h"
#include "output.h"
#include "shade/render_image.h"
#include "shade/shader.h"

namespace epi::cli {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

int run_render(const RenderOptions& options) {
#ifdef EPI_WITH_FRAMES
  if (options.mode == "epi" || options.mode == "rendercache") return run_render_frames(options);
#endif
  if (!options.save_epi.empty()) throw std::invalid_argument("--save-epi needs --mode epi");
  if (options.path_rate > 0.0 || !options.frames_at.empty())
    throw std::invalid_argument(std::string(options.path_rate > 0.0 ? "--path-rate" : "--frames-at") +
                                " needs the frame loop (--mode epi or rendercache)");
  const auto start = Clock::now();
  // Fail on a bad output path before any long work.
  check_output_image(options.output);
  if (!options.stats.empty()) check_output_file(options.stats);
  check_distinct_outputs({options.output, options.stats});
  check_not_input({options.output, options.stats}, options.reference);
  const ShaderSettings settings = shader_settings(options);
  // One float image and the writer's copy: ~12 bytes a pixel measured (peak RSS, 2048x2048 less 512x512).
  constexpr double kBytesPerPixel = 24.0;
  check_memory_estimate("--size " + std::to_string(options.width) + "x" + std::to_string(options.height),
                        "a " + options.mode + " image", kBytesPerPixel * options.width * options.height,
                        options.memory_limit);
  std::optional<ReferenceImage> reference;  // read and its size checked before work
  if (!options.reference.empty()) reference = read_reference(options.reference, options.width, options.height);

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

  View view;
#ifdef EPI_WITH_FRAMES
  view.camera = last_frame_camera(options, scene);  // the view the same command's frame loop ends on
#else
  view.camera = apply_camera_override(scene, options.camera);
#endif
  view.width = options.width;
  view.height = options.height;
  const ViewFrame frame(view);  // validates the camera

  stage = Clock::now();
  const RayScene ray_scene(scene);
  const Shader shader(ray_scene, settings);
  const double build_ms = ms_since(stage);

  const int spp = options.mode == "raytrace" ? 1 : options.spp;
  stage = Clock::now();
  RgbImage image;
  RenderStats render_stats;
  {
    ProgressBar bar("render", options.quiet);
    image = render_image(shader, view, spp, [&bar](double fraction) { bar.update(fraction); }, &render_stats);
  }
  const double render_ms = ms_since(stage);
  const uint64_t rays = render_stats.rays;
  const double mrays_per_s = render_stats.mrays_per_second();

  stage = Clock::now();
  StagedOutputs outputs;
  outputs.add_image(options.output, image, options.exposure);
  const double write_ms = ms_since(stage);
  const double total_ms = ms_since(start);

  std::printf("%s: %dx%d, %s, %d spp, %s shader, %d threads, %zu triangles\n", options.scene.c_str(), view.width,
              view.height, options.mode.c_str(), spp, options.shader.c_str(), threads, scene.triangle_count());
  std::printf("  load %.0f ms | ray scene %.0f ms | render %.0f ms (%.1f Mrays/s) | write %.0f ms | total %.0f ms\n",
              load_ms, build_ms, render_ms, mrays_per_s, write_ms, total_ms);
  std::optional<ImageDifference> difference;
  if (reference) {
    difference = compare_images(image, ImageEncoding::linear, reference->image, reference->encoding, options.exposure);
    std::printf("  against %s: %s\n", options.reference.c_str(), difference_line(*difference).c_str());
  }
  if (!options.stats.empty()) {
    nlohmann::json stats = {
        {"scene", options.scene},
        {"mode", options.mode},
        {"shader", options.shader},
        {"width", view.width},
        {"height", view.height},
        {"spp", spp},
        {"seed", options.seed},
        {"threads", threads},
        {"triangles", scene.triangle_count()},
        {"rays", rays},
        {"mrays_per_s", mrays_per_s},
        {"stages_ms", {{"load", load_ms}, {"build", build_ms}, {"render", render_ms}, {"write", write_ms}, {"total", total_ms}}},
    };
    if (difference) {
      stats["reference"] = difference_json(*difference);
      stats["reference"]["file"] = options.reference;
    }
    outputs.add_json(options.stats, stats);
  }
  outputs.commit();
  std::printf("  wrote %s%s%s\n", options.output.c_str(), options.stats.empty() ? "" : " and ", options.stats.c_str());
  return 0;
}

}  // namespace epi::cli

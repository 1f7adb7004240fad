// The command-line half of the shared render options: `epi render` and `epi-viewer` add the
// same flags through add_render_options (CLI11 is slow to compile: few files include it).
#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>

#include "render_options.h"

namespace epi::cli {

namespace {

// Parses "x,y,z" into a vector of three finite floats.
bool parse_vec3(const std::string& text, glm::vec3& out) {
  std::stringstream in(text);
  std::string part;
  float v[3];
  for (int i = 0; i < 3; ++i) {
    if (!std::getline(in, part, ',')) return false;
    try {
      size_t used = 0;
      v[i] = std::stof(part, &used);
      if (used != part.size() || !std::isfinite(v[i])) return false;
    } catch (const std::exception&) {
      return false;
    }
  }
  if (std::getline(in, part)) return false;
  out = {v[0], v[1], v[2]};
  return true;
}

void add_vec3_option(CLI::App& app, const std::string& name, std::optional<glm::vec3>& target, const std::string& help) {
  app.add_option_function<std::string>(
         name,
         [&target, name](const std::string& text) {
           glm::vec3 v;
           if (!parse_vec3(text, v)) throw CLI::ValidationError(name, "expected three numbers x,y,z, got '" + text + "'");
           target = v;
         },
         help)
      ->type_name("X,Y,Z");
}

// Parses "WxH" with both in [1, 16384]; digits only (no sign, no overflow: from_chars checks the range).
bool parse_size(const std::string& text, int& width, int& height) {
  const size_t x = text.find_first_of("xX");
  if (x == std::string::npos) return false;
  auto number = [](const char* first, const char* last, int& out) {
    if (first == last || *first < '0' || *first > '9') return false;
    const auto [end, error] = std::from_chars(first, last, out);
    return error == std::errc() && end == last && out >= 1 && out <= 16384;
  };
  return number(text.data(), text.data() + x, width) && number(text.data() + x + 1, text.data() + text.size(), height);
}

}  // namespace

const CLI::Validator kFinite(
    [](std::string& text) {
      const double v = std::strtod(text.c_str(), nullptr);
      return std::isfinite(v) ? std::string() : "expected a finite number, got '" + text + "'";
    },
    "FINITE");

void add_memory_limit_option(CLI::App& app, uint64_t& limit_bytes) {
  app.add_option_function<double>(
         "--memory-limit",
         [&limit_bytes](double gib) { limit_bytes = uint64_t(gib * double(uint64_t(1) << 30)); },
         "Refuse work estimated to need more memory than this many GiB (default " +
             std::to_string(kDefaultMemoryLimit >> 30) + "; docs/reliability.md)")
      ->check(kFinite & CLI::Range(0.001, 1e6))
      ->type_name("GIB");
}

void add_camera_options(CLI::App& app, CameraOverride& camera) {
  add_vec3_option(app, "--eye", camera.eye, "Camera position (overrides the scene's default camera)");
  add_vec3_option(app, "--target", camera.target, "Point the camera looks at");
  add_vec3_option(app, "--up", camera.up, "Camera up vector");
  app.add_option_function<float>(
         "--fov", [&camera](float v) { camera.fov_degrees = v; }, "Vertical field of view in degrees")
      ->check(kFinite & CLI::Range(0.01f, 179.0f));
}

void add_size_option(CLI::App& app, int& width, int& height) {
  app.add_option_function<std::string>(
         "--size",
         [&width, &height](const std::string& text) {
           int w = 0, h = 0;
           if (!parse_size(text, w, h))
             throw CLI::ValidationError("--size", "expected WxH with 1..16384, got '" + text + "'");
           width = w;
           height = h;
         },
         "Image size, e.g. 512x512")
      ->type_name("WxH");
}

void add_render_options(CLI::App& app, RenderOptions& render, bool with_frame_loop) {
  app.add_option("scene", render.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
  if (with_frame_loop) {
    app.add_option("--mode", render.mode,
                   "epi (the default): the edge-and-point renderer, run over --frames frames of the camera path; "
                   "rendercache: the same without edges; raytrace: 1 sample per pixel; reference: converged, --spp "
                   "samples per pixel")
        ->check(CLI::IsMember({"epi", "rendercache", "raytrace", "reference"}))
        ->capture_default_str();
    app.add_flag("--sync", render.sync,
                 "Shade exactly the sample budget inside every frame: the same bytes for the same seed. Default: "
                 "asynchronous, as interactively (the shader runs beside the frame loop; timing-dependent)");
    app.add_flag("!--no-trace-ahead", render.trace_ahead,
                 "Trace each frame's requests through the camera they were chosen for, not through the camera "
                 "extrapolated to the frame their results will be drawn in (asynchronous loop; docs/render.md)");
    app.add_option("--sample-budget", render.sample_budget, "Fraction of the pixels shaded per frame")
        ->check(kFinite & CLI::Range(0.0, 1.0))
        ->capture_default_str();
    app.add_option("--rest-sample-budget", render.rest_sample_budget,
                   "Asynchronous loop at rest (camera, objects and lights still): the budget grows up to this "
                   "fraction while the shader finishes each frame's requests, so an idle shader refines the "
                   "image sooner; at most --sample-budget: off (docs/render.md, \"Idle shading at rest\")")
        ->check(kFinite & CLI::Range(0.0, 1.0))
        ->capture_default_str();
    app.add_option("--motion-sample-budget", render.motion_sample_budget,
                   "Asynchronous loop in motion: the budget grows up to this fraction while the shader finishes "
                   "each frame's requests and a frame takes at most a 60 Hz display's frame (the shader's idle time "
                   "goes into frames a display shows); at most --sample-budget: off (docs/render.md, \"Idle shading "
                   "in motion\")")
        ->check(kFinite & CLI::Range(0.0, 1.0))
        ->capture_default_str();
    app.add_option("--camera-path", render.camera_path, "Camera keys per frame (docs/camera-path.md)");
    app.add_flag("--soft-shadow-edges", render.soft_shadow_edges,
                 "epi mode: also cut interpolation at area lights' umbral and penumbral edges, as the paper does "
                 "(off by default: it costs quality where a penumbra is a few pixels wide; docs/render.md)");
    app.add_flag("!--no-sparse-blend", render.sparse_blend,
                 "epi mode: show sparse regions (samples several pixels apart, as on a surface the camera "
                 "approaches) as the EPI reconstructs them, a patch per sample, instead of blending them towards "
                 "an edge-stopping smooth interpolation of the samples (docs/render.md)");
    app.add_option("--sparse-effort", render.sparse_effort,
                   "epi mode: a request where the EPI's samples are sparse (one result shown over many pixels) "
                   "takes up to this many times the shader's sample counts, in the asynchronous loop while the shader "
                   "keeps up; 1: off (docs/render.md, \"Effort where samples are sparse\")")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    app.add_flag("!--no-punctual-highlights", render.punctual_highlights,
                 "epi mode: show the punctual lights' highlights as each point was shaded, fading as the view turns, "
                 "instead of recomputing them for every frame's eye from the lights that reach the point "
                 "(docs/render.md, \"Punctual highlights\")");
    app.add_option("--sparse-occlusion-radius", render.sparse_occlusion_radius,
                   "epi mode: pixels within which a nearer point standing alone hides the points behind it (a near "
                   "surface magnified by motion is sampled sparsely; docs/render.md). Default 4; 2 turns this "
                   "off: a faster points stage, but far points may show through such surfaces")
        ->check(CLI::Range(2, 8));
    app.add_option("--new-occluder-radius", render.new_occluder_radius,
                   "epi mode: pixels within which a lone point whose result landed in front of the point drawn at "
                   "its pixel (a surface that has just come in front, as an object sweeping across the view) hides "
                   "the points behind it for a few frames (docs/render.md). Default 8; at most the sparse radius "
                   "turns this off")
        ->check(CLI::Range(2, 15));
    app.add_option("--predict-share", render.predict_share,
                   "Predictive sampling: at most this share of the budget goes to the gaps the camera, "
                   "extrapolated ahead, is about to open (docs/render.md, \"Sampling\"). Default 0: off (0.25 was the "
                   "default until the paths measured better without it)")
        ->check(kFinite & CLI::Range(0.0, 1.0));
    app.add_option("--predict-frames", render.predict_frames,
                   "Predictive sampling: how many frames ahead the camera is extrapolated. Default 4")
        ->check(kFinite & CLI::Range(0.0, 64.0));
    app.add_option("--predict-stride", render.predict_stride,
                   "Predictive sampling: 1 in this many cached points is projected into the view ahead (a hash "
                   "of the slot picks them). Default 8; 1 projects them all")
        ->check(CLI::Range(1, 64));
    app.add_option("--predict-splat", render.predict_splat,
                   "Predictive sampling: each projected point marks a square of this many pixels a side as "
                   "covered. Default 5")
        ->check(CLI::Range(1, 15));
  } else {
    render.mode = "reference";  // built without the frame loop
    app.add_option("--mode", render.mode, "reference: converged, --spp samples per pixel; raytrace: 1 sample per pixel")
        ->check(CLI::IsMember({"reference", "raytrace"}))
        ->capture_default_str();
  }
  add_size_option(app, render.width, render.height);
  add_memory_limit_option(app, render.memory_limit);
  app.add_option("--spp", render.spp, "Samples per pixel (reference mode)")->check(CLI::Range(1, 1 << 20))->capture_default_str();
  app.add_option("--shader", render.shader, "direct: lights and soft shadows; glossy: + glossy reflection; gi: + path-traced indirect")
      ->check(CLI::IsMember({"direct", "glossy", "gi"}))
      ->capture_default_str();
  app.add_option("--seed", render.seed, "Random seed (results do not depend on --threads)")->capture_default_str();
  app.add_option("--threads", render.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 1024));
  app.add_option("--exposure", render.exposure,
                 "Exposure in stops for 8-bit outputs (.png): linear * 2^stops, then a highlight shoulder above "
                 "0.8 that keeps hue, then sRGB. EXR is written linear, untouched")
      ->check(kFinite & CLI::Range(-32.0f, 32.0f))
      ->capture_default_str();
  app.add_option("--area-light-samples", render.shading.area_light_samples, "Shadow rays to area lights per hit")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  app.add_option("--glossy-samples", render.shading.glossy_samples, "Glossy reflection rays per hit (glossy shader)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  app.add_option("--glossy-light-samples", render.shading.glossy_light_samples,
                 "Area-light shadow rays at each reflected hit (glossy shader)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  app.add_option("--gi-paths", render.shading.gi_paths, "Indirect paths per hit (gi shader)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  app.add_option("--gi-light-samples", render.shading.gi_light_samples, "Area-light shadow rays per path vertex (gi shader)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  app.add_option("--gi-max-bounces", render.shading.gi_max_bounces, "Longest indirect path, in bounces (gi shader)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  app.add_option("--subdiv-level", render.subdiv_level, "Override the subdivision level")->check(CLI::Range(0, 8));
  add_camera_options(app, render.camera);
}

}  // namespace epi::cli

// The image a user sees while moving (issue 9, docs/render.md "Quality in motion"): each bundled
// scene along its camera path (sync, fixed seed: --seed, default 5), its last frame against a converged reference of
// that view, beside the same frame count with the camera held at that view and beside the render
// cache along the path. Display-space RMSE and the share of pixels off by more than 0.1 and 0.2
// (max over channels), and where the large errors come from, pixel by pixel:
//   hidden    the drawn point is not the nearest surface along its own ray
//   colour    the drawn point is the right surface, its colour is off (stale or noisy shading)
//   near      no point drawn; a hidden point is drawn within 2 pixels
//   other     no point drawn, none hidden near (reconstruction, holes)
// With --out, each run also writes RUN_causes.png: pixels off by more than 0.1 coloured by cause
// (hidden red, colour yellow, near hidden magenta, other blue) over the dimmed frame.
// --runs picks the runs (comma-separated: path, still, rc; all three by default). --reference-dir
// keeps each scene's reference there (SCENE_N_Sspp_FRAMES.exr, the same for every seed) and reads
// it back on later runs. --occlusion-radius, --sparse-occlusion-radius and --new-occluder-radius set the PointCacheSettings
// of that name (0 turns the sparse test off); --times adds a column, the median ms per frame of the
// points stage (insert, project, culls, fill; docs/render.md). --as-async sets
// FrameSettings::sync_as_async: requests made for the view that chose them and shaded a frame
// later, as the viewer's asynchronous loop does (deterministic). --no-trace-ahead turns
// FrameSettings::trace_ahead off (requests traced through the camera that chose them).
// --no-punctual-highlights keeps the punctual lights' highlights in the cached colours, as seen
// from the shading view (PointCacheSettings::punctual_highlight_share; docs/render.md, "Punctual highlights").
// --settle N holds the camera at the last view for N more frames after the epi and render cache
// paths (how fast the image settles when the user stops) and adds a table: the display RMSE at
// the stop and 1, 2, 4, ... N frames later, beside the still run's (the same frame count at that
// view from an empty cache), and the frames it takes to come within 1.5x and 1.1x of it; with
// --out, those frames are written too (RUN_settleN.png).
// --colours adds a second table: the colour the cache shows for every drawn point (before any
// fade) against its surface shaded again from the last view (same seed), the points off by more than 0.1 (display luminance), and of
// those, the ones the shader reports as mostly view-dependent (view share above 0.5: stale
// highlights, faded or dropped as the view turns) and, of the rest, the ones the diffuse lobe's
// Fresnel transmission explains: the shader weights the diffuse
// lobe by 1 - F(n.v) (brdf.h), which depends on the eye but is not in ShadeResult::view_dependent:
// a point shaded at a grazing angle showed a darker colour when seen face-on until the cache
// rescaled its diffuse part with the view (docs/render.md, "Diffuse transmission"). "Explained": T(n.v then) / T(n.v now) is off 1 by more than 0.1 and
// the stored colour is within 0.05 of the fresh diffuse part scaled by it plus the stored
// view-dependent part (T(c) = 1 - F(c), F0 = 0.04; n the geometric normal).
// --edges adds a column: the share of the visible edge pieces' length, over every frame of the run,
// that lies behind the ray-traced surface at its pixel by more than 10 % of its depth (an edge of a
// surface hidden by a nearer one, drawn across that nearer one; docs/render.md, "Edges behind
// nearer surfaces"), sampled every half pixel along each piece; with --out, RUN_edges.png: the last
// frame with the pixels of those pieces in magenta.
// Usage: render_motion_quality [--size N] [--frames N] [--budget F] [--spp N] [--seed N] [--runs LIST] [--reference-dir DIR]
//        [--occlusion-radius N] [--sparse-occlusion-radius N] [--new-occluder-radius N] [--as-async] [--no-trace-ahead]
//        [--no-punctual-highlights] [--times]
//        [--colours] [--edges] [--out DIR] SCENE.gltf...
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "image_io.h"
#include "load_scene.h"
#include "render/camera_path.h"
#include "render/point_cache_detail.h"
#include "render/renderer.h"
#include "shade/brdf.h"
#include "shade/render_image.h"

namespace {

using namespace epi;
using namespace epi::render;

double display(float linear) {
  const double v = std::clamp(double(linear), 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

struct Run {
  double rmse = 0, over01 = 0, over02 = 0;
  double points_ms = 0;  // median per frame of the points stage (FrameStage::points)
  size_t hidden = 0, colour = 0, near = 0, other = 0;
  // --colours: drawn points (on an object, shaded again from the last view), off by more than 0.1,
  // of those reported view-dependent, and of the rest explained by the diffuse lobe's Fresnel transmission.
  size_t compared = 0, off = 0, transmission = 0, reported = 0;
  std::vector<double> settle;  // --settle: RMSE at the stop (0) and each frame held there after it
  double edge_length = 0, edge_behind = 0;  // --edges: visible edge length (pixels), of it behind the surface
};

struct Options {
  int size = 256, frames = 60, spp = 64;
  double budget = 0.02;
  uint64_t seed = 5;
  std::string out;
  std::string runs = "path,still,rc";
  std::string reference_dir;
  int occlusion_radius = -1;  // PointCacheSettings::occlusion_radius (-1: the default)
  int sparse_occlusion_radius = -1;  // PointCacheSettings::sparse_occlusion_radius (-1: the default, 0: off)
  int new_occluder_radius = -1;      // PointCacheSettings::new_occluder_radius (-1: the default, 0: off)
  bool times = false;  // --times: a last column, the points stage's median ms per frame
  bool as_async = false;  // --as-async: FrameSettings::sync_as_async
  bool trace_ahead = true;  // --no-trace-ahead: FrameSettings::trace_ahead off
  bool punctual_highlights = true;  // --no-punctual-highlights: PointCacheSettings::punctual_highlight_share off
  bool colours = false;     // --colours: the stored colours against fresh shading (the second table)
  int settle = 0;           // --settle N: frames held at the last view after the path (the settling table)
  bool edges = false;       // --edges: the share of visible edge length behind the ray-traced surface
};

// The frame's visible edge pieces sampled every half pixel: their length, and the length where the
// ray through the sample hits a surface nearer than the edge by more than 10 % of the edge's depth.
// `marks`, when given, receives the pixels of the samples behind.
void edges_behind(const FrameRenderer& renderer, const RayScene& ray_scene, const Camera& camera, int size, Run& r,
                  std::vector<glm::ivec2>* marks = nullptr) {
  View view;
  view.camera = camera, view.width = size, view.height = size;
  const ViewFrame frame(view);
  const std::vector<Segment>& pieces = renderer.segments();
  const std::vector<glm::dvec2>& inv = renderer.piece_inv_depths();
  for (size_t k = 0; k < pieces.size() && k < inv.size(); ++k) {
    const Segment& s = pieces[k];
    const double length = std::hypot(s.x1 - s.x0, s.y1 - s.y0);
    const int samples = std::max(1, int(std::ceil(2.0 * length)));
    const double step = length / samples;
    for (int j = 0; j < samples; ++j) {
      const double t = (j + 0.5) / samples;
      const double x = s.x0 + t * (s.x1 - s.x0), y = s.y0 + t * (s.y1 - s.y0);
      if (!(x >= 0.0 && y >= 0.0 && x < size && y < size)) continue;
      r.edge_length += step;
      const double edge_depth = 1.0 / (inv[k].x + t * (inv[k].y - inv[k].x));
      const Ray ray = frame.ray(float(x), float(y));
      const RayHit hit = ray_scene.intersect(ray);
      if (!(hit.hit && double(frame.project(ray.origin + hit.t * ray.direction).depth) * 1.1 < edge_depth)) continue;
      r.edge_behind += step;
      if (marks) marks->emplace_back(int(x), int(y));
    }
  }
}

// Display-space RMSE of two images of the same size, through this tool's display() (clamped, sRGB;
// `epi compare` tone-maps linear images first, so its figures differ).
double display_rmse(const RgbImage& image, const RgbImage& reference) {
  double squared = 0.0;
  for (size_t k = 0; k < image.pixels.size(); ++k) {
    const double d = display(image.pixels[k]) - display(reference.pixels[k]);
    squared += d * d;
  }
  return std::sqrt(squared / double(std::max<size_t>(1, image.pixels.size())));
}

// The drawn points' stored colours against their surfaces shaded again from `frame` (Run's --colours counts).
void compare_colours(const PointCache& cache, const ViewFrame& frame, std::span<const glm::mat4> transforms,
                     const Shader& shader, Run& r) {
  const PointImage& drawn = cache.image();
  std::vector<ShadeRequest> requests;
  std::vector<uint32_t> slots;
  for (const int32_t slot : drawn.point) {
    if (slot < 0 || cache.points()[size_t(slot)].object == kNone) continue;
    const Projection proj = frame.project(cache.world_position(cache.points()[size_t(slot)], frame, transforms));
    requests.push_back({uint32_t(requests.size()), proj.pixel.x, proj.pixel.y});
    slots.push_back(uint32_t(slot));
  }
  ShadeBatch fresh;
  shader.shade(frame, requests, fresh);
  for (const ShadeResult& now : fresh.results) {
    const CachePoint& p = cache.points()[slots[now.id]];
    const PointColour& c = cache.colours()[slots[now.id]];
    if (!now.hit || now.object != p.object) continue;  // another surface in front: hidden, not a colour
    ++r.compared;
    // What the cache shows now (before any fade): a rescaled point's diffuse part times this view's
    // transmission about the geometric normal, as PointCache::transmission_now takes it.
    const glm::vec3 then_dir = detail::unpack_unit(p.view), now_dir = glm::normalize(frame.eye() - now.position);
    // (plus the punctual highlight, recomputed for the last view: PointCache::highlight_now)
    const glm::vec3 shown = (p.srgb >> 24 ? (c.color - c.view_dependent) * diffuse_transmission(glm::dot(now.normal, now_dir)) + c.view_dependent
                                          : c.color) +
                            cache.highlight_now(slots[now.id]);
    const double stored = display(rgb_luminance(shown));
    if (std::abs(stored - display(rgb_luminance(now.color))) <= 0.1) continue;
    ++r.off;
    const float ratio = diffuse_transmission(std::abs(glm::dot(now.normal, then_dir))) /
                        std::max(1e-6f, diffuse_transmission(std::abs(glm::dot(now.normal, now_dir))));
    const float predicted = rgb_luminance(now.color - now.view_dependent) * ratio + rgb_luminance(c.view_dependent);
    if (p.view_share > 0.5f) ++r.reported;
    else if (std::abs(ratio - 1.0f) > 0.1f && std::abs(stored - display(predicted)) < 0.05) ++r.transmission;
  }
}


Run run(const Scene& scene, RayScene& ray_scene, const Shader& shader, const Options& o, bool still, RenderMode mode,
        const RgbImage& reference, const std::string& image_file) {
  FrameSettings s;
  s.mode = mode, s.width = o.size, s.height = o.size, s.sync = true, s.sample_budget = o.budget, s.seed = o.seed;
  s.sync_as_async = o.as_async;
  s.trace_ahead = o.trace_ahead;
  if (!o.punctual_highlights) s.cache.punctual_highlight_share = PointCacheSettings::kNoPunctualHighlights;
  if (o.occlusion_radius >= 0) s.cache.occlusion_radius = o.occlusion_radius;
  if (o.sparse_occlusion_radius >= 0) s.cache.sparse_occlusion_radius = o.sparse_occlusion_radius;
  if (o.new_occluder_radius >= 0) s.cache.new_occluder_radius = o.new_occluder_radius;
  FrameRenderer renderer(scene, ray_scene, shader, s);
  const CameraPath path = scene_camera_path(scene, o.frames);
  const Camera last = path.camera_at(o.frames - 1);
  RgbImage image;
  std::vector<double> points_ms;
  Run r;
  std::vector<glm::ivec2> marks;  // --edges: the last frame's pixels of edges behind
  for (int f = 0; f < o.frames; ++f) {
    image = renderer.render(still ? last : path.camera_at(f));
    points_ms.push_back(renderer.stats().ms[FrameStage::points]);
    if (o.edges && mode == RenderMode::epi)
      edges_behind(renderer, ray_scene, still ? last : path.camera_at(f), o.size, r, f == o.frames - 1 ? &marks : nullptr);
  }
  if (!image_file.empty()) write_image(image_file, image);
  if (!image_file.empty() && o.edges && mode == RenderMode::epi) {
    // The last frame with the pixels its edges behind nearer surfaces cross in magenta.
    RgbImage edges = image;
    for (const glm::ivec2& m : marks) {
      float* px = &edges.pixels[(size_t(m.y) * size_t(o.size) + size_t(m.x)) * 3];
      px[0] = 1.0f, px[1] = 0.0f, px[2] = 1.0f;
    }
    write_image(image_file.substr(0, image_file.size() - 4) + "_edges.png", edges);
  }

  View view;
  view.camera = last, view.width = o.size, view.height = o.size;
  const ViewFrame frame(view);
  std::vector<glm::mat4> transforms(scene.objects.size());
  for (size_t k = 0; k < transforms.size(); ++k) transforms[k] = ray_scene.object_to_world(uint32_t(k));
  const PointCache& cache = renderer.cache();
  const PointImage& drawn = cache.image();
  auto hidden_at = [&](size_t i) {
    if (drawn.point[i] < 0) return false;
    const CachePoint& p = cache.points()[size_t(drawn.point[i])];
    const Projection proj = frame.project(cache.world_position(p, frame, transforms));
    const Ray ray = frame.ray(proj.pixel.x, proj.pixel.y);
    const RayHit hit = ray_scene.intersect(ray);
    if (p.object == kNone) return hit.hit;
    return hit.hit && proj.depth > frame.project(ray.origin + hit.t * ray.direction).depth * 1.02f + 1e-3f;
  };
  r.rmse = display_rmse(image, reference);
  const int n = o.size;
  // The causes as a picture: the frame dimmed, each pixel off by more than 0.1 coloured by cause
  // (hidden red, colour yellow, near hidden magenta, other blue).
  RgbImage causes = image;
  for (float& v : causes.pixels) v *= 0.25f;
  auto mark = [&](size_t i, float r_, float g, float b) {
    causes.pixels[3 * i] = r_, causes.pixels[3 * i + 1] = g, causes.pixels[3 * i + 2] = b;
  };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const size_t i = size_t(y) * size_t(n) + size_t(x);
      double worst = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double d = display(image.pixels[i * 3 + size_t(c)]) - display(reference.pixels[i * 3 + size_t(c)]);
        worst = std::max(worst, std::abs(d));
      }
      r.over01 += worst > 0.1, r.over02 += worst > 0.2;
      if (worst <= 0.1) continue;
      if (drawn.point[i] >= 0) {
        const bool hidden = hidden_at(i);
        (hidden ? r.hidden : r.colour) += 1;
        hidden ? mark(i, 1, 0, 0) : mark(i, 1, 1, 0);
        continue;
      }
      bool near = false;
      for (int qy = std::max(0, y - 2); qy <= std::min(n - 1, y + 2) && !near; ++qy)
        for (int qx = std::max(0, x - 2); qx <= std::min(n - 1, x + 2) && !near; ++qx)
          near = hidden_at(size_t(qy) * size_t(n) + size_t(qx));
      (near ? r.near : r.other) += 1;
      near ? mark(i, 1, 0, 1) : mark(i, 0, 0.3f, 1);
    }
  if (!image_file.empty()) write_image(image_file.substr(0, image_file.size() - 4) + "_causes.png", causes);
  if (o.colours && mode == RenderMode::epi) compare_colours(cache, frame, transforms, shader, r);
  const double pixels = double(n) * double(n);
  r.over01 *= 100.0 / pixels, r.over02 *= 100.0 / pixels;
  std::nth_element(points_ms.begin(), points_ms.begin() + ptrdiff_t(points_ms.size() / 2), points_ms.end());
  r.points_ms = points_ms[points_ms.size() / 2];
  if (!still && o.settle > 0) {
    // With --out, the frames 1, 2, 4, ... after the stop are written too (RUN_settleN.png).
    const std::string stem = image_file.empty() ? "" : image_file.substr(0, image_file.size() - 4) + "_settle";
    r.settle.push_back(display_rmse(image, reference));
    for (int f = 1; f <= o.settle; ++f) {
      image = renderer.render(last);
      r.settle.push_back(display_rmse(image, reference));
      if (!stem.empty() && (std::has_single_bit(unsigned(f)) || f == o.settle)) write_image(stem + std::to_string(f) + ".png", image);
    }
  }
  return r;
}

}  // namespace

int run_all(int argc, char** argv) {
  Options o;
  std::vector<std::string> scenes;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    auto value = [&] {
      if (k + 1 >= argc) {
        std::fprintf(stderr, "render_motion_quality: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return std::string(argv[++k]);
    };
    if (a == "--size") o.size = std::stoi(value());
    else if (a == "--frames") o.frames = std::stoi(value());
    else if (a == "--budget") o.budget = std::stod(value());
    else if (a == "--spp") o.spp = std::stoi(value());
    else if (a == "--out") o.out = value();
    else if (a == "--seed") o.seed = std::stoull(value());
    else if (a == "--runs") o.runs = "," + value() + ",";
    else if (a == "--reference-dir") o.reference_dir = value();
    else if (a == "--occlusion-radius") o.occlusion_radius = std::stoi(value());
    else if (a == "--sparse-occlusion-radius") o.sparse_occlusion_radius = std::stoi(value());
    else if (a == "--new-occluder-radius") o.new_occluder_radius = std::stoi(value());
    else if (a == "--times") o.times = true;
    else if (a == "--as-async") o.as_async = true;
    else if (a == "--no-trace-ahead") o.trace_ahead = false;
    else if (a == "--no-punctual-highlights") o.punctual_highlights = false;
    else if (a == "--colours") o.colours = true;
    else if (a == "--settle") o.settle = std::stoi(value());
    else if (a == "--edges") o.edges = true;
    else if (a.starts_with("-")) o.size = 0;  // unknown option (also --help): the usage line below
    else scenes.push_back(a);
  }
  if (scenes.empty() || o.size < 8 || o.frames < 1 || o.settle < 0 || !(o.budget > 0.0 && o.budget <= 1.0)) {
    std::fprintf(stderr, "usage: render_motion_quality [--size N] [--frames N] [--budget F] [--spp N] [--seed N] [--runs path,still,rc] [--reference-dir DIR] [--occlusion-radius N] [--sparse-occlusion-radius N] [--new-occluder-radius N] [--as-async] [--no-trace-ahead] [--no-punctual-highlights] [--times] [--colours] [--settle N] [--edges] [--out DIR] SCENE.gltf...\n");
    return 2;
  }
  if (!o.out.empty()) std::filesystem::create_directories(o.out);
  std::printf("%dx%d, %d frames along the path, sync%s%s, budget %.3f, seed %llu, direct shader, reference %d spp\n", o.size,
              o.size, o.frames, o.as_async ? " as async" : "", o.trace_ahead ? "" : ", not traced ahead", o.budget, (unsigned long long)o.seed, o.spp);
  std::printf("| scene | run | RMSE | > 0.1 | > 0.2 | hidden | colour | near hidden | other |%s%s\n|---|---|---|---|---|---|---|---|---|%s%s\n",
              o.times ? " points ms |" : "", o.edges ? " edges behind |" : "", o.times ? "---|" : "", o.edges ? "---|" : "");
  std::vector<Run> colour_rows;
  std::vector<std::string> colour_labels;
  struct Settling {
    std::string scene, run;
    std::vector<double> rmse;
    double still = 0.0;
  };
  std::vector<Settling> settling;
  for (const std::string& file : scenes) {
    const Scene scene = load_scene(file);
    RayScene ray_scene(scene);
    const Shader shader(ray_scene, ShaderSettings{});
    View view;
    view.camera = scene_camera_path(scene, o.frames).camera_at(o.frames - 1), view.width = o.size, view.height = o.size;
    const std::string name = std::filesystem::path(file).stem().string();
    const std::string kept = o.reference_dir.empty() ? "" : o.reference_dir + "/" + name + "_" + std::to_string(o.size) + "_" +
                                                                std::to_string(o.spp) + "spp_" + std::to_string(o.frames) + ".exr";
    RgbImage reference;
    if (!kept.empty() && std::filesystem::exists(kept)) {
      reference = read_image(kept);
    } else {
      reference = render_image(shader, view, o.spp);
      if (!kept.empty()) std::filesystem::create_directories(o.reference_dir), write_image(kept, reference);
    }
    if (!o.out.empty()) write_image(o.out + "/" + name + "_reference.png", reference);
    const struct {
      const char* label;
      const char* key;
      bool still;
      RenderMode mode;
    } runs[] = {{"epi, path", ",path,", false, RenderMode::epi}, {"epi, still", ",still,", true, RenderMode::epi},
                {"render cache, path", ",rc,", false, RenderMode::rendercache}};
    for (const auto& k : runs) {
      if (o.runs != "path,still,rc" && o.runs.find(k.key) == std::string::npos) continue;
      const std::string image_file = o.out.empty() ? "" : o.out + "/" + name + "_" + (k.mode == RenderMode::epi ? "epi" : "rc") +
                                                               (k.still ? "_still" : "_path") + ".png";
      const Run r = run(scene, ray_scene, shader, o, k.still, k.mode, reference, image_file);
      if (o.colours && k.mode == RenderMode::epi) colour_rows.push_back(r), colour_labels.push_back(name + " | " + k.label);
      if (!r.settle.empty()) settling.push_back({name, k.label, r.settle});
      if (k.still && k.mode == RenderMode::epi)
        for (Settling& t : settling)
          if (t.scene == name) t.still = r.rmse;
      std::printf("| %s | %s | %.4f | %.2f %% | %.2f %% | %zu | %zu | %zu | %zu |", name.c_str(), k.label, r.rmse, r.over01,
                  r.over02, r.hidden, r.colour, r.near, r.other);
      if (o.times) std::printf(" %.2f |", r.points_ms);
      if (o.edges) std::printf(" %.2f %% |", r.edge_length > 0 ? 100.0 * r.edge_behind / r.edge_length : 0.0);
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  if (!settling.empty()) {
    // The checkpoints: the stop, 1, 2, 4, ... frames after it, and the last.
    std::vector<int> at;
    for (int f = 0; f <= o.settle; f = f == 0 ? 1 : 2 * f) at.push_back(f);
    if (at.back() != o.settle) at.push_back(o.settle);
    std::printf("\nSettling: the camera held at the last view after the path, display RMSE %d frames after the stop (+0: the stop)\n\n| scene | run |", o.settle);
    for (const int f : at) std::printf(" +%d |", f);
    std::printf(" still | frames to 1.5x still | frames to 1.1x still |\n|---|---|");
    for (size_t k = 0; k < at.size() + 3; ++k) std::printf("---|");
    std::printf("\n");
    for (const Settling& t : settling) {
      std::printf("| %s | %s |", t.scene.c_str(), t.run.c_str());
      for (const int f : at) std::printf(" %.4f |", t.rmse[size_t(f)]);
      auto frames_to = [&](double factor) {
        for (size_t f = 0; f < t.rmse.size(); ++f)
          if (t.still > 0.0 && t.rmse[f] <= factor * t.still) return std::to_string(f);
        return t.still > 0.0 ? "> " + std::to_string(o.settle) : std::string("(no still run)");
      };
      std::printf(t.still > 0.0 ? " %.4f |" : " |", t.still);
      std::printf(" %s | %s |\n", frames_to(1.5).c_str(), frames_to(1.1).c_str());
    }
  }
  if (o.colours) {
    std::printf("\n| scene | run | drawn points compared | colour shown off > 0.1 | reported view-dependent | diffuse transmission | other |\n|---|---|---|---|---|---|---|\n");
    for (size_t k = 0; k < colour_rows.size(); ++k) {
      const Run& r = colour_rows[k];
      const double off = std::max<double>(1.0, double(r.off));
      const size_t other = r.off - r.reported - r.transmission;
      std::printf("| %s | %zu | %zu (%.2f %%) | %zu (%.0f %%) | %zu (%.0f %%) | %zu (%.0f %%) |\n", colour_labels[k].c_str(), r.compared,
                  r.off, 100.0 * double(r.off) / std::max<double>(1.0, double(r.compared)), r.reported,
                  100.0 * double(r.reported) / off, r.transmission, 100.0 * double(r.transmission) / off, other, 100.0 * double(other) / off);
    }
  }
  return 0;
}

int main(int argc, char** argv) {
  try {
    return run_all(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_motion_quality: %s\n", e.what());
    return 1;
  }
}

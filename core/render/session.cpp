#include "render/session.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "epi/geometry.h"
#include "epi/reachability.h"
#include "shade/render_image.h"

namespace epi::render {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// FNV-1a over raw bytes: what an accumulation (raytrace, reference) was made for.
struct Hash {
  uint64_t h = 1469598103934665603ull;
  template <class T>
  void add(const T& v) {
    const auto* b = reinterpret_cast<const unsigned char*>(&v);
    for (size_t i = 0; i < sizeof(T); ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
};

uint64_t view_hash(const SessionInput& in) {
  Hash h;
  h.add(in.camera.eye), h.add(in.camera.target), h.add(in.camera.up), h.add(in.camera.yfov_degrees);
  for (const glm::mat4& m : in.objects) h.add(m);
  for (const glm::vec3& l : in.lights) h.add(l);
  const SessionSettings& s = in.settings;
  h.add(s.mode), h.add(s.frame.width), h.add(s.frame.height), h.add(s.reference_spp);
  return h.h;
}

bool same_shader(const ShaderSettings& a, const ShaderSettings& b) {
  return a.kind == b.kind && a.area_light_samples == b.area_light_samples && a.glossy_samples == b.glossy_samples &&
         a.glossy_light_samples == b.glossy_light_samples && a.gi_paths == b.gi_paths &&
         a.gi_light_samples == b.gi_light_samples && a.gi_max_bounces == b.gi_max_bounces &&
         a.gi_roulette_bounce == b.gi_roulette_bounce && a.gi_path_clamp == b.gi_path_clamp &&
         a.specular == b.specular && a.record_blockers == b.record_blockers && a.seed == b.seed &&
         a.ray_offset == b.ray_offset;
}

bool same_frame_settings(const FrameSettings& a, const FrameSettings& b) {
  return a.width == b.width && a.height == b.height && a.sample_budget == b.sample_budget &&
         a.rest_sample_budget == b.rest_sample_budget && a.grow_integrate_share == b.grow_integrate_share &&
         a.motion_sample_budget == b.motion_sample_budget && a.motion_frame_ms == b.motion_frame_ms &&
         a.sync == b.sync && a.seed == b.seed && a.antialias == b.antialias && a.complex_filter == b.complex_filter &&
         a.stage_timings == b.stage_timings && a.shader_threads == b.shader_threads && a.view_edges == b.view_edges &&
         a.shadow_edges == b.shadow_edges && a.soft_shadow_edges == b.soft_shadow_edges &&
         a.occlusion_culling == b.occlusion_culling && a.occlusion_test == b.occlusion_test && a.fill_holes == b.fill_holes &&
         a.sparse_blend == b.sparse_blend && a.sparse_effort == b.sparse_effort &&
         a.cache.sparse_occlusion_radius == b.cache.sparse_occlusion_radius &&
         a.cache.new_occluder_radius == b.cache.new_occluder_radius &&
         a.cache.punctual_highlight_share == b.cache.punctual_highlight_share && a.trace_ahead == b.trace_ahead;
}

View make_view(const Camera& camera, int width, int height) {
  View v;
  v.camera = camera, v.width = width, v.height = height;
  return v;
}

// A per-pixel jitter in [0, 1) for raytrace pass `pass` (pass 0: the pixel centre).
float jitter(uint64_t pixel, uint64_t pass, uint64_t axis) {
  uint64_t x = pixel * 0x9e3779b97f4a7c15ull ^ (pass * 0xbf58476d1ce4e5b9ull) ^ (axis * 0x94d049bb133111ebull);
  x ^= x >> 31, x *= 0xd6e9a3c1c1b1e4b5ull, x ^= x >> 29;
  return float(x >> 40) / float(1ull << 24);
}

void set(RgbImage& image, size_t i, glm::vec3 c) {
  image.pixels[3 * i] = c.r, image.pixels[3 * i + 1] = c.g, image.pixels[3 * i + 2] = c.b;
}

// Colours of the stage views (linear RGB).
constexpr glm::vec3 kEdgeColors[edges::kEdgeKindCount] = {
    {1.0f, 0.85f, 0.1f},   // silhouette
    {0.1f, 0.8f, 1.0f},    // sharp
    {1.0f, 0.2f, 1.0f},    // border
    {1.0f, 0.1f, 0.05f},   // umbral
    {1.0f, 0.45f, 0.0f},   // penumbral
    {0.25f, 0.35f, 1.0f},  // shadow
};

glm::vec3 class_color(int type, bool sample) {
  if (type == kTypeComplex) return sample ? glm::vec3(1.0f, 0.45f, 0.45f) : glm::vec3(0.75f, 0.05f, 0.05f);
  if (type_is_simple(type)) return sample ? glm::vec3(0.45f, 1.0f, 0.5f) : glm::vec3(0.05f, 0.45f, 0.1f);
  return sample ? glm::vec3(0.55f) : glm::vec3(0.03f);
}

void draw_segment(RgbImage& image, const Segment& s, glm::vec3 color) {
  const double dx = s.x1 - s.x0, dy = s.y1 - s.y0;
  const int steps = std::max(1, int(std::ceil(std::max(std::abs(dx), std::abs(dy)) * 2.0)));
  for (int k = 0; k <= steps; ++k) {
    const double t = double(k) / steps;
    const int x = int(std::floor(s.x0 + dx * t)), y = int(std::floor(s.y0 + dy * t));
    if (x >= 0 && y >= 0 && x < image.width && y < image.height) set(image, size_t(y) * size_t(image.width) + size_t(x), color);
  }
}

// Square dilation (grow = true) or erosion of a 0/1 mask by radius r, separably with running
// counts: O(pixels) whatever r.
void grow_mask(std::vector<uint8_t>& mask, std::vector<uint8_t>& scratch, int w, int h, int r, bool grow) {
  auto pass = [&](const std::vector<uint8_t>& in, std::vector<uint8_t>& out, int n, int lines, size_t step, size_t line_step) {
    tbb::parallel_for(0, lines, [&](int line) {
      const size_t base = size_t(line) * line_step;
      int count = 0;  // set pixels in the window [k - r, k + r]
      for (int k = 0; k < std::min(r, n); ++k) count += in[base + size_t(k) * step];
      for (int k = 0; k < n; ++k) {
        if (k + r < n) count += in[base + size_t(k + r) * step];
        if (k - r - 1 >= 0) count -= in[base + size_t(k - r - 1) * step];
        const int window = std::min(n - 1, k + r) - std::max(0, k - r) + 1;
        out[base + size_t(k) * step] = grow ? count > 0 : count == window;
      }
    });
  };
  scratch.resize(mask.size());
  pass(mask, scratch, w, h, 1, size_t(w));         // rows
  pass(scratch, mask, h, w, size_t(w), 1);         // columns
}

// Sets every 0 pixel that no path of 0 pixels (4-connected) joins to the image border.
void fill_holes(std::vector<uint8_t>& mask, int w, int h) {
  std::vector<uint8_t> outside(mask.size(), 0);
  std::vector<size_t> stack;
  auto visit = [&](int x, int y) {
    const size_t i = size_t(y) * size_t(w) + size_t(x);
    if (!mask[i] && !outside[i]) outside[i] = 1, stack.push_back(i);
  };
  for (int x = 0; x < w; ++x) visit(x, 0), visit(x, h - 1);
  for (int y = 0; y < h; ++y) visit(0, y), visit(w - 1, y);
  while (!stack.empty()) {
    const size_t i = stack.back();
    stack.pop_back();
    const int x = int(i % size_t(w)), y = int(i / size_t(w));
    if (x > 0) visit(x - 1, y);
    if (x + 1 < w) visit(x + 1, y);
    if (y > 0) visit(x, y - 1);
    if (y + 1 < h) visit(x, y + 1);
  }
  for (size_t i = 0; i < mask.size(); ++i) mask[i] = mask[i] || !outside[i];
}

void close_mask(std::vector<uint8_t>& mask, std::vector<uint8_t>& scratch, int w, int h, int r) {
  grow_mask(mask, scratch, w, h, r, true);
  grow_mask(mask, scratch, w, h, r, false);
}

}  // namespace

const char* to_string(SessionMode mode) {
  switch (mode) {
    case SessionMode::epi: return "epi";
    case SessionMode::rendercache: return "rendercache";
    case SessionMode::raytrace: return "raytrace";
    case SessionMode::reference: return "reference";
  }
  return "?";
}

const char* to_string(StageView view) {
  switch (view) {
    case StageView::final: return "final";
    case StageView::points: return "points";
    case StageView::edges: return "edges";
    case StageView::classes: return "classes";
    case StageView::reachability: return "reachability";
    case StageView::priority: return "priority";
    case StageView::depth: return "depth";
  }
  return "?";
}

SessionMode session_mode(const std::string& name) {
  for (SessionMode m : {SessionMode::epi, SessionMode::rendercache, SessionMode::raytrace, SessionMode::reference})
    if (name == to_string(m)) return m;
  throw std::invalid_argument("unknown mode '" + name + "'");
}

bool SessionSettings::needs_rebuild(const SessionSettings& other) const {
  return mode != other.mode || !same_frame_settings(frame, other.frame) || !same_shader(shader, other.shader) ||
         threads != other.threads || reference_spp != other.reference_spp;
}

Session::Session(const Scene& scene, const SessionInput& input, DisplayFunction display)
    : scene_(scene), display_(std::move(display)), input_(input) {
  input_.time = Clock::now();
  ray_scene_ = std::make_unique<RayScene>(scene_);
  rebuild(input.settings);
  // A bad camera or placement fails here, on the caller's thread, not later in a frame.
  const ViewFrame check(make_view(input.camera, input.settings.frame.width, input.settings.frame.height));
  if (!input.objects.empty() && input.objects.size() != scene.objects.size())
    throw std::invalid_argument("session: " + std::to_string(input.objects.size()) + " object transforms for " +
                                std::to_string(scene.objects.size()) + " objects");
  if (!input.lights.empty() && input.lights.size() != scene.punctual_lights.size())
    throw std::invalid_argument("session: " + std::to_string(input.lights.size()) + " light positions for " +
                                std::to_string(scene.punctual_lights.size()) + " punctual lights");
  rays_mark_time_ = Clock::now();
  thread_ = std::thread([this] { run(); });
}

Session::~Session() {
  {
    std::lock_guard lock(input_mutex_);
    stop_ = true;
  }
  input_changed_.notify_all();
  if (thread_.joinable()) thread_.join();
  renderer_.reset();  // the async shader joins before the shader and ray scene go
}

uint64_t Session::post(SessionInput input) {
  {
    std::lock_guard lock(input_mutex_);
    input.sequence = ++next_sequence_;
    input.time = Clock::now();
    input_ = std::move(input);
  }
  input_changed_.notify_all();
  return next_sequence_;
}

uint64_t Session::pick(glm::ivec2 pixel) {
  uint64_t id;
  {
    std::lock_guard lock(input_mutex_);
    id = ++next_pick_;
    picks_.push_back({id, pixel});
  }
  input_changed_.notify_all();
  return id;
}

bool Session::take_frame(uint64_t have, SessionFrame& out) const {
  std::lock_guard lock(frame_mutex_);
  if (front_.number <= have) return false;
  out = front_;  // vector assignment keeps out's buffers when they are large enough
  return true;
}

bool Session::take_frame(uint64_t have, SessionFrame& out, const DisplayTarget& display_target) const {
  std::lock_guard lock(frame_mutex_);
  if (front_.number <= have) return false;
  RgbImage image;
  std::vector<uint32_t> display;
  std::swap(front_.image, image);
  std::swap(front_.display, display);
  out = front_;  // everything but the pixels
  std::swap(front_.image, image);
  std::swap(front_.display, display);
  if (display_target && !front_.display.empty())
    if (uint32_t* target = display_target(front_.width, front_.height))
      std::memcpy(target, front_.display.data(), front_.display.size() * sizeof(uint32_t));
  return true;
}

uint64_t Session::copy_image(RgbImage& out) const {
  std::lock_guard lock(frame_mutex_);
  out = front_.image;
  return front_.number;
}

bool Session::wait_for_frame(uint64_t n, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(frame_mutex_);
  return frame_ready_.wait_for(lock, timeout, [&] { return front_.number >= n; });
}

void Session::rebuild(const SessionSettings& settings) {
  renderer_.reset();  // joins its async shader first
  if (!thread_limit_ || settings.threads != built_.threads) {
    thread_limit_.reset();
    if (settings.threads > 0)
      thread_limit_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(settings.threads));
  }
  if (!shader_ || !same_shader(settings.shader, built_.shader)) shader_ = std::make_unique<Shader>(*ray_scene_, settings.shader);
  if (settings.mode == SessionMode::epi || settings.mode == SessionMode::rendercache) {
    FrameSettings fs = settings.frame;
    fs.mode = settings.mode == SessionMode::epi ? RenderMode::epi : RenderMode::rendercache;
    const auto edge_settings = FrameRenderer::edge_finder_settings(fs);
    if (edge_settings && !(edge_finder_ && edge_finder_->settings() == *edge_settings)) {
      edge_finder_ = std::make_shared<edges::SceneEdgeFinder>(scene_, *edge_settings);
      ++edge_finder_builds_;
    }
    renderer_ = std::make_unique<FrameRenderer>(scene_, *ray_scene_, *shader_, fs, edge_settings ? edge_finder_ : nullptr);
  }
  built_ = settings;
  passes_ = 0;
  accumulated_for_ = 0;
  reference_done_ = false;
}

void Session::place_directly(const SessionInput& input) {
  // raytrace and reference: no asynchronous shading runs, so the ray scene is moved here.
  for (uint32_t o = 0; o < input.objects.size(); ++o)
    if (ray_scene_->object_to_world(o) != input.objects[o]) ray_scene_->set_object_transform(o, input.objects[o]);
  for (uint32_t l = 0; l < input.lights.size(); ++l)
    if (scene_.punctual_lights[l].type != LightType::directional &&
        ray_scene_->punctual_lights()[l].position != input.lights[l])
      ray_scene_->set_punctual_light_position(l, input.lights[l]);
}

void Session::render_raytrace_pass(const SessionInput& input, bool restart) {
  const int w = built_.frame.width, h = built_.frame.height;
  const size_t pixels = size_t(w) * size_t(h);
  if (restart || accumulated_.width != w || accumulated_.height != h) {
    accumulated_ = RgbImage(w, h);
    averaged_ = RgbImage(w, h);
    ray_objects_.assign(pixels, -1);
    passes_ = 0;
  }
  const ViewFrame frame(make_view(input.camera, w, h));
  std::vector<ShadeRequest> requests(pixels);
  for (size_t i = 0; i < pixels; ++i) {
    const int x = int(i % size_t(w)), y = int(i / size_t(w));
    const float jx = passes_ == 0 ? 0.5f : jitter(i, uint64_t(passes_), 0);
    const float jy = passes_ == 0 ? 0.5f : jitter(i, uint64_t(passes_), 1);
    requests[i] = {uint32_t(i), float(x) + jx, float(y) + jy};
  }
  ShadeBatch batch;
  shader_->shade(frame, requests, batch);
  for (const ShadeResult& r : batch.results) {
    float* a = &accumulated_.pixels[3 * size_t(r.id)];
    a[0] += r.color.r, a[1] += r.color.g, a[2] += r.color.b;
    ray_objects_[r.id] = r.hit ? int32_t(r.object) : -1;
  }
  ++passes_;
  const float scale = 1.0f / float(passes_);
  for (size_t k = 0; k < accumulated_.pixels.size(); ++k) averaged_.pixels[k] = accumulated_.pixels[k] * scale;
}

void Session::run() {
  Clock::time_point next_frame = Clock::now();
  uint64_t last_hash = 0;
  while (true) {
    SessionInput input;
    double path_frame = -1.0;  // the path frame this input shows (-1: none)
    std::vector<PickRequest> picks;
    {
      std::unique_lock lock(input_mutex_);
      // Idle while there is nothing new to show: past the frame limit, a finished reference, or a
      // raytrace accumulation that has converged enough; a new input or pick wakes the thread.
      input_changed_.wait(lock, [&] {
        if (stop_) return true;
        if (!picks_.empty()) return true;
        const SessionSettings& s = input_.settings;
        if (s.frame_limit > 0 && frames_.load() >= s.frame_limit) return false;
        if (s.mode == SessionMode::reference && reference_done_ && view_hash(input_) == last_hash &&
            !s.needs_rebuild(built_))
          return false;
        if (s.mode == SessionMode::raytrace && passes_ >= 4096 && view_hash(input_) == last_hash) return false;
        return true;
      });
      if (stop_) return;
      input = input_;
      if (input.path) {  // this frame's keys
        const double f =
            input.path_rate > 0.0
                ? std::min(input.path->last_frame(),
                           input.path_rate * std::max(0.0, std::chrono::duration<double>(Clock::now() - input.path_clock_start).count()))
                : double(frames_.load() - std::min(frames_.load(), input.path_start));
        path_frame = f;
        if (!input.path->cameras.empty()) input.camera = input.path->camera_at(f);
        if (input.path->moves_objects()) input.objects = input.path->object_transforms_at(scene_, f);
        if (input.path->moves_lights()) input.lights = input.path->light_positions_at(scene_, f);
      }
      picks.swap(picks_);
    }
    if (input.settings.max_fps > 0.0) {
      std::this_thread::sleep_until(next_frame);
      next_frame = std::max(next_frame + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(1.0 / input.settings.max_fps)),
                            Clock::now() - std::chrono::milliseconds(100));
    }
    const auto start = Clock::now();
    SessionFrame& frame = back_;
    frame.error.clear();
    frame.picks.clear();
    try {
      if (input.settings.needs_rebuild(built_)) rebuild(input.settings);
      render_frame(input, frame);
      for (const PickRequest& p : picks) {
        PickResult answer;
        answer_pick(p, input, answer);
        picks_answered_.push_back(answer);
        if (picks_answered_.size() > 16) picks_answered_.erase(picks_answered_.begin());
      }
    } catch (const std::exception& e) {
      frame.error = e.what();
    }
    last_hash = view_hash(input);
    frame.input_sequence = input.sequence;
    frame.input_time = input.time;
    frame.camera = input.camera;
    frame.path_frame = path_frame;
    frame.settings = input.settings;
    frame.settings.frame.before_shading_slice = nullptr;
    // Rays per second over the last half second or more of wall time.
    const double since = std::chrono::duration<double>(Clock::now() - rays_mark_time_).count();
    if (since >= 0.5) {
      const uint64_t rays = shader_->rays_traced();
      mrays_per_second_ = double(rays - std::min(rays, rays_mark_)) / since * 1e-6;
      rays_mark_ = rays, rays_mark_time_ = Clock::now();
    }
    frame.mrays_per_second = mrays_per_second_;
    frame.picks = picks_answered_;
    frame.frame_ms = ms_since(start);
    frame.done_time = Clock::now();
    {
      std::lock_guard lock(frame_mutex_);
      frame.number = frames_.load() + 1;
      std::swap(front_, back_);
      frames_.store(front_.number);
    }
    frame_ready_.notify_all();
  }
}

void Session::render_frame(const SessionInput& input, SessionFrame& frame) {
  const SessionMode mode = built_.mode;
  const RgbImage* final_image = nullptr;
  frame.stats = {};
  frame.cache_points = frame.cache_capacity = 0;
  frame.passes = 0;
  if (mode == SessionMode::epi || mode == SessionMode::rendercache) {
    if (!renderer_) throw std::runtime_error("the frame loop could not be built for these settings");
    final_image = &renderer_->render(input.camera, input.objects, input.lights);
    frame.stats = renderer_->stats();
    frame.cache_points = renderer_->cache().valid_points();
    frame.cache_capacity = renderer_->cache().capacity();
  } else {
    place_directly(input);
    const uint64_t hash = view_hash(input);
    const bool changed = hash != accumulated_for_;
    accumulated_for_ = hash;
    const auto t = Clock::now();
    if (mode == SessionMode::raytrace) {
      render_raytrace_pass(input, changed);
    } else if (changed || !reference_done_) {
      reference_progress_ = 0.0;
      averaged_ = render_image(*shader_, make_view(input.camera, built_.frame.width, built_.frame.height), built_.reference_spp,
                               [this](double done) { reference_progress_ = done; });
      reference_progress_ = 1.0;
      ray_objects_.clear();
      passes_ = 1;
      reference_done_ = true;
    }
    frame.stats.ms.total = ms_since(t);
    frame.passes = passes_;
    final_image = &averaged_;
  }
  stage_image(input, *final_image, frame);
  frame.width = frame.image.width, frame.height = frame.image.height;
  frame.display.clear();
  frame.display_tag = display_ ? display_(frame.image, frame.display) : -1;
}

void Session::stage_image(const SessionInput& input, const RgbImage& final_image, SessionFrame& frame) {
  const int w = final_image.width, h = final_image.height;
  const size_t pixels = size_t(w) * size_t(h);
  StageView stage = input.settings.stage;
  if (!renderer_) stage = StageView::final;  // the stage images are the frame loop's
  RgbImage& out = frame.image;
  out.width = w, out.height = h;
  if (stage == StageView::final) {
    // 25 MB at 1920x1080, every frame: copied in parallel blocks.
    out.pixels.resize(final_image.pixels.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, out.pixels.size(), size_t(1) << 16), [&](const tbb::blocked_range<size_t>& r) {
      std::copy(final_image.pixels.begin() + ptrdiff_t(r.begin()), final_image.pixels.begin() + ptrdiff_t(r.end()),
                out.pixels.begin() + ptrdiff_t(r.begin()));
    });
  } else {
    out.pixels.assign(pixels * 3, 0.0f);
  }
  frame.probe = PixelProbe{};

  // The object per pixel (outline, picking): the drawn points, or the raytrace pass's hits.
  auto object_at = [&](size_t i) -> int {
    if (renderer_) {
      const int32_t p = renderer_->cache().image().point[i];
      if (p < 0) return -1;
      const uint32_t o = renderer_->cache().points()[size_t(p)].object;
      return o == kNone ? -1 : int(o);
    }
    return ray_objects_.size() == pixels ? ray_objects_[i] : -1;
  };

  if (renderer_) {
    const PointImage& points = renderer_->cache().image();
    // The classified words (the renderer's EPI is the reconstruction's input: no types or masks).
    const std::vector<uint16_t>& edge = renderer_->classified_edge();
    const std::vector<uint32_t>& cache = renderer_->classified_cache();
    const bool classified = edge.size() == pixels && cache.size() == pixels;
    switch (stage) {
      case StageView::final: break;
      case StageView::points: {
        const int max_age = std::max(1, renderer_->cache().settings().max_age);
        tbb::parallel_for(size_t(0), pixels, [&](size_t i) {
          const int32_t p = points.point[i];
          if (p < 0) return;
          const float t = std::min(1.0f, float(renderer_->cache().points()[size_t(p)].age) / float(max_age) * 8.0f);
          set(out, i, glm::mix(glm::vec3(0.2f, 1.0f, 0.25f), glm::vec3(1.0f, 0.08f, 0.05f), std::sqrt(t)));
        });
        break;
      }
      case StageView::edges: {
        const auto& segments = renderer_->segments();
        const auto& kinds = renderer_->segment_kinds();
        for (size_t k = 0; k < segments.size(); ++k)
          draw_segment(out, segments[k], kEdgeColors[k < kinds.size() ? int(kinds[k]) : 0]);
        break;
      }
      case StageView::classes:
      case StageView::reachability: {
        const float dim = stage == StageView::reachability ? 0.35f : 1.0f;
        if (classified)
          tbb::parallel_for(size_t(0), pixels, [&](size_t i) {
            set(out, i, class_color(pixel_type(cache[i]), usable_sample(edge[i])) * dim);
          });
        break;
      }
      case StageView::priority: {
        const std::vector<float>& pr = renderer_->priority();
        scratch_.assign(pr.begin(), pr.end());
        float top = 0.0f;
        if (!scratch_.empty()) {
          const size_t k = scratch_.size() * 99 / 100;
          std::nth_element(scratch_.begin(), scratch_.begin() + ptrdiff_t(k), scratch_.end());
          top = scratch_[k];
        }
        const float scale = top > 0.0f ? 1.0f / std::log1p(top) : 1.0f;
        tbb::parallel_for(size_t(0), std::min(pixels, pr.size()), [&](size_t i) {
          const float v = std::min(1.0f, std::log1p(std::max(0.0f, pr[i])) * scale);
          set(out, i, glm::vec3(v, v * v, 0.15f * (1.0f - v) + v * v * v));
        });
        break;
      }
      case StageView::depth: {
        // The depth the edge cull compares against (filtered, holes closed) where it exists,
        // else the drawn points' depth; near is bright.
        const std::vector<float>& filtered = renderer_->filtered_depth();
        const bool use_filtered = filtered.size() == pixels;
        auto depth = [&](size_t i) { return use_filtered ? filtered[i] : points.depth[i]; };
        float lo = 1e30f, hi = 0.0f;
        const float background = renderer_->cache().background_depth() * 0.5f;
        for (size_t i = 0; i < pixels; ++i)
          if (const float d = depth(i); std::isfinite(d) && d < background) lo = std::min(lo, d), hi = std::max(hi, d);
        const float span = hi > lo ? hi - lo : 1.0f;
        tbb::parallel_for(size_t(0), pixels, [&](size_t i) {
          const float d = depth(i);
          if (!std::isfinite(d) || d >= background) return;
          const float v = 1.0f - 0.85f * (d - lo) / span;
          set(out, i, glm::vec3(v * v));
        });
        break;
      }
    }
    // The hovered pixel's 5x5 (its reachability after classification).
    const glm::ivec2 q = input.probe;
    if (q.x >= 0 && q.y >= 0 && q.x < w && q.y < h && classified) {
      PixelProbe& probe = frame.probe;
      probe.pixel = q;
      auto index = [&](int x, int y) { return size_t(y) * size_t(w) + size_t(x); };
      probe.reach = reach_mask(cache[index(q.x, q.y)]);
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int x = q.x + dx, y = q.y + dy;
          const bool inside = x >= 0 && y >= 0 && x < w && y < h;
          probe.types[dy + 2][dx + 2] = inside ? pixel_type(cache[index(x, y)]) : -1;
          probe.samples[dy + 2][dx + 2] = inside && usable_sample(edge[index(x, y)]);
          if (stage != StageView::reachability || !inside) continue;
          const bool centre = dx == 0 && dy == 0;
          const bool reached = !centre && (probe.reach >> reach_bit(dx, dy)) & 1u;
          set(out, index(x, y), centre ? glm::vec3(0.2f, 0.4f, 1.0f) : reached ? glm::vec3(0.2f, 1.0f, 0.3f) : glm::vec3(1.0f, 0.15f, 0.1f));
        }
    }
  }

  // The selected object's outline: its footprint among the drawn points, closed (dilated, then
  // eroded, by about the typical gap between points) and with its holes filled (a gap wider than
  // the closing, or a hole in the object), and the ring one pixel outside it.
  if (input.highlight_object >= 0 && stage == StageView::final) {
    std::vector<uint8_t> mask(pixels, 0), scratch(pixels, 0);
    size_t drawn = 0;
    for (size_t i = 0; i < pixels; ++i) {
      const int o = object_at(i);
      drawn += o != -1 || (renderer_ && renderer_->cache().image().point[i] >= 0);
      mask[i] = o == input.highlight_object;
    }
    const int gap = int(std::lround(std::sqrt(double(pixels) / double(std::max<size_t>(drawn, 1)))));
    const int r = std::clamp(gap, 1, 8);
    close_mask(mask, scratch, w, h, r);
    fill_holes(mask, w, h);
    std::vector<uint8_t> ring = mask;
    grow_mask(ring, scratch, w, h, 1, true);
    for (size_t i = 0; i < pixels; ++i)
      if (ring[i] && !mask[i]) set(out, i, glm::vec3(1.0f, 0.55f, 0.0f));
  }
}

void Session::answer_pick(const PickRequest& request, const SessionInput& input, PickResult& out) {
  out = PickResult{};
  out.id = request.id;
  const int w = built_.frame.width, h = built_.frame.height;
  const glm::ivec2 q = request.pixel;
  if (q.x < 0 || q.y < 0 || q.x >= w || q.y >= h) return;
  auto transform = [&](uint32_t o) { return input.objects.empty() ? ray_scene_->object_to_world(o) : input.objects[o]; };
  if (renderer_) {
    // The drawn point nearest the pixel, within 3 pixels (the point image has holes).
    const PointImage& points = renderer_->cache().image();
    for (int r = 0; r <= 3; ++r)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (std::max(std::abs(dx), std::abs(dy)) != r) continue;
          const int x = q.x + dx, y = q.y + dy;
          if (x < 0 || y < 0 || x >= w || y >= h) continue;
          const int32_t p = points.point[points.index(x, y)];
          if (p < 0) continue;
          const CachePoint& cp = renderer_->cache().points()[size_t(p)];
          if (cp.object == kNone) return;  // background
          out.object = int(cp.object);
          out.world = glm::vec3(transform(cp.object) * glm::vec4(cp.local, 1.0f));
          return;
        }
    return;
  }
  // raytrace and reference: nothing traces concurrently, so a ray answers.
  const ViewFrame frame(make_view(input.camera, w, h));
  const Ray ray = frame.ray(float(q.x) + 0.5f, float(q.y) + 0.5f);
  const RayHit hit = ray_scene_->intersect(ray);
  if (!hit.hit || hit.object == kNone) return;
  out.object = int(hit.object);
  out.world = ray.origin + ray.direction * hit.t;
}

}  // namespace epi::render

#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "render/sampling.h"

namespace epi::render {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

View make_view(const Camera& camera, int width, int height) {
  View v;
  v.camera = camera, v.width = width, v.height = height;
  return v;
}

bool same_camera(const Camera& a, const Camera& b) {
  return a.eye == b.eye && a.target == b.target && a.up == b.up && a.yfov_degrees == b.yfov_degrees;
}

}  // namespace

FrameRenderer::FrameRenderer(const Scene& scene, RayScene& ray_scene, const Shader& shader, const FrameSettings& settings)
    : scene_(scene),
      ray_scene_(ray_scene),
      shader_(shader),
      settings_(settings),
      cache_(settings.width, settings.height, settings.cache),
      epi_(settings.width, settings.height),
      masks_(settings.width, settings.height, settings.mode == RenderMode::epi && settings.complex_filter) {
  if (!(settings.sample_budget > 0.0 && settings.sample_budget <= 1.0))
    throw std::invalid_argument("sample budget " + std::to_string(settings.sample_budget) + " is not in (0, 1]");
  transforms_.reserve(scene.objects.size());
  for (uint32_t o = 0; o < scene.objects.size(); ++o) transforms_.push_back(ray_scene.object_to_world(o));
  if (!settings.sync) async_ = std::make_unique<AsyncShader>(shader, settings.shader_threads);
}

FrameRenderer::~FrameRenderer() = default;  // the AsyncShader drops pending work and joins

size_t FrameRenderer::budget() const {
  const double pixels = double(settings_.width) * double(settings_.height);
  return size_t(std::max(1.0, std::round(settings_.sample_budget * pixels)));
}

void FrameRenderer::apply_transforms(std::span<const glm::mat4> object_to_world) {
  if (object_to_world.empty()) return;
  if (object_to_world.size() != transforms_.size())
    throw std::invalid_argument("frame renderer: " + std::to_string(object_to_world.size()) + " object transforms for " +
                                std::to_string(transforms_.size()) + " objects");
  bool moved = false;
  for (uint32_t o = 0; o < transforms_.size(); ++o) {
    if (object_to_world[o] == transforms_[o]) continue;
    transforms_[o] = object_to_world[o];
    moved = true;
    if (async_) {
      async_->run_between_batches([&rs = ray_scene_, o, m = object_to_world[o]] { rs.set_object_transform(o, m); });
    } else {
      ray_scene_.set_object_transform(o, object_to_world[o]);
    }
  }
  // Requests shaded against the old placement would put points in the wrong place.
  if (moved && async_) async_->cancel_pending();
}

void FrameRenderer::integrate(const ShadeBatch& batch) {
  // Results come in submission order; each run of ids belongs to one shot.
  size_t begin = 0;
  ShadeBatch part;
  while (begin < batch.results.size()) {
    const uint32_t id = batch.results[begin].id;
    const auto shot = std::find_if(shots_.begin(), shots_.end(),
                                   [id](const Shot& s) { return id - s.first_id < s.count; });
    size_t end = begin + 1;
    if (shot != shots_.end())
      while (end < batch.results.size() && batch.results[end].id - shot->first_id < shot->count) ++end;
    if (shot != shots_.end()) {
      part.results.assign(batch.results.begin() + ptrdiff_t(begin), batch.results.begin() + ptrdiff_t(end));
      stats_.samples += cache_.insert(shot->frame, part, transforms_);
    }
    begin = end;
  }
}

std::vector<FrameRenderer::NewShot> FrameRenderer::choose_requests(const ViewFrame& frame, std::span<const float> priority) {
  std::vector<NewShot> shots;
  const int w = settings_.width, h = settings_.height;
  size_t main_budget = budget();

  // Predictive sampling: the gaps of the view a few frames ahead, when the camera moves.
  const Camera& camera = frame.view().camera;
  if (previous_camera_ && !same_camera(*previous_camera_, camera) && settings_.predict_share > 0.0f) {
    const Camera ahead = extrapolate_camera(*previous_camera_, camera, settings_.predict_frames);
    const ViewFrame predicted(make_view(ahead, w, h));
    const std::vector<uint8_t> occupied = predicted_occupancy(cache_, predicted, transforms_, settings_.predict_stride,
                                                              frame_ % std::max(1, settings_.predict_stride),
                                                              settings_.predict_splat);
    std::vector<float> gaps(occupied.size());
    size_t gap_count = 0;
    for (size_t i = 0; i < occupied.size(); ++i) gaps[i] = occupied[i] ? 0.0f : 1.0f, gap_count += !occupied[i];
    const size_t n = std::min(gap_count, size_t(double(main_budget) * double(settings_.predict_share)));
    if (n > 0) {
      NewShot shot{predicted, {}};
      make_requests(dither_pixels(gaps, w, h, n), w, settings_.seed, uint64_t(frame_) * 2 + 1, 0, shot.requests);
      main_budget -= n;
      stats_.predicted = n;
      shots.push_back(std::move(shot));
    }
  }
  NewShot shot{frame, {}};
  make_requests(dither_pixels(priority, w, h, main_budget), w, settings_.seed, uint64_t(frame_) * 2, 0, shot.requests);
  shots.insert(shots.begin(), std::move(shot));

  // Ids, and the record of which view each id was made for.
  for (NewShot& s : shots) {
    for (ShadeRequest& r : s.requests) r.id = next_id_++;
    stats_.requested += s.requests.size();
    shots_.push_back({s.requests.empty() ? next_id_ : s.requests.front().id, uint32_t(s.requests.size()), s.frame});
  }
  while (shots_.size() > 32) shots_.pop_front();
  return shots;
}

const RgbImage& FrameRenderer::render(const Camera& camera, std::span<const glm::mat4> object_to_world) {
  const auto start = Clock::now();
  stats_ = {};
  apply_transforms(object_to_world);
  const ViewFrame frame(make_view(camera, settings_.width, settings_.height));

  // New shading results into the cache.
  auto t = Clock::now();
  ShadeBatch batch;
  double sampling_ms = 0.0;
  if (!async_) {
    // Sync: this frame's budget, chosen from the last priority image (uniform at first), shaded now.
    const auto ts = Clock::now();
    std::vector<NewShot> shots = choose_requests(frame, reconstruction_.priority);
    sampling_ms += ms_since(ts);
    const auto tsh = Clock::now();
    for (const NewShot& s : shots) shader_.shade(s.frame, s.requests, batch);
    stats_.ms.shade = ms_since(tsh);
  } else {
    async_->take_results(batch);
  }
  integrate(batch);
  stats_.points = cache_.project(frame, transforms_);
  cache_.fill_epi(epi_);
  stats_.ms.points = ms_since(t) - sampling_ms - stats_.ms.shade;

  // Edges (epi mode): none yet in this pipeline; the masks stay empty.
  if (settings_.mode == RenderMode::epi) masks_.clear();

  // Reconstruction.
  ReconstructSettings rs;
  rs.filter = settings_.mode == RenderMode::epi ? Filter::epi : Filter::rendercache;
  rs.antialias = settings_.antialias;
  rs.complex_filter = settings_.complex_filter;
  ReconstructTimes rt;
  reconstructor_.run(epi_, masks_, rs, reconstruction_, rt);
  stats_.ms.classify = rt.classify, stats_.ms.reachability = rt.reachability, stats_.ms.interpolate = rt.interpolate;
  stats_.ms.antialias = rt.antialias, stats_.ms.complex = rt.complex;
  stats_.pixels = reconstruction_.counts;

  // Async: the next requests from this frame's priority; stale ones are dropped.
  if (async_) {
    const auto ts = Clock::now();
    std::vector<NewShot> shots = choose_requests(frame, reconstruction_.priority);
    async_->cancel_pending();
    for (NewShot& s : shots) async_->submit(s.frame.view(), std::move(s.requests));
    sampling_ms += ms_since(ts);
  }
  stats_.ms.sampling = sampling_ms;
  previous_camera_ = std::make_unique<Camera>(camera);
  ++frame_;
  stats_.ms.total = ms_since(start);
  return reconstruction_.image;
}

}  // namespace epi::render

#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "epi/interpolate.h"
#include "render/hole_fill.h"
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

// Pixels crossed by the edge pieces, sampled every 1/8 pixel along each: kDepthEdge where a
// silhouette or border crosses, kSharpEdge where a sharp edge does, kShadowEdge where an umbral,
// penumbral or shadow edge does.
void mark_edge_pixels(std::span<const Segment> segments, std::span<const edges::EdgeKind> kinds, int w, int h,
                      std::vector<uint8_t>& mask) {
  mask.assign(size_t(w) * size_t(h), 0);
  for (size_t k = 0; k < segments.size(); ++k) {
    const edges::EdgeKind kind = kinds[k];
    const uint8_t bit = kind == edges::EdgeKind::silhouette || kind == edges::EdgeKind::border ? kDepthEdge
                        : kind == edges::EdgeKind::sharp                                       ? kSharpEdge
                                                                                               : kShadowEdge;
    const Segment& s = segments[k];
    const int steps = 1 + int(8.0 * std::hypot(double(s.x1) - double(s.x0), double(s.y1) - double(s.y0)));
    for (int j = 0; j <= steps; ++j) {
      const double t = double(j) / steps;
      const double x = s.x0 + t * (double(s.x1) - double(s.x0)), y = s.y0 + t * (double(s.y1) - double(s.y0));
      if (!(x >= 0.0 && y >= 0.0 && x < double(w) && y < double(h))) continue;
      mask[size_t(y) * size_t(w) + size_t(x)] |= bit;
    }
  }
}

}  // namespace

FrameRenderer::FrameRenderer(const Scene& scene, RayScene& ray_scene, const Shader& shader, const FrameSettings& settings)
    : scene_(scene),
      ray_scene_(ray_scene),
      shader_(shader),
      settings_(settings),
      cache_(settings.width, settings.height, settings.cache),
      epi_(settings.width, settings.height),
      masks_(settings.width, settings.height, settings.mode == RenderMode::epi && settings.complex_filter),
      reconstructor_(settings.kernels) {
  if (!(settings.sample_budget > 0.0 && settings.sample_budget <= 1.0))
    throw std::invalid_argument("sample budget " + std::to_string(settings.sample_budget) + " is not in (0, 1]");
  transforms_.reserve(scene.objects.size());
  for (uint32_t o = 0; o < scene.objects.size(); ++o) transforms_.push_back(ray_scene.object_to_world(o));
  for (const PunctualLight& l : ray_scene.punctual_lights()) light_positions_.push_back(l.position);
  placement_ = std::make_shared<const PlacementState>(PlacementState{transforms_, light_positions_});
  if (settings.mode == RenderMode::epi && (settings.view_edges || settings.shadow_edges)) {
    edges::SceneEdgeSettings edge_settings = settings.edge_finder;
    edge_settings.receiver_trees = settings.shadow_edges;  // model only what the settings use
    finder_ = std::make_unique<edges::SceneEdgeFinder>(scene, edge_settings);
    edge_scene_.source = scene.source;
    edge_scene_.objects = scene.objects;
    edge_scene_.punctual_lights = scene.punctual_lights;
    edge_scene_.area_lights = scene.area_lights;
    for (const Object& o : scene.objects) load_transforms_.push_back(o.object_to_world);
  }
  if (!settings.sync)
    async_ = std::make_unique<AsyncShader>(shader, settings.shader_threads, 1024, settings.before_shading_slice);
}

// The shader thread stops first: nothing it may still touch is torn down under it.
FrameRenderer::~FrameRenderer() { async_.reset(); }

size_t FrameRenderer::budget() const {
  const double pixels = double(settings_.width) * double(settings_.height);
  return size_t(std::max(1.0, std::round(settings_.sample_budget * pixels)));
}

void FrameRenderer::apply_placement(std::span<const glm::mat4> object_to_world, std::span<const glm::vec3> light_positions) {
  if (!object_to_world.empty() && object_to_world.size() != transforms_.size())
    throw std::invalid_argument("frame renderer: " + std::to_string(object_to_world.size()) + " object transforms for " +
                                std::to_string(transforms_.size()) + " objects");
  if (!light_positions.empty() && light_positions.size() != light_positions_.size())
    throw std::invalid_argument("frame renderer: " + std::to_string(light_positions.size()) + " light positions for " +
                                std::to_string(light_positions_.size()) + " punctual lights");
  std::vector<std::pair<uint32_t, glm::mat4>> moves;
  for (uint32_t o = 0; o < object_to_world.size(); ++o)
    if (object_to_world[o] != transforms_[o]) moves.push_back({o, object_to_world[o]}), transforms_[o] = object_to_world[o];
  std::vector<std::pair<uint32_t, glm::vec3>> light_moves;  // directional lights have no position: ignored
  for (uint32_t l = 0; l < light_positions.size(); ++l)
    if (scene_.punctual_lights[l].type != LightType::directional && light_positions[l] != light_positions_[l])
      light_moves.push_back({l, light_positions[l]}), light_positions_[l] = light_positions[l];
  if (moves.empty() && light_moves.empty()) return;
  // Shots submitted from now on record the new placement; earlier ones keep theirs, and their
  // results are placed with it (the hit was there), so they then move with their object. A moved
  // light makes cached shading stale; it is left to aging (docs/render.md, "Moving lights").
  placement_ = std::make_shared<const PlacementState>(PlacementState{transforms_, light_positions_, uint16_t(placement_->epoch + 1)});
  auto apply = [&rs = ray_scene_, moves = std::move(moves), light_moves = std::move(light_moves)] {
    for (const auto& [o, m] : moves) rs.set_object_transform(o, m);
    for (const auto& [l, p] : light_moves) rs.set_punctual_light_position(l, p);
  };
  if (!async_) {
    apply();
    return;
  }
  // Async: a shot must be traced against the placement it records. Cancel the requests not yet
  // started first, so none of them can be traced after the move; the slice in flight finishes
  // against the old placement (its shot's), and the move runs before any later slice.
  async_->cancel_pending();
  async_->run_between_batches(std::move(apply));
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
      if (finder_ && settings_.shadow_edges)
        for (size_t k = begin; k < end; ++k)
          for (const BlockerTriple& t : batch.triples_of(batch.results[k]))
            if (t.blocker < transforms_.size() && t.receiver < transforms_.size())
              triples_[{t.light, t.blocker, t.receiver}] = frame_;
      part.results.assign(batch.results.begin() + ptrdiff_t(begin), batch.results.begin() + ptrdiff_t(end));
      stats_.samples += cache_.insert(shot->frame, part, shot->placement->objects, shot->placement->epoch);
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
    // Gaps about to open: predicted pixels without points whose ray, at the typical depth of the
    // current points, lies outside the current view (areas the current priority cannot see).
    double depth_sum = 0.0;
    size_t depth_count = 0;
    for (float d : cache_.image().depth)
      if (std::isfinite(d) && d < cache_.background_depth() * 0.5f) depth_sum += d, ++depth_count;
    const float typical_depth = depth_count ? float(depth_sum / double(depth_count)) : 1.0f;
    // The test runs at the centres of 8x8 blocks (the unseen region's border is a smooth curve).
    constexpr int kBlock = 8;
    const int bw = (w + kBlock - 1) / kBlock, bh = (h + kBlock - 1) / kBlock;
    std::vector<uint8_t> unseen(size_t(bw) * size_t(bh), 0);
    tbb::parallel_for(0, bh, [&](int by) {
      for (int bx = 0; bx < bw; ++bx) {
        const float cx = std::min(float(w), float(bx * kBlock) + 0.5f * kBlock);
        const float cy = std::min(float(h), float(by * kBlock) + 0.5f * kBlock);
        const Ray ray = predicted.ray(cx, cy);
        const Projection now = frame.project(ray.origin + ray.direction * typical_depth);
        unseen[size_t(by) * size_t(bw) + size_t(bx)] = !now.in_front() || now.pixel.x < 0.0f || now.pixel.y < 0.0f ||
                                                         now.pixel.x >= float(w) || now.pixel.y >= float(h);
      }
    });
    std::vector<uint8_t> gaps(occupied.size(), 0);
    const size_t gap_count = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, h, 8), size_t(0),
        [&](const tbb::blocked_range<int>& rows, size_t count) {
          for (int y = rows.begin(); y != rows.end(); ++y)
            for (int x = 0; x < w; ++x) {
              const size_t i = size_t(y) * size_t(w) + size_t(x);
              const bool gap = !occupied[i] && unseen[size_t(y / kBlock) * size_t(bw) + size_t(x / kBlock)];
              gaps[i] = gap, count += gap;
            }
          return count;
        },
        std::plus<size_t>());
    const size_t n = std::min(gap_count, size_t(double(main_budget) * double(settings_.predict_share)));
    if (n > 0) {
      NewShot shot{predicted, {}};
      // Evenly spaced over the gaps in scan order (the gaps are uniform in priority).
      std::vector<uint32_t> picked;
      picked.reserve(n);
      size_t seen = 0;
      for (size_t i = 0; i < gaps.size() && picked.size() < n; ++i)
        if (gaps[i] && (seen++ * n) % gap_count < n) picked.push_back(uint32_t(i));
      make_requests(picked, w, settings_.seed, uint64_t(frame_) * 2 + 1, 0, shot.requests);
      main_budget -= picked.size();
      stats_.predicted = picked.size();
      shots.push_back(std::move(shot));
    }
  }
  NewShot shot{frame, {}};
  make_requests(dither_pixels(priority, w, h, main_budget), w, settings_.seed, uint64_t(frame_) * 2, 0, shot.requests);
  shots.insert(shots.begin(), std::move(shot));

  // Async: the shader may get through only a prefix before the next frame cancels the rest, so
  // the requests go in a shuffled order (see render() for the interleaving of the shots).
  if (async_)
    for (size_t k = 0; k < shots.size(); ++k) shuffle_requests(shots[k].requests, settings_.seed, uint64_t(frame_) * 2 + k);
  // Ids, and the record of which view and placement each id was made for.
  for (NewShot& s : shots) {
    for (ShadeRequest& r : s.requests) r.id = next_id_++;
    stats_.requested += s.requests.size();
    shots_.push_back({s.requests.empty() ? next_id_ : s.requests.front().id, uint32_t(s.requests.size()), s.frame, placement_});
  }
  while (shots_.size() > 32) shots_.pop_front();
  return shots;
}

void FrameRenderer::find_and_rasterize_edges(const ViewFrame& frame) {
  // The finder's scene placed as now; area light outlines follow their objects, punctual lights
  // their positions (a moved light fails the finder's same-light test for its pairs only).
  auto t = Clock::now();
  for (size_t l = 0; l < light_positions_.size(); ++l) edge_scene_.punctual_lights[l].position = light_positions_[l];
  for (uint32_t o = 0; o < transforms_.size(); ++o) {
    if (edge_scene_.objects[o].object_to_world == transforms_[o]) continue;
    edge_scene_.objects[o].object_to_world = transforms_[o];
    for (size_t l = 0; l < edge_scene_.area_lights.size(); ++l) {
      if (scene_.area_lights[l].object != o) continue;
      const glm::mat4 move = transforms_[o] * glm::inverse(load_transforms_[o]);
      AreaLight& light = edge_scene_.area_lights[l];
      light.outlines = scene_.area_lights[l].outlines;
      for (auto& loop : light.outlines)
        for (glm::vec3& p : loop) p = glm::vec3(move * glm::vec4(p, 1.0f));
    }
  }
  edges_.clear();
  if (settings_.view_edges) finder_->view_edges(edge_scene_, glm::dvec3(frame.eye()), edges_);
  if (!settings_.sharp_border_edges)
    std::erase_if(edges_, [](const edges::SceneEdge& e) { return e.kind == edges::EdgeKind::sharp || e.kind == edges::EdgeKind::border; });
  if (settings_.shadow_edges && !triples_.empty()) {
    // A triple not reported for longer than a point lives backs no point in the cache any more.
    std::erase_if(triples_, [this](const auto& t) { return frame_ - t.second > cache_.settings().max_age; });
    std::vector<edges::LightBlockerReceiver> triples;
    triples.reserve(triples_.size());
    const size_t punctual = scene_.punctual_lights.size();  // lights past these are area lights
    for (const auto& t : triples_)
      if (settings_.soft_shadow_edges || t.first.light < punctual) triples.push_back(t.first);
    finder_->shadow_edges(edge_scene_, triples, edges_);
  }
  stats_.ms.find_edges = ms_since(t);

  // Projection, clipping, occlusion culling, rasterization.
  t = Clock::now();
  if (settings_.occlusion_culling) filter_depth(cache_.image(), settings_.depth_filter, filtered_depth_);
  else filtered_depth_.clear();
  for (const edges::SceneEdge& e : edges_) {
    const EdgeFate fate = project_edge(frame, e.a, e.b, filtered_depth_, segments_);
    segment_kinds_.resize(segments_.size(), e.kind);
    if (fate == EdgeFate::outside) continue;
    if (fate == EdgeFate::culled) {
      ++stats_.edges.culled;
      continue;
    }
    switch (e.kind) {
      case edges::EdgeKind::silhouette: ++stats_.edges.silhouette; break;
      case edges::EdgeKind::sharp: ++stats_.edges.sharp; break;
      case edges::EdgeKind::border: ++stats_.edges.border; break;
      default: ++stats_.edges.shadow; break;
    }
  }
  rasterize_edges(masks_, segments_);
  stats_.ms.rasterize_edges = ms_since(t);
}

const RgbImage& FrameRenderer::render(const Camera& camera, std::span<const glm::mat4> object_to_world,
                                      std::span<const glm::vec3> light_positions) {
  const auto start = Clock::now();
  stats_ = {};
  apply_placement(object_to_world, light_positions);
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
  // Epi mode: the depth cull waits for the edges (it must spare the far side of silhouettes), and
  // the edge-aware occlusion test follows it (docs/render.md, "Hidden points").
  const bool edge_aware = settings_.mode == RenderMode::epi && settings_.occlusion_test && finder_ && settings_.view_edges;
  stats_.points = cache_.project(frame, transforms_, !edge_aware);
  stats_.ms.points = ms_since(t) - sampling_ms - stats_.ms.shade;

  // Edges (epi mode), then the points they show hidden.
  if (settings_.mode == RenderMode::epi) {
    masks_.clear();
    segments_.clear();
    segment_kinds_.clear();
    if (finder_) find_and_rasterize_edges(frame);
  }
  t = Clock::now();
  if (settings_.mode == RenderMode::epi) {
    mark_edge_pixels(segments_, segment_kinds_, settings_.width, settings_.height, edge_pixels_);
    if (edge_aware) {
      stats_.points.culled = cache_.depth_cull(edge_pixels_);
      crossings_.build(segments_, segment_kinds_, settings_.width, settings_.height);
      stats_.points.occluded = cache_.cull_behind_surfaces(frame, transforms_, crossings_);
      stats_.points.drawn -= stats_.points.culled + stats_.points.occluded;
    }
    // A pixel an edge crosses keeps one side's sample: averaging results from both sides there
    // would blend what anti-aliasing blends again.
    cache_.set_refine_mask(edge_pixels_);
  }
  cache_.fill_epi(epi_);
  stats_.ms.points += ms_since(t);

  // Reconstruction.
  ReconstructSettings rs;
  rs.filter = settings_.mode == RenderMode::epi ? Filter::epi : Filter::rendercache;
  rs.antialias = settings_.antialias;
  rs.complex_filter = settings_.complex_filter;
  ReconstructTimes rt;
  if (settings_.stage_timings) {
    reconstructor_.staged(epi_, masks_, rs, reconstruction_, rt);
  } else {
    const auto tr = Clock::now();
    reconstructor_.tiled(epi_, masks_, rs, Schedule{}, reconstruction_);
    rt[Stage::interpolate] = ms_since(tr);
  }
  stats_.ms.classify = rt.reported(Stage::classify), stats_.ms.reachability = rt.reported(Stage::reachability);
  stats_.ms.interpolate = rt.reported(Stage::interpolate), stats_.ms.antialias = rt.reported(Stage::antialias);
  stats_.ms.complex = rt.reported(Stage::complex);
  stats_.pixels = reconstruction_.counts;

  // Epi mode: pixels that reached no sample (black, top priority) filled from their own region.
  if (settings_.mode == RenderMode::epi && settings_.fill_holes) {
    const auto tf = Clock::now();
    const size_t n = reconstruction_.priority.size();
    holes_.assign(n, 0);
    barrier_.assign(n, 0);
    const float* rgb = reconstruction_.image.pixels.data();
    for (size_t i = 0; i < n; ++i) {
      holes_[i] = reconstruction_.priority[i] >= kMaxPriority && rgb[3 * i] == 0.0f && rgb[3 * i + 1] == 0.0f && rgb[3 * i + 2] == 0.0f;
      barrier_[i] = (edge_pixels_[i] & (kDepthEdge | kSharpEdge)) != 0;
    }
    stats_.holes_filled = fill_holes(reconstruction_.image, holes_, barrier_);
    stats_.ms.interpolate += ms_since(tf);
  }

  // Async: the next requests from this frame's priority; stale ones are dropped.
  if (async_) {
    const auto ts = Clock::now();
    std::vector<NewShot> shots = choose_requests(frame, reconstruction_.priority);
    async_->cancel_pending();
    // Main and predicted requests interleaved in proportion, in rounds of a quarter slice.
    std::vector<size_t> sizes;
    for (const NewShot& s : shots) sizes.push_back(s.requests.size());
    for (const SubmissionPart& part : interleave_shots(sizes, 256)) {
      const std::vector<ShadeRequest>& requests = shots[part.shot].requests;
      async_->submit(shots[part.shot].frame.view(), {requests.begin() + ptrdiff_t(part.begin), requests.begin() + ptrdiff_t(part.end)});
    }
    sampling_ms += ms_since(ts);
  }
  stats_.ms.sampling = sampling_ms;
  if (stats_.samples > 0) stats_.sparseness = double(settings_.width) * double(settings_.height) / double(stats_.samples);
  previous_camera_ = std::make_unique<Camera>(camera);
  ++frame_;
  stats_.ms.total = ms_since(start);
  return reconstruction_.image;
}

}  // namespace epi::render

#include "render/renderer.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

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

}  // namespace

std::optional<edges::SceneEdgeSettings> FrameRenderer::edge_finder_settings(const FrameSettings& settings) {
  if (settings.mode != RenderMode::epi || !(settings.view_edges || settings.shadow_edges)) return std::nullopt;
  edges::SceneEdgeSettings edge_settings = settings.edge_finder;
  edge_settings.receiver_trees = settings.shadow_edges;  // model only what the settings use
  return edge_settings;
}

FrameRenderer::FrameRenderer(const Scene& scene, RayScene& ray_scene, const Shader& shader, const FrameSettings& settings,
                             std::shared_ptr<edges::SceneEdgeFinder> edge_finder)
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
  // Punctual highlights recomputed for each frame's eye (epi mode; docs/render.md, "Punctual highlights").
  if (settings.mode == RenderMode::epi && shader.settings().specular && !ray_scene.punctual_lights().empty() &&
      settings.cache.punctual_highlights())
    cache_.set_highlight_model(shader.punctual_specular_model());
  if (const auto edge_settings = edge_finder_settings(settings)) {
    if (edge_finder && !(edge_finder->settings() == *edge_settings))
      throw std::invalid_argument("frame renderer: the edge finder given was built with other settings");
    finder_ = edge_finder ? std::move(edge_finder) : std::make_shared<edges::SceneEdgeFinder>(scene, *edge_settings);
    edge_scene_.source = scene.source;
    edge_scene_.objects = scene.objects;
    edge_scene_.punctual_lights = scene.punctual_lights;
    edge_scene_.area_lights = scene.area_lights;
    for (const Object& o : scene.objects) load_transforms_.push_back(o.object_to_world);
  }
  if (!settings.sync) {
    cores_ = std::max(1, tbb::this_task_arena::max_concurrency());
    shader_threads_ = settings.shader_threads > 0                  ? settings.shader_threads
                      : settings.core_split == CoreSplit::adaptive ? std::max(1, cores_ - 1)
                                                                   : 0;  // 0: all cores
    async_ = std::make_unique<AsyncShader>(shader, shader_threads_, 1024, settings.before_shading_slice);
    if (settings.core_split == CoreSplit::adaptive)
      loop_arena_ = std::make_unique<tbb::task_arena>(std::max(1, cores_ - std::max(1, shader_threads_)));
  }
}

// The shader thread stops first: nothing it may still touch is torn down under it.
FrameRenderer::~FrameRenderer() { async_.reset(); }

size_t FrameRenderer::budget() const {
  const double pixels = double(settings_.width) * double(settings_.height);
  return size_t(std::max(1.0, std::round(settings_.sample_budget * budget_scale_ * pixels)));
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
      light_moves.push_back({l, light_positions[l]}), light_positions_[l] = light_positions[l], cache_.move_highlight_light(l, light_positions[l]);
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
  // Async: a shot must be traced against the placement it records. The move runs on the shading
  // thread before any request not yet started (the slice in flight finishes against the old
  // placement), so each shot's record is split where its first such request is: the part before
  // keeps the old placement, the rest records the new one. (Those requests used to be
  // cancelled: with an object or a light moving every frame, requests then lived only from a
  // frame's end to the next frame's start, and the shader starved; docs/render.md, "The
  // loop", "Moving objects".)
  const std::vector<uint32_t> unstarted = async_->run_between_batches(std::move(apply));
  for (size_t k = 0; k < shots_.size(); ++k) {
    Shot& shot = shots_[k];
    uint32_t started = shot.count;  // the shot's requests before its first not yet started
    for (const uint32_t id : unstarted)  // offsets from first_id, as integrate() matches ids (ids wrap)
      if (id - shot.first_id < shot.count) started = std::min(started, id - shot.first_id);
    if (started == shot.count) continue;
    Shot rest = shot;
    rest.first_id = shot.first_id + started, rest.count = shot.count - started, rest.placement = placement_;
    shot.count = started;
    if (shot.count == 0) shot = rest;
    else shots_.insert(shots_.begin() + ptrdiff_t(++k), rest);
  }
}

void FrameRenderer::integrate(const ShadeBatch& batch) {
  // Results come in submission order; each run of ids belongs to one shot.
  size_t begin = 0, lagged = 0;
  double lag = 0.0;
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
      lag += double(frame_ - shot->chosen) * double(end - begin), lagged += end - begin;
    }
    begin = end;
  }
  if (lagged > 0) result_lag_ = lag / double(lagged);
  stats_.result_lag = result_lag_;
}

std::vector<FrameRenderer::NewShot> FrameRenderer::choose_requests(const ViewFrame& frame, std::span<const float> priority,
                                                                  int index) {
  std::vector<NewShot> shots;
  const int w = settings_.width, h = settings_.height;
  size_t main_budget = budget();

  // Predictive sampling: the gaps of the view a few frames ahead, when the camera moves.
  const Camera& camera = frame.view().camera;
  if (previous_camera_ && !same_camera(*previous_camera_, camera) && settings_.predict_share > 0.0f) {
    const Camera ahead = extrapolate_camera(*previous_camera_, camera, settings_.predict_frames);
    const ViewFrame predicted(make_view(ahead, w, h));
    // Gaps about to open: predicted pixels without points whose ray, at the typical depth of the
    // current points, lies outside the current view (areas the current priority cannot see).
    // The typical depth: the mean over fixed bands of rows, summed in band order (the same for
    // any thread count; a serial sum in pixel order rounds differently in the last bits).
    const std::vector<float>& depths = cache_.image().depth;
    constexpr int kDepthRows = 32;
    const int depth_bands = (h + kDepthRows - 1) / kDepthRows;
    depth_sums_.resize(size_t(depth_bands));
    tbb::parallel_for(0, depth_bands, [&](int b) {
      double sum = 0.0;
      size_t count = 0;
      const float far = cache_.background_depth() * 0.5f;
      // No branch: drawn and empty pixels alternate at random. An empty or far pixel adds +0 (its
      // bits masked off), which changes no sum (GCC turns a `? :` here back into a branch).
      for (size_t i = size_t(b) * kDepthRows * size_t(w), end = std::min(depths.size(), i + kDepthRows * size_t(w)); i < end; ++i) {
        const bool near = int(std::isfinite(depths[i])) & int(depths[i] < far);
        sum += double(std::bit_cast<float>(std::bit_cast<uint32_t>(depths[i]) & (0u - uint32_t(near))));
        count += near;
      }
      depth_sums_[size_t(b)] = {sum, count};
    });
    double depth_sum = 0.0;
    size_t depth_count = 0;
    for (const auto& [sum, count] : depth_sums_) depth_sum += sum, depth_count += count;
    const float typical_depth = depth_count ? float(depth_sum / double(depth_count)) : 1.0f;
    // The test runs at the centres of 8x8 blocks (the unseen region's border is a smooth curve).
    constexpr int kBlock = 8;
    const int bw = (w + kBlock - 1) / kBlock, bh = (h + kBlock - 1) / kBlock;
    unseen_.resize(size_t(bw) * size_t(bh));
    tbb::parallel_for(0, bh, [&](int by) {
      for (int bx = 0; bx < bw; ++bx) {
        const float cx = std::min(float(w), float(bx * kBlock) + 0.5f * kBlock);
        const float cy = std::min(float(h), float(by * kBlock) + 0.5f * kBlock);
        const Ray ray = predicted.ray(cx, cy);
        const Projection now = frame.project(ray.origin + ray.direction * typical_depth);
        unseen_[size_t(by) * size_t(bw) + size_t(bx)] = !now.in_front() || now.pixel.x < 0.0f || now.pixel.y < 0.0f ||
                                                          now.pixel.x >= float(w) || now.pixel.y >= float(h);
      }
    });
    // A gap needs an unseen block: with none (the camera moves forward, or barely), the predicted
    // occupancy cannot matter and is not computed.
    if (std::find(unseen_.begin(), unseen_.end(), uint8_t(1)) != unseen_.end())
      predicted_occupancy(cache_, predicted, transforms_, settings_.predict_stride, index % std::max(1, settings_.predict_stride),
                          settings_.predict_splat, occupied_);
    else
      occupied_.resize(size_t(w) * size_t(h));
    std::vector<uint8_t>& gaps = occupied_;  // each pixel read, then overwritten by its gap flag
    gap_rows_.resize(size_t(h) + 1);  // gap_rows_[y]: gaps in the rows above y
    gap_rows_[0] = 0;
    tbb::parallel_for(0, h, [&](int y) {
      size_t count = 0;
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        const bool gap = int(gaps[i] == 0) & int(unseen_[size_t(y / kBlock) * size_t(bw) + size_t(x / kBlock)] != 0);
        gaps[i] = gap, count += gap;
      }
      gap_rows_[size_t(y) + 1] = count;
    });
    for (int y = 0; y < h; ++y) gap_rows_[size_t(y) + 1] += gap_rows_[size_t(y)];
    const size_t gap_count = gap_rows_[size_t(h)];
    const size_t n = std::min(gap_count, size_t(double(main_budget) * double(settings_.predict_share)));
    if (n > 0) {
      NewShot shot{predicted, {}};
      // Evenly spaced over the gaps in scan order (the gaps are uniform in priority): the gap of
      // ordinal k is picked when (k n) mod G < n, i.e. k = ceil(j G / n) for j < n; so the picks
      // before ordinal k number floor((k - 1) n / G) + 1 (none for k = 0), and each row writes
      // its own picks in place, rows in parallel.
      std::vector<uint32_t>& picked = picked_;
      picked.resize(n);
      tbb::parallel_for(0, h, [&](int y) {
        size_t k = gap_rows_[size_t(y)];
        if (k == gap_rows_[size_t(y) + 1]) return;
        size_t at = k == 0 ? 0 : (k - 1) * n / gap_count + 1;
        for (int x = 0; x < w; ++x) {
          const size_t i = size_t(y) * size_t(w) + size_t(x);
          if (!gaps[i]) continue;
          if ((k * n) % gap_count < n && at < n) picked[at++] = uint32_t(i);
          ++k;
        }
      });
      make_requests(picked, w, settings_.seed, uint64_t(index) * 2 + 1, 0, shot.requests);
      main_budget -= picked.size();
      stats_.predicted = picked.size();
      shots.push_back(std::move(shot));
    }
  }
  // Traced through the camera where the results will be drawn (FrameSettings::trace_ahead): a
  // ray from the eye that chose it finds what that eye saw, which the view it is drawn in may
  // already see hidden (docs/render.md, "Requests traced ahead").
  NewShot shot{frame, {}};
  if (settings_.trace_ahead && result_lag_ > 0.0 && previous_camera_ && !same_camera(*previous_camera_, camera))
    shot.frame = ViewFrame(make_view(extrapolate_camera(*previous_camera_, camera, float(result_lag_)), w, h));
  make_requests(dither_pixels(priority, w, h, main_budget), w, settings_.seed, uint64_t(index) * 2, 0, shot.requests);
  stats_.most_effort = settings_.mode == RenderMode::epi && frame_ > 0 && shader_.effort_matters()
                           ? (async_ ? effort_most_ : settings_.sparse_effort)
                           : 1;
  set_sparse_effort(shot.requests, epi_, settings_.sparse.dense, stats_.most_effort, effort_counts_);
  shots.insert(shots.begin(), std::move(shot));
  // Triples only for the edges this renderer draws (docs/render.md, "Triples only where used").
  const Blockers blockers = settings_.mode != RenderMode::epi || !settings_.shadow_edges ? Blockers::none
                            : settings_.soft_shadow_edges                                  ? Blockers::all
                                                                                           : Blockers::punctual;
  for (NewShot& s : shots)
    for (ShadeRequest& r : s.requests) r.blockers = blockers;

  // Async: the shader may get through only a prefix before the next frame cancels the rest, so
  // the requests go in a shuffled order (see render() for the interleaving of the shots).
  if (async_)
    for (size_t k = 0; k < shots.size(); ++k) shuffle_requests(shots[k].requests, settings_.seed, uint64_t(index) * 2 + k);
  // Ids, and the record of which view and placement each id was made for.
  for (NewShot& s : shots) {
    for (ShadeRequest& r : s.requests) r.id = next_id_++, stats_.effort += std::max<uint8_t>(r.effort, 1);
    stats_.requested += s.requests.size();
    shots_.push_back({s.requests.empty() ? next_id_ : s.requests.front().id, uint32_t(s.requests.size()), frame_, s.frame,
                      placement_});
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
  stats_.ms[FrameStage::find_edges] = ms_since(t);

  // Projection, clipping, occlusion culling, rasterization.
  t = Clock::now();
  if (settings_.occlusion_culling) filter_depth(cache_.image(), settings_.depth_filter, filtered_depth_);
  else filtered_depth_.clear();
  project_edges(frame, edges_, filtered_depth_, segments_, piece_edge_, piece_inv_depth_, edge_fates_, edge_scratch_);
  segment_kinds_.resize(segments_.size());
  for (size_t k = 0; k < segments_.size(); ++k) segment_kinds_[k] = edges_[piece_edge_[k]].kind;
  for (size_t k = 0; k < edges_.size(); ++k) {
    if (edge_fates_[k] == EdgeFate::outside) continue;
    if (edge_fates_[k] == EdgeFate::culled) {
      ++stats_.edges.culled;
      continue;
    }
    switch (edges_[k].kind) {
      case edges::EdgeKind::silhouette: ++stats_.edges.silhouette; break;
      case edges::EdgeKind::sharp: ++stats_.edges.sharp; break;
      case edges::EdgeKind::border: ++stats_.edges.border; break;
      default: ++stats_.edges.shadow; break;
    }
  }
  // Bands of rows in parallel, bit for bit the serial rasterizer's masks (core/epi tests it).
  rasterize_edges_parallel(masks_, segments_, 64, tbb::this_task_arena::max_concurrency());
  stats_.ms[FrameStage::rasterize_edges] = ms_since(t);
}

const RgbImage& FrameRenderer::render(const Camera& camera, std::span<const glm::mat4> object_to_world,
                                      std::span<const glm::vec3> light_positions) {
  // Adaptive core split: while the shader is behind (the last frame's requests not all shaded
  // when that frame chose the next ones), the loop keeps to its own cores and leaves the rest to
  // shading; while it keeps up, the loop takes every core (the shader idles part of the frame).
  if (loop_arena_ && shader_behind_) {
    const RgbImage* image = nullptr;
    loop_arena_->execute([&] { image = &render_frame(camera, object_to_world, light_positions); });
    return *image;
  }
  return render_frame(camera, object_to_world, light_positions);
}

const RgbImage& FrameRenderer::render_frame(const Camera& camera, std::span<const glm::mat4> object_to_world,
                                            std::span<const glm::vec3> light_positions) {
  const auto start = Clock::now();
  stats_ = {};
  stats_.loop_threads = tbb::this_task_arena::max_concurrency();
  auto t = Clock::now();
  ShadeBatch batch;
  double sampling_ms = 0.0;
  const bool as_async = !async_ && settings_.sync_as_async;
  // sync_as_async: the requests the last frame chose for its own view are shaded now, before this
  // frame's placement (they are traced with the placement their shot records).
  if (as_async && !sync_shots_.empty()) {
    const auto tsh = Clock::now();
    for (const NewShot& s : sync_shots_) shader_.shade(s.frame, s.requests, batch);
    stats_.ms[FrameStage::shade] = ms_since(tsh);
    sync_shots_.clear();
  }
  const uint16_t epoch_before = placement_->epoch;
  apply_placement(object_to_world, light_positions);
  const bool at_rest = previous_camera_ && same_camera(*previous_camera_, camera) && placement_->epoch == epoch_before;
  const ViewFrame frame(make_view(camera, settings_.width, settings_.height));

  // New shading results into the cache.
  if (!async_ && (!as_async || frame_ == 0)) {
    // Sync: this frame's budget, chosen from the last priority image (uniform at first), shaded
    // now through this frame's view (sync_as_async: the first frame only).
    const auto ts = Clock::now();
    std::vector<NewShot> shots = choose_requests(frame, reconstruction_.priority, frame_);
    sampling_ms += ms_since(ts);
    const auto tsh = Clock::now();
    for (const NewShot& s : shots) shader_.shade(s.frame, s.requests, batch);
    stats_.ms[FrameStage::shade] += ms_since(tsh);
  } else if (async_) {
    async_->take_results(batch);
  }
  const auto ti = Clock::now();
  integrate(batch);
  stats_.integrate_ms = ms_since(ti);
  // Epi mode: the depth cull waits for the edges (it must spare the far side of silhouettes), and
  // the edge-aware occlusion test follows it (docs/render.md, "Hidden points").
  const bool edge_aware = settings_.mode == RenderMode::epi && settings_.occlusion_test && finder_ && settings_.view_edges;
  stats_.points = cache_.project(frame, transforms_, !edge_aware);
  stats_.ms[FrameStage::points] = ms_since(t) - sampling_ms - stats_.ms[FrameStage::shade];

  // Edges (epi mode), then the points they show hidden.
  if (settings_.mode == RenderMode::epi) {
    masks_.clear();
    segments_.clear();
    segment_kinds_.clear();
    piece_edge_.clear();
    piece_inv_depth_.clear();
    if (finder_) find_and_rasterize_edges(frame);
  }
  t = Clock::now();
  if (settings_.mode == RenderMode::epi) {
    mark_edge_pixels(segments_, segment_kinds_, settings_.width, settings_.height, edge_pixels_);
    if (edge_aware) {
      stats_.points.culled = cache_.depth_cull(edge_pixels_);
      crossings_.build(segments_, segment_kinds_, settings_.width, settings_.height, piece_inv_depth_);
      stats_.points.occluded = cache_.cull_behind_surfaces(frame, transforms_, crossings_);
      stats_.points.drawn -= stats_.points.culled + stats_.points.occluded;
    }
    // A pixel an edge crosses keeps one side's sample: averaging results from both sides there
    // would blend what anti-aliasing blends again.
    cache_.set_refine_mask(edge_pixels_);
  }
  cache_.fill_epi(epi_);
  stats_.ms[FrameStage::points] += ms_since(t);

  // Reconstruction.
  const ReconstructSettings rs = reconstruct_settings();
  ReconstructTimes rt;
  if (settings_.stage_timings) {
    Schedule schedule;
    schedule.threads = stats_.loop_threads;
    reconstructor_.staged(epi_, masks_, rs, reconstruction_, rt, schedule);
  } else {
    const auto tr = Clock::now();
    Schedule schedule;
    schedule.threads = stats_.loop_threads;  // the reconstructor's own arena, as wide as the loop's
    reconstructor_.tiled(epi_, masks_, rs, schedule, reconstruction_);
    rt[Stage::interpolate] = ms_since(tr);
  }
  for (const StageInfo& i : kStages)
    if (is_reported(i.stage)) stats_.ms[frame_stage(i.stage)] = rt.reported(i.stage);
  stats_.pixels = reconstruction_.counts;

  // Epi mode: sparse regions smoothed (sparse_blend.h).
  if (settings_.mode == RenderMode::epi && settings_.sparse_blend) {
    const auto tb = Clock::now();
    stats_.sparse_blended = sparse_blend(reconstruction_.image, epi_, edge_pixels_, settings_.sparse, sparse_scratch_);
    stats_.ms[FrameStage::sparse_blend] = ms_since(tb);
  }
  // Epi mode: pixels that reached no sample (black, top priority) filled from their own region.
  if (settings_.mode == RenderMode::epi && settings_.fill_holes) {
    const auto tf = Clock::now();
    list_holes(reconstruction_.image, reconstruction_.priority, edge_pixels_, kDepthEdge | kSharpEdge, barrier_, hole_scratch_);
    // No hole (the usual frame at rest): nothing to fill.
    stats_.holes_filled = hole_scratch_.holes.empty() ? 0 : fill_listed_holes(reconstruction_.image, barrier_, hole_scratch_);
    stats_.ms[FrameStage::interpolate] += ms_since(tf);
  }

  // Async: the next requests from this frame's priority; stale ones are dropped.
  if (async_) {
    const auto ts = Clock::now();
    shader_behind_ = async_->pending_requests() > 0;  // before the last requests are dropped
    // The budget follows what the shader finishes in a frame, as long as integrating the results
    // stays a small share of the frame; in motion only while frames are as fast as a display's
    // (FrameSettings::rest_sample_budget, motion_sample_budget).
    const double frame_ms = ms_since(start);
    const double cap = settings_.sample_budget > 0.0
                           ? std::max(1.0, (at_rest ? settings_.rest_sample_budget : settings_.motion_sample_budget) / settings_.sample_budget)
                           : 1.0;
    const bool grow = !shader_behind_ && stats_.integrate_ms < settings_.grow_integrate_share * frame_ms;
    const double scale = std::min(cap, budget_scale_);
    budget_scale_ = !at_rest && frame_ms > settings_.motion_frame_ms ? 1.0 : grow ? std::min(cap, scale * 1.5) : std::max(1.0, scale / 1.5);
    // Effort only from the shader's spare time: a shader that is behind would finish fewer requests.
    effort_most_ = shader_behind_ ? std::max(1, effort_most_ / 2) : std::min(settings_.sparse_effort, effort_most_ + 1);
    std::vector<NewShot> shots = choose_requests(frame, reconstruction_.priority, frame_);
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
  // sync_as_async: the next frame's requests, from this frame's priority and for this frame's
  // view (the next frame shades them first; their jitter is keyed by the frame that shades them).
  if (as_async) {
    const auto ts = Clock::now();
    stats_.requested = stats_.predicted = stats_.effort = 0;  // the requests chosen this frame: those for the next
    sync_shots_ = choose_requests(frame, reconstruction_.priority, frame_ + 1);
    sampling_ms += ms_since(ts);
  }
  stats_.ms[FrameStage::sampling] = sampling_ms;
  if (stats_.samples > 0) stats_.sparseness = double(settings_.width) * double(settings_.height) / double(stats_.samples);
  previous_camera_ = std::make_unique<Camera>(camera);
  ++frame_;
  stats_.ms.total = ms_since(start);
  return reconstruction_.image;
}

ReconstructSettings FrameRenderer::reconstruct_settings() const {
  ReconstructSettings rs;
  rs.filter = settings_.mode == RenderMode::epi ? Filter::epi : Filter::rendercache;
  rs.antialias = settings_.antialias;
  rs.complex_filter = settings_.complex_filter;
  // Edge-free pixels that reach no sample are left black where the hole fill fills them from
  // their own region: the reconstruction's blend across a nearby edge painted the near side's
  // colour into the background a disocclusion uncovered (docs/render.md, "Holes").
  rs.blend_unreached_near_edges = !settings_.fill_holes;
  return rs;
}

}  // namespace epi::render

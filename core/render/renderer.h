// The frame loop of the edge-and-point renderer and of the render cache (docs/render.md):
// every frame, shading results that have arrived are cached as points, the cloud is reprojected,
// the EPI filters (or the render cache's) reconstruct the image, and the priority image decides
// where the shader works next. The shader runs on its own threads (AsyncShader): a frame never
// waits for it. In sync mode each frame shades exactly its budget first (tests, comparisons).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <tbb/task_arena.h>

#include "edges/scene_edges.h"
#include "epi/reconstruct.h"
#include "render/edge_projection.h"
#include "render/frame_stages.h"
#include "render/hole_fill.h"
#include "render/sparse_blend.h"
#include "render/point_cache.h"
#include "shade/async_shader.h"
#include "shade/shader.h"

namespace epi::render {

enum class RenderMode { epi, rendercache };
enum class CoreSplit { adaptive, shared };

struct FrameSettings {
  RenderMode mode = RenderMode::epi;
  int width = 512, height = 512;
  double sample_budget = 0.02;  // fraction of the pixels requested per frame
  // Asynchronous loop at rest (camera, objects and lights as in the last frame): the budget grows
  // 1.5x a frame while the shader finishes every request before the next frame chooses (it idles
  // otherwise) and integrating the results takes less than grow_integrate_share of the frame (the
  // loop stays responsive for the next move), up to this fraction; it shrinks 1.5x a frame
  // otherwise (docs/render.md, "Idle shading at rest"). At most sample_budget: off. Sync mode
  // shades sample_budget exactly.
  double rest_sample_budget = 0.08;
  // In motion the same, up to motion_sample_budget, while a frame takes at most motion_frame_ms (a
  // display's frame: the shader's idle time goes into frames the user sees, not into frames faster
  // than a display shows); a slower frame starts again from sample_budget at once (docs/render.md,
  // "Idle shading in motion"). At most sample_budget: off.
  double motion_sample_budget = 0.08;
  double motion_frame_ms = 1000.0 / 60.0;
  double grow_integrate_share = 0.25;
  bool sync = false;            // shade the budget inside each frame (deterministic for a seed)
  // With sync: the requests a frame chooses are made for its own view and shaded at the start of
  // the next frame, with the placement they were made for (the asynchronous loop's order when the
  // shader keeps up), instead of being chosen and shaded through the new frame's view. A
  // deterministic stand-in for what the viewer shows (docs/render.md, "Sparse near surfaces",
  // "Requests traced ahead").
  bool sync_as_async = false;
  // A frame's requests are traced through its camera extrapolated to the frame their results will
  // be drawn in: by the lag, in frames, of the results the last frame integrated (0 in sync mode,
  // 1 with sync_as_async, measured in the asynchronous loop). false: through the camera that chose
  // them (docs/render.md, "Requests traced ahead").
  bool trace_ahead = true;
  uint64_t seed = 1;            // request jitter (the shader has its own seed)
  bool antialias = true, complex_filter = true;  // epi mode
  // true: the filters run stage by stage (each timed; epi::Reconstructor::staged); false: the
  // fused, tiled row stream (same image, faster; its time is reported under interpolate).
  bool stage_timings = true;
  PointCacheSettings cache;
  // At most this share of the budget goes to predicted gaps. Off by default: along the bundled
  // paths, at 1, 1/4 and 1/10 of their pace, the whole budget on the priority image measured as
  // good or better on every scene (render.md, "Sampling"); 0.25 was the default until 2026-11-27.
  float predict_share = 0.0f;
  float predict_frames = 4.0f;  // how far ahead the camera is extrapolated
  int predict_stride = 8;       // predictive projection uses 1/stride of the points ...
  int predict_splat = 5;        // ... as splat x splat squares (8 and 5: the same quality as 2 and 3
                                // along the paths at about half the cost; render.md, "Sampling")
  // How the asynchronous shader and the frame loop share the cores (docs/render.md, "Cores").
  // adaptive: the shader gets shader_threads (0: all cores but one, at least one) and the loop
  // one core while the shader is behind (the last frame's requests not all shaded when that
  // frame ended), all cores while it keeps up; shared: both use all cores, the OS splits them.
  CoreSplit core_split = CoreSplit::adaptive;
  int shader_threads = 0;       // AsyncShader concurrency (0: as core_split says)
  // epi mode: which edges go into the EPI, and their occlusion culling.
  bool view_edges = true;       // silhouette, sharp, border
  bool sharp_border_edges = true;  // with view_edges: false keeps silhouettes only (the study's edge-kind knob)
  edges::SceneEdgeSettings edge_finder;  // tree vs brute force per mesh (force: 0 cost model, 1 tree, -1 brute force)
  KernelChoice kernels;         // the reconstruction's row kernels (oracle, or a SIMD target; 0: the best here)
  bool shadow_edges = true;     // from the light-blocker-receiver triples the shader reports
  // Umbral and penumbral edges of area lights (the paper's soft-shadow edges). Off by default:
  // cutting interpolation at a penumbra a few pixels wide costs more than it gains (docs/render.md,
  // "Soft-shadow edges"); hard shadow edges of punctual lights are kept either way.
  bool soft_shadow_edges = false;
  bool fill_holes = true;       // epi mode: pixels that reach no sample get their region's nearest colours (hole_fill.h)
  bool sparse_blend = true;     // epi mode: sparse regions smoothed (sparse_blend.h)
  // epi mode: a request where the EPI's samples are sparse takes up to this many times the shader's
  // sample counts (set_sparse_effort, sampling.h; docs/render.md, "Effort where samples are
  // sparse"); 1: off. In the asynchronous loop only while the shader keeps up: the most effort
  // halves after a frame whose requests the shader did not finish and grows by 1 after one it did.
  // Off by default: rooms' frames along its path 0.89x the error, the others' the same, but on two
  // cores the shader's extra work slows the loop (0.81-0.95x the frame rate).
  int sparse_effort = 1;
  SparseBlendSettings sparse;
  bool occlusion_culling = true;
  // Points behind the tangent plane of a nearer point with no geometric edge between them are not
  // drawn (PointCache::cull_behind_surfaces; needs view_edges).
  bool occlusion_test = true;
  DepthFilterSettings depth_filter;
  // Tests only: runs on the shading thread before each slice of async work (see AsyncShader).
  std::function<void()> before_shading_slice;
};

struct EdgeCounts {
  int64_t silhouette = 0, sharp = 0, border = 0, shadow = 0, culled = 0;
};

struct FrameStats {
  StageTimes ms;
  ClassCounts pixels;
  EdgeCounts edges;
  ProjectionCounts points;
  size_t samples = 0;    // shading results integrated into the cache this frame
  size_t requested = 0;  // requests made this frame (incl. predicted)
  size_t predicted = 0;  // of which for predicted gaps
  size_t effort = 0;     // the requests' summed effort (ShadeRequest::effort; requested when all are 1)
  int most_effort = 1;   // the most effort a request could take this frame (FrameSettings::sparse_effort)
  size_t holes_filled = 0;  // pixels that reached no sample, filled by fill_holes
  size_t sparse_blended = 0;  // pixels blended towards the smooth interpolation (sparse_blend.h)
  int loop_threads = 0;     // the frame loop's concurrency this frame (FrameSettings::core_split)
  double integrate_ms = 0.0;  // of ms.points: integrating the new results into the cache (PointCache::insert)
  // Frames from a request's choice to its result's integration, mean over this frame's results
  // (the last frame's value when none came); what FrameSettings::trace_ahead extrapolates by.
  double result_lag = 0.0;
  // Pixels per new sample this frame; +infinity when no sample was integrated (not 0: 0 would
  // read as "densest possible").
  double sparseness = std::numeric_limits<double>::infinity();
};

class FrameRenderer {
 public:
  // ray_scene must be the one `shader` traces; moving objects updates it. All three outlive this.
  // `edge_finder`, when given, must have been built from `scene` with edge_finder_settings(settings)
  // (std::invalid_argument otherwise): a renderer rebuilt for other settings (the viewer's window
  // size, budget, ...) reuses the edge trees instead of building them again.
  FrameRenderer(const Scene& scene, RayScene& ray_scene, const Shader& shader, const FrameSettings& settings,
                std::shared_ptr<edges::SceneEdgeFinder> edge_finder = nullptr);
  // The edge finder settings a renderer with these settings builds its finder with; none when it
  // needs no finder (not epi mode, or neither view nor shadow edges).
  static std::optional<edges::SceneEdgeSettings> edge_finder_settings(const FrameSettings& settings);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // Renders the next frame from `camera` with objects placed by object_to_world (one per scene
  // object; empty: as the scene places them) and punctual lights at light_positions (world space,
  // one per Scene::punctual_lights entry, directional lights' entries ignored; empty: as the
  // scene places them). Returns the image, valid until the next call.
  const RgbImage& render(const Camera& camera, std::span<const glm::mat4> object_to_world = {},
                         std::span<const glm::vec3> light_positions = {});

  const FrameStats& stats() const { return stats_; }
  const PointCache& cache() const { return cache_; }
  const std::vector<float>& priority() const { return reconstruction_.priority; }
  const EpiImage& epi() const { return epi_; }  // this frame's EPI as filled: the reconstruction's input
  // The same EPI classified by the reconstruction (reconstruct.h): edge words with their codes and
  // usable bits, cache words with the type and reach mask; one per pixel.
  const std::vector<uint16_t>& classified_edge() const { return reconstruction_.edge; }
  const std::vector<uint32_t>& classified_cache() const { return reconstruction_.cache; }
  const FrameSettings& settings() const { return settings_; }
  // The settings this renderer reconstructs its EPI with (what an EPI snapshot must carry).
  ReconstructSettings reconstruct_settings() const;
  const std::vector<Segment>& segments() const { return segments_; }  // this frame's visible edge pieces
  const std::vector<glm::dvec2>& piece_inv_depths() const { return piece_inv_depth_; }  // 1/depth at each piece's ends
  const BoundaryMasks& masks() const { return masks_; }       // and its boundary masks (EPI snapshots)
  const std::vector<edges::EdgeKind>& segment_kinds() const { return segment_kinds_; }  // one per piece
  const std::vector<float>& filtered_depth() const { return filtered_depth_; }
  const std::vector<uint8_t>& edge_pixels() const { return edge_pixels_; }  // epi mode: this frame's, by kind (point_cache.h)
  const std::vector<edges::SceneEdge>& scene_edges() const { return edges_; }  // this frame's, world space
  const edges::SceneEdgeFinder* edge_finder() const { return finder_.get(); }
  double edge_finder_build_ms() const { return finder_ ? finder_->build_ms() : 0.0; }
  const char* kernel_name() const { return reconstructor_.kernel_name(); }  // "oracle" or the SIMD target's
  int frame() const { return frame_; }
  const std::vector<glm::vec3>& light_positions() const { return light_positions_; }  // as placed now
  // The light positions recorded with the newest shot (what its requests are traced with).
  const std::vector<glm::vec3>& newest_shot_light_positions() const { return shots_.empty() ? light_positions_ : shots_.back().placement->lights; }
  size_t pending_requests() const { return async_ ? async_->pending_requests() : 0; }  // async: not yet shaded

 private:
  struct PlacementState {
    std::vector<glm::mat4> objects;  // object_to_world per object
    std::vector<glm::vec3> lights;   // position per punctual light
    uint16_t epoch = 0;              // counts placements: shading of one epoch refines its own (PointCache)
  };
  using Placement = std::shared_ptr<const PlacementState>;
  struct Shot {  // a batch of requests, the view they were made for, and the object and light placement
    uint32_t first_id = 0, count = 0;
    int chosen = 0;  // the frame that chose it
    ViewFrame frame;
    Placement placement;  // the placement its requests are traced with (shared while nothing moves)
  };
  struct NewShot {
    ViewFrame frame;
    std::vector<ShadeRequest> requests;
  };
  const RgbImage& render_frame(const Camera& camera, std::span<const glm::mat4> object_to_world,
                               std::span<const glm::vec3> light_positions);
  void apply_placement(std::span<const glm::mat4> object_to_world, std::span<const glm::vec3> light_positions);
  void find_and_rasterize_edges(const ViewFrame& frame);
  void integrate(const ShadeBatch& batch);
  // The requests of the frame numbered `index` (it keys their jitter), from `priority`, made for
  // `frame` (the view the priority image belongs to), and predicted ones when the camera moves.
  std::vector<NewShot> choose_requests(const ViewFrame& frame, std::span<const float> priority, int index);
  size_t budget() const;

  const Scene& scene_;
  RayScene& ray_scene_;
  const Shader& shader_;
  FrameSettings settings_;
  std::unique_ptr<AsyncShader> async_;
  int cores_ = 1, shader_threads_ = 0;
  bool shader_behind_ = false;  // the last frame's requests were not all shaded by its end
  std::vector<uint32_t> effort_counts_;  // set_sparse_effort's block counts
  int effort_most_ = 1;  // async: the most effort a request may take now (FrameSettings::sparse_effort)
  double budget_scale_ = 1.0;   // of sample_budget, grown while the shader keeps up (FrameSettings::rest_sample_budget, motion_sample_budget)
  std::unique_ptr<tbb::task_arena> loop_arena_;  // the loop's cores while the shader is behind (adaptive)
  PointCache cache_;
  EpiImage epi_;
  BoundaryMasks masks_;
  Reconstructor reconstructor_;  // scratch and kernels chosen once
  Reconstruction reconstruction_;
  std::vector<glm::mat4> transforms_;
  std::vector<glm::vec3> light_positions_;  // per punctual light, as placed now
  std::deque<Shot> shots_;
  std::vector<NewShot> sync_shots_;  // sync_as_async: chosen at the end of a frame, shaded at the start of the next
  Placement placement_;  // a snapshot of transforms_ and light_positions_, renewed when something moves
  uint32_t next_id_ = 0;
  std::unique_ptr<Camera> previous_camera_;
  double result_lag_ = 0.0;  // FrameStats::result_lag of the last frame that integrated results
  // epi mode: the edge finder sees a light copy of the scene (objects, lights) placed as now.
  std::shared_ptr<edges::SceneEdgeFinder> finder_;
  Scene edge_scene_;
  std::vector<glm::mat4> load_transforms_;
  std::map<edges::LightBlockerReceiver, int> triples_;  // -> the last frame a result reported it
  std::vector<edges::SceneEdge> edges_;
  std::vector<Segment> segments_;
  std::vector<edges::EdgeKind> segment_kinds_;
  std::vector<uint32_t> piece_edge_;  // the edge of each piece in segments_
  std::vector<glm::dvec2> piece_inv_depth_;  // 1/depth at each piece's ends
  std::vector<EdgeFate> edge_fates_;
  EdgeProjectionScratch edge_scratch_;
  std::vector<float> filtered_depth_;
  EdgeCrossings crossings_;           // the same edges' barrier pieces, for the occlusion test
  std::vector<uint8_t> edge_pixels_;  // pixels crossed by edges, by kind (point_cache.h)
  std::vector<uint8_t> barrier_;  // hole filling
  HoleFillScratch hole_scratch_;
  SparseBlendScratch sparse_scratch_;
  // Predictive sampling's per-frame scratch: predicted occupancy (then the gaps), depth sums per
  // band of rows, unseen 8x8 blocks, the gap pixels picked, gaps per row.
  std::vector<uint8_t> occupied_, unseen_;
  std::vector<std::pair<double, size_t>> depth_sums_;
  std::vector<uint32_t> picked_;
  std::vector<size_t> gap_rows_;  // gaps above each row (prefix sums)
  FrameStats stats_;
  int frame_ = 0;
};

}  // namespace epi::render

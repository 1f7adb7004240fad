// The render cache's point processing (docs/render.md, "Points"): a fixed-size cloud of shaded
// points, projected every frame with a z-buffer and 4-bit sub-pixel positions, the depth-cull
// filter, aging, and new shading results overwriting old points. Points are stored in their
// object's space, so points on a moving object move with it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "epi/epi_pixel.h"
#include "render/edge_crossings.h"
#include "render/point_projection.h"
#include "scene/scene.h"
#include "shade/shader.h"
#include "shade/view.h"

namespace epi::render {

// std::lround's value for any finite float of magnitude below 2^52, inline (lround is a call into
// libm): x + 1/2 is exact in double, and trunc rounds it towards zero.
inline double round_half_away(float x) { return std::trunc(double(x) + std::copysign(0.5, double(x))); }

// The occlusion test scans a window row as one 32-bit mask: radii above this are refused.
inline constexpr int kMaxOcclusionRadius = 15;
// A result lands in front of the point drawn at its pixel (PointCacheSettings::new_occluder_radius)
// when its depth times 1 + this is below that point's.
inline constexpr float kNewOccluderMargin = 0.1f;

struct PointCacheSettings {
  double capacity_factor = 1.15;   // cloud size as a multiple of the pixel count
  int max_age = 240;               // points older than this are not drawn (and their slot is freed)
  int offscreen_penalty = 3;       // extra age per frame for points that project outside the image
  float depth_cull_offset = 0.1f;  // cull a point deeper than (1 + offset) x the 3x3 mean depth
  float change_threshold = 0.1f;   // relative colour change that counts as "shading changed"
  int change_penalty = 48;         // age added around a pixel whose shading changed
  int change_radius = 2;           // ... over a (2r+1)^2 window
  // Edge-aware occlusion (epi mode, cull_behind_surfaces): a drawn point lying more than this
  // (relative depth) behind the tangent plane of a nearer drawn point within `occlusion_radius`
  // pixels, with no geometric edge between them, is hidden.
  float occlusion_margin = 0.02f;
  int occlusion_radius = 2;  // at most kMaxOcclusionRadius, as sparse_occlusion_radius
  // ... and up to `sparse_occlusion_radius` pixels, a nearer point that stands alone (no other
  // drawn point in its 3x3 is nearer than the tested one by the margin): a near surface sampled
  // more sparsely than occlusion_radius, as one magnified by the camera's motion, hides what lies
  // behind the gaps between its points (docs/render.md, "Sparse near surfaces"). 0: off.
  int sparse_occlusion_radius = 4;
  // ... and up to `new_occluder_radius` pixels, a lone point shaded within the last
  // `new_occluder_frames` projections whose result landed in front of the point drawn at its pixel
  // (by kNewOccluderMargin): a surface that has just come in front of the cached points, such as
  // an object sweeping across the view, has only the few samples that found it, farther apart
  // than sparse_occlusion_radius (docs/render.md, "New occluders"). At most kMaxOcclusionRadius;
  // not above sparse_occlusion_radius: off (the rule also needs the sparse rule on).
  int new_occluder_radius = 8;
  int new_occluder_frames = 4;
  // Progressive refinement (docs/render.md, "Convergence at rest"): a result landing on the same
  // surface point, shaded under the same placement (epoch) and, for view-dependent shading, from
  // about the same direction, is averaged into it instead of replacing it.
  bool refine = true;
  // View-dependent shading (the Shading Cache's aging, measured by the turn of the view): a
  // point's staleness is the angle between the eye's direction now and at shading, in widths of
  // its specular lobe. It raises the point's sampling priority by view_priority x (view-dependent
  // share) x staleness (in age units), and the view-dependent part of its colour fades out between
  // view_fade_start and view_fade_end lobe widths (a highlight seen from elsewhere is not shown;
  // 2 to 6 measured better than 1 to 3 along the bundled paths: docs/render.md, "View-dependent
  // shading").
  float view_priority = 16.0f;
  float view_fade_start = 2.0f, view_fade_end = 6.0f;
  // A point past view_fade_end whose colour is mostly view-dependent (share above this: metals,
  // mirrors) is not written into the EPI at all: its pixel is reconstructed from fresher
  // neighbours instead of shown as a faded, too dark sample (it stays an occluder).
  float view_drop_share = 0.5f;
  // Sampling priority (the age the EPI sees): the age times the relative standard error of the
  // point's mean luminance over single_sample_error, clamped to [1/4, 4]; a single result counts as
  // that error (factor 1), so refined, converged points ask later and noisy ones sooner.
  float single_sample_error = 0.25f;
  // Punctual highlights (docs/render.md, "Punctual highlights"): a result whose punctual lights'
  // specular part (ShadeResult::punctual_specular) is at least this share of its colour's
  // luminance keeps that part apart, with what recomputes it (the lights that reach the point,
  // its shading normal, its material); the cache then shows it recomputed for the eye of each
  // frame (PunctualSpecularModel, given by set_highlight_model) instead of as it was seen
  // from the shading view, and ages, fades and refines only the rest of the colour. Without a
  // model, or above 1 (kNoPunctualHighlights), no result keeps it apart.
  float punctual_highlight_share = 0.1f;
  static constexpr float kNoPunctualHighlights = 2.0f;
  bool punctual_highlights() const { return punctual_highlight_share <= 1.0f; }
  // The straightforward implementation of project, depth_cull, cull_behind_surfaces and fill_epi
  // (point_cache_reference.cpp): the oracle the fast path matches bit for bit (tests, benchmarks).
  bool reference_path = false;
};

// Per-pixel edge flags (the renderer's rasterized edges of the last frame).
// kDepthEdge: silhouette or border (the visible depth may jump); kSharpEdge: a crease (the
// surface turns); kShadowEdge: umbral, penumbral, shadow.
inline constexpr uint8_t kDepthEdge = 1, kShadowEdge = 2, kSharpEdge = 4;

// A cloud slot is split in two records (docs/performance.md, "Point processing"): CachePoint, what
// the projection and the EPI word read every frame (48 bytes, streamed), and PointColour, the
// colour statistics read only when a result arrives, a colour fades, or by the reference path.
struct CachePoint {
  glm::vec3 local{0.0f};  // object space; for background (object == kNone) a world direction
  uint32_t object = kNone;
  uint32_t normal = 0;    // geometric normal in object space, octahedral 16:16 (0 for background)
  uint32_t view = 0;      // world direction from the point to the eye it was shaded from, octahedral
  float lobe_width = 0.0f;  // specular lobe width at the point (radians); 0: none
  // Bits 0-23: the colour as the EPI stores it (encode_epi_color8 r, g, b), encoded once, as seen
  // from the view the point was shaded from; bits 24-31: that view's diffuse transmission
  // (ShadeResult::diffuse_transmission) in 1/255, 0: the colour is not rescaled with the view.
  uint32_t srgb = 0;
  int32_t image_id = -1;  // pixel index of the last projection, -1: none
  // Of the colour statistics, set with them (PointCache::update_from_colour): the sampling priority's
  // factor (PointCacheSettings::single_sample_error) and the share of the colour that depends on
  // the eye (PointCacheSettings::view_priority).
  float priority_factor = 1.0f;
  float view_share = 0.0f;
  uint16_t age = 0;
  uint8_t staleness = 0;  // view turned since shading, in 1/16 lobe widths (last projection; capped)
  bool valid = false;
};
static_assert(sizeof(CachePoint) == 48);

// What recomputes a point's punctual highlight for another eye (PointCacheSettings::
// punctual_highlight_share; lights == 0: the point has none, its colour is all it shows).
struct PunctualHighlight {
  uint32_t shading_normal = 0;  // object space, octahedral 16:16 (as CachePoint::normal)
  uint32_t lights = 0;          // ShadeResult::punctual_lights
  uint32_t material = 0;        // Scene::materials
};

struct PointColour {
  glm::vec3 color{0.0f};  // linear RGB (the mean of `count` results, each weighted by its effort)
  glm::vec3 view_dependent{0.0f};  // of color, the part that depends on the eye (ShadeResult::view_dependent)
  // Sum of the results' weighted squared deviations from the mean of their luminance (West's
  // weighted Welford): a result of effort w has 1/w of a single result's variance, so
  // luminance_m2 / (count - 1) estimates that variance and dividing by `weight` gives the mean's.
  float luminance_m2 = 0.0f;
  uint16_t count = 1;         // results averaged into color
  uint16_t epoch = 0;         // placement (objects, lights) the results were shaded under
  uint16_t weight = 1;        // the results' summed effort (ShadeResult::effort), the mean's weight
};
static_assert(sizeof(PointColour) == 36);

// The points drawn in the current frame: one per pixel at most (after the z-buffer and depth cull).
struct PointImage {
  int width = 0, height = 0;
  std::vector<int32_t> point;  // index into the cloud, -1: empty
  std::vector<float> depth;    // along the view axis; +inf where empty
  std::vector<uint8_t> region; // sub-pixel position rx + 4 ry on the 4x4 grid
  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
};

struct ProjectionCounts {
  size_t projected = 0;  // points landing in the image in front of the eye
  size_t drawn = 0;      // pixels holding a point after z-buffer and depth cull
  size_t culled = 0;     // z-buffer winners removed by the depth cull
  size_t occluded = 0;   // of the drawn, removed by the edge-aware occlusion test (epi mode)
  size_t expired = 0;    // points freed for exceeding the maximum age
  size_t back_facing = 0;  // points in the image whose surface faces away from the eye (not drawn)
};

// The colour a point gives the EPI (docs/render.md, "Bright colours"): its view-independent part
// (diffuse, emission) up to kEpiColourMax with its hue kept; the view-dependent part adds to it up
// to 1 per channel (or the base's own level, if brighter) and no further: a highlight's peak is a
// narrow lobe sampled about once per pixel, and above white, interpolated over the gaps between
// points, it spread as blotches (chains at rest, display RMSE 0.031 -> 0.041 when it was kept).
glm::vec3 epi_colour(const glm::vec3& color, const glm::vec3& view_dependent);

// encode_epi_color8 (epi_pixel.h) without its pow and log: the 255 steps' least floats, found once
// with encode_epi_color8 itself, scanned from a lower bound looked up by the float's top 16 bits.
// Equal to it for every float (docs/performance.md, "Point processing").
uint8_t encode_epi_color8_by_steps(float linear);

class PointCache {
 public:
  PointCache(int width, int height, const PointCacheSettings& settings = {});

  // Ages every point, projects the cloud into `frame` with a z-buffer (points of object o placed
  // by object_to_world[o]), then runs depth_cull() (unless depth_cull is false: the EPI runs it
  // once its edges are known). Fills image().
  ProjectionCounts project(const ViewFrame& frame, std::span<const glm::mat4> object_to_world, bool depth_cull = true);

  // The render cache's depth cull: removes from image() a drawn point deeper than (1 + offset) x
  // the mean depth of the drawn points in its 3x3, except (given edge_pixels of the image's size)
  // within a pixel of a silhouette or border (kDepthEdge), whose far side is visible. Returns the
  // number removed.
  size_t depth_cull(std::span<const uint8_t> edge_pixels = {});

  // Integrates shading results made for `shot` (its camera gives misses their direction) and traced
  // with objects placed by object_to_world (the hit positions are converted to object space with
  // it, so they then move with their object). A result
  // replaces the point drawn at its pixel in the last projection when that point is the same
  // surface; otherwise it takes a free slot, or the next slot in round-robin order. When the
  // replaced point's colour differs noticeably, the points around it are aged (shading changed).
  // Returns the number of results integrated.
  // `epoch` names the placement of objects and lights the shot was traced under: results of one
  // epoch may refine each other (PointCacheSettings::refine); a new epoch starts every point anew.
  size_t insert(const ViewFrame& shot, const ShadeBatch& batch, std::span<const glm::mat4> object_to_world,
                uint16_t epoch = 0);

  // Epi mode, after project(): removes from image() the drawn points that lie behind the tangent
  // plane of a nearer drawn point close by (within occlusion_radius, or sparse_occlusion_radius
  // when that point stands alone in its 3x3), unless a geometric edge (silhouette, border, sharp)
  // passes between the two (`crossings`: this frame's edges, tested exactly, sub-pixel). The
  // EPI's edges say where depth may jump; elsewhere the visible surface is continuous, so a
  // far point next to a near one shows through a sparsely sampled nearer surface (the dots
  // of docs/render.md, "Hidden points"). Returns the number removed.
  size_t cull_behind_surfaces(const ViewFrame& frame, std::span<const glm::mat4> object_to_world,
                              const EdgeCrossings& crossings);
  // Pixels (of the last projection) where results replace rather than refine: non-zero entries.
  // Empty: none.
  void set_refine_mask(std::span<const uint8_t> no_refine) { no_refine_.assign(no_refine.begin(), no_refine.end()); }

  // Writes the drawn points into the EPI as samples (colour, sub-pixel region, age); clears the rest.
  void fill_epi(EpiImage& epi) const;

  // What recomputes the points' punctual highlights (Shader::punctual_specular_model; none: none
  // kept, PointCacheSettings::punctual_highlight_share), read when the EPI is filled. The cache
  // owns it; the caller moves its lights as the frame's placement moves them.
  void set_highlight_model(std::optional<PunctualSpecularModel> model);
  void move_highlight_light(size_t light, const glm::vec3& position);
  // A point's punctual highlight seen from the last projection's eye (zero without one).
  glm::vec3 highlight_now(size_t slot) const;
  const std::vector<PunctualHighlight>& highlights() const { return highlights_; }  // of points()[i]; empty: none kept

  // Where a point is in the world under the given object transforms (background points sit at
  // background_depth() along their direction from the frame's eye).
  glm::vec3 world_position(const CachePoint& p, const ViewFrame& frame, std::span<const glm::mat4> object_to_world) const {
    if (p.object == kNone || p.object >= object_to_world.size()) return frame.eye() + p.local * background_depth_;
    return glm::vec3(object_to_world[p.object] * glm::vec4(p.local, 1.0f));
  }

  const PointImage& image() const { return image_; }
  const std::vector<CachePoint>& points() const { return points_; }
  const std::vector<PointColour>& colours() const { return colours_; }  // of points()[i]: colours()[i]
  size_t capacity() const { return points_.size(); }
  size_t valid_points() const { return valid_points_; }  // kept as slots change (no pass over the cloud)
  size_t hidden_removed() const { return hidden_removed_; }  // points whose slot a ray showed hidden
  size_t refined() const { return refined_; }                // results averaged into a point
  const PointCacheSettings& settings() const { return settings_; }
  void use_reference_path(bool on) { settings_.reference_path = on, pixel_words_current_ = false; }  // see PointCacheSettings
  float background_depth() const { return background_depth_; }

 private:
  // What the EPI word takes from a point's colour statistics: stored in the point (the fast path)
  // or computed from its PointColour (the reference path, so that the oracle checks the stored ones).
  struct ColourTerms {
    float view_share, priority_factor;
  };
  static ColourTerms stored_terms(const CachePoint& p) { return {p.view_share, p.priority_factor}; }
  ColourTerms colour_terms(const PointColour& c) const;
  // Sets p's srgb and colour terms from its colour statistics (whenever they change).
  void update_from_colour(CachePoint& p, const PointColour& c) const;
  // How far the view has turned at p since it was shaded (to_eye: from the point to the eye now),
  // in 1/16 lobe widths; 0 for shading that does not depend on the view.
  uint8_t view_staleness(const CachePoint& p, float view_share, const glm::vec3& to_eye) const;
  // Whether p's shading depends on the view at all (else its staleness is 0).
  static bool view_dependent(const CachePoint& p, float view_share) {
    return p.lobe_width > 0.0f && p.object != kNone && view_share > 0.0f;
  }
  bool refines(const CachePoint& cached, const PointColour& cached_colour, const CachePoint& result,
               const PointColour& result_colour) const;
  // The EPI's age byte drives sampling priority (age / 16): points whose mean is still uncertain
  // ask for samples sooner (colour_terms); the background is exact.
  int priority_age(const CachePoint& p, ColourTerms terms) const {
    if (p.object == kNone || settings_.single_sample_error <= 0.0f) return p.age;
    const float view = settings_.view_priority * terms.view_share * float(p.staleness) / 16.0f;
    return int(round_half_away(std::min(float(p.age) * terms.priority_factor + view, 1e4f)));
  }
  // srgb, less the view-dependent part as it goes stale, the diffuse part times the current view's
  // diffuse transmission (transmission_now) where it differs from the shading view's by more than
  // kTransmissionTolerance (8 %: 2 % measured the same RMSE along the paths within 1.6 %, and
  // re-encodes more colours a frame; docs/render.md, "Diffuse transmission"); by_steps: encoded
  // with encode_epi_color8_by_steps
  static constexpr float kTransmissionTolerance = 0.08f;
  // `highlight`: a punctual highlight to add (highlight_now; its point's colour is shown through
  // faded_srgb then, whether or not it fades).
  uint32_t display_srgb(const CachePoint& p, const PointColour& c, float transmission_now, bool by_steps = false,
                        const glm::vec3& highlight = glm::vec3(0.0f)) const {
    if (highlight != glm::vec3(0.0f)) return faded_srgb(p, c, transmission_now, by_steps, highlight);
    return shows_faded(p, transmission_now) ? faded_srgb(p, c, transmission_now, by_steps) : p.srgb & 0xffffffu;
  }
  // Whether display_srgb computes the colour (faded_srgb) instead of taking srgb as stored.
  bool shows_faded(const CachePoint& p, float transmission_now) const {
    const float then = float(p.srgb >> 24);
    const bool rescale = then > 0.0f && std::abs(transmission_now * 255.0f - then) > kTransmissionTolerance * then;
    return !(float(p.staleness) / 16.0f <= settings_.view_fade_start && !rescale);
  }
  uint32_t faded_srgb(const CachePoint& p, const PointColour& c, float transmission_now, bool by_steps,
                      const glm::vec3& highlight = glm::vec3(0.0f)) const;
  // Whether slot has a punctual highlight: a bit per slot, which the projection reads for every
  // point (fill_epi reads the 12-byte records of the drawn ones only).
  bool has_highlight(size_t slot) const { return !highlight_bits_.empty() && (highlight_bits_[slot >> 6] >> (slot & 63) & 1u); }
  void set_highlight(size_t slot, const PunctualHighlight& h) {
    highlights_[slot] = h;
    const uint64_t bit = uint64_t(1) << (slot & 63);
    highlight_bits_[slot >> 6] = h.lights != 0 ? highlight_bits_[slot >> 6] | bit : highlight_bits_[slot >> 6] & ~bit;
  }
  // The current view's diffuse transmission at p (brdf.h; 1 without a normal), from the eye of the
  // last projection: what project_batch's transmission gives the fast path's projection.
  float transmission_now(const CachePoint& p) const;
  // stale and mostly view-dependent (view_drop_share)
  bool shows_nothing(const CachePoint& p, float view_share) const {
    return float(p.staleness) / 16.0f >= settings_.view_fade_end && view_share > settings_.view_drop_share;
  }
  size_t take_slot();
  bool drawn(size_t slot) const;  // the point is the one drawn at its pixel in the last projection
  bool back_facing(const CachePoint& p) const;  // uses eye_local_ of the current projection
  void choose_evict_age(size_t needed);
  // insert's first phase, one result at a time and independent of the others (so in parallel):
  // the new point, where its surface was at the last projection, and find_hidden's verdict with
  // the pixels it read, to be checked against what earlier results of the batch changed.
  struct HiddenSearch {
    static constexpr int kMaxPixels = 25;  // the 3x3 around the hit, then at most 16 steps of the walk
    int32_t found = -1;
    int count = 0;  // pixels read, in order, up to and including the one found
    std::array<uint32_t, kMaxPixels> pixels;
  };
  struct PreparedResult {
    CachePoint point;
    PointColour colour;
    PunctualHighlight highlight;
    glm::vec3 world;  // where the point's surface was at the last projection
    Projection last;  // `world` in the last projection (when there is one)
    int32_t last_pixel = -1;  // the pixel `last` lands in; -1 behind the eye or outside the image
    int listed = 0;  // hidden.pixels listed by hidden_candidates, before they are read
    HiddenSearch hidden;
  };
  void prepare_result(const ViewFrame& shot, const ShadeResult& r, std::span<const glm::mat4> object_to_world,
                      uint16_t epoch, bool search_hidden, PreparedResult& out) const;
  // Whether an earlier result of the batch changed what `search` read (a winner, or a winner's record).
  bool search_outdated(const HiddenSearch& search) const;
  void touch_slot(size_t slot) {
    if (!slot_touched_[slot]) slot_touched_[slot] = 1, touched_slots_.push_back(uint32_t(slot));
  }
  // `trace`, when given, records the pixels read and the verdict. The search in two steps (which
  // insert's first phase takes for many results at once, prefetching between them): the pixels it
  // may read, in order, and the first of them whose winner the shot's ray shows hidden.
  int32_t find_hidden(const ViewFrame& shot, const ShadeResult& r, const glm::vec3& last_world,
                      std::span<const glm::mat4> object_to_world, HiddenSearch* trace = nullptr) const;
  int hidden_candidates(const ViewFrame& shot, const ShadeResult& r, const Projection& at_last,
                        std::array<uint32_t, HiddenSearch::kMaxPixels>& pixels) const;
  void first_hidden(const ViewFrame& shot, const ShadeResult& r, std::span<const glm::mat4> object_to_world, int listed,
                    HiddenSearch& search) const;
  // The reference path (PointCacheSettings::reference_path).
  ProjectionCounts project_reference(const ViewFrame& frame, std::span<const glm::mat4> object_to_world, bool depth_cull);
  size_t depth_cull_reference(std::span<const uint8_t> edge_pixels);
  // The reference path: whether a projection lands in the image (in front of the near plane),
  // ageing p by the off-screen penalty when it does not (the fast path: place(), project_batch).
  bool in_view_or_penalised(CachePoint& p, const Projection& proj, float znear) const {
    const bool inside = proj.depth > znear && proj.pixel.x >= 0.0f && proj.pixel.y >= 0.0f &&
                        proj.pixel.x < float(image_.width) && proj.pixel.y < float(image_.height);
    if (!inside) penalise_offscreen(p);
    return inside;
  }
  // A point outside the view: older by the off-screen penalty, at no pixel.
  void penalise_offscreen(CachePoint& p) const {
    p.age = uint16_t(std::min(p.age + settings_.offscreen_penalty, 0xffff));
    p.image_id = -1;
  }
  // Both paths: whether (x, y) is within a pixel of a depth edge (the depth cull leaves it alone).
  bool near_depth_edge(std::span<const uint8_t> edge_pixels, int x, int y) const;
  // The occlusion test of one drawn pixel (both paths; normal_to_world_ made for this frame).
  // background_ring: the stray background rule's window (stray_background) is scanned.
  bool hidden_behind_a_neighbour(const ViewFrame& frame, std::span<const glm::mat4> object_to_world,
                                 const EdgeCrossings& crossings, int x, int y, bool dense_window = true,
                                 bool sparse_ring = true, bool occluder_ring = true, bool background_ring = true) const;
  // Whether the point drawn at (x, y) is a stray background point (docs/render.md, "Stray
  // background points"): a background point (at least kBackgroundDepthShare of background_depth_
  // deep, as every background point in a view narrower than 178 degrees is) with no barrier edge
  // (silhouette, border, sharp) within stray_background_radius() pixels. Background shows only
  // where no surface is, and every surface's outline is a barrier edge: every nearer point of
  // that window, not only a lone one, may hide it (8 pixels: 4, the sparse radius, left as many
  // dots on chains' floor after a fast orbit as there were without the rule on one seed of three).
  static constexpr float kBackgroundDepthShare = 0.01f;
  static constexpr int kStrayBackgroundRadius = 8;
  bool stray_background(const EdgeCrossings& crossings, int x, int y) const;
  int stray_background_radius() const {  // at least the other rules' windows (their points are a subset)
    return std::min(kMaxOcclusionRadius, std::max({kStrayBackgroundRadius, settings_.sparse_occlusion_radius,
                                                   settings_.occlusion_radius, settings_.new_occluder_radius}));
  }
  size_t cull_behind_surfaces_reference(const ViewFrame& frame, std::span<const glm::mat4> object_to_world,
                                        const EdgeCrossings& crossings);
  void fill_epi_reference(EpiImage& epi) const;
  // The fast path's per-block partial results, kept between frames (nothing is reallocated).
  struct PointBlock {  // kPointBlock points of the cloud
    size_t projected = 0, expired = 0, back_facing = 0;
    std::vector<uint32_t> ages;        // eviction order, as age_histogram_
    std::vector<uint32_t> free;        // invalid slots, ascending
    std::vector<uint32_t> tile_count;  // points drawn per tile, then the binning's write cursor
  };
  struct TileBlock {  // a kTileSize^2 tile of the image
    size_t drawn = 0;
    std::vector<uint32_t> ages;  // of the drawn points
  };
  void count_drawn(size_t tile, int x0, int y0, int x1, int y1);
  // fill_epi's colour word: display colour and priority age
  uint32_t epi_color_word(size_t slot, float transmission_now) const {
    const CachePoint& p = points_[slot];
    return display_srgb(p, colours_[slot], transmission_now, true, highlight_now(slot)) | priority_bits(p);
  }
  uint32_t priority_bits(const CachePoint& p) const {  // the colour word's age byte
    return uint32_t(std::min<int>(priority_age(p, stored_terms(p)), 255)) << bits::kAgeShift;
  }
  void window_min_depth(int radius);  // min_depth_: the least depth over each pixel's (2r+1)^2 window
  void window_min(const std::vector<float>& depth, int radius, std::vector<float>& min_depth);  // the same of any image
  // For the sparse occlusion radius: neighbour_min_depth_, the least depth of the other pixels of
  // each pixel's 3x3 (a point q stands alone for a farther point p when that times 1 + margin is
  // not below p's depth), and alone_depth_, the depth of the points nearer than all their
  // neighbours (the only ones that can stand alone; +inf elsewhere), whose window minimum finds
  // the candidates. Returns false when the sparse radius adds nothing (nothing computed, and
  // hidden_behind_a_neighbour reads neither). With the new-occluder rule, also occluder_depth_:
  // alone_depth_ where the point is a new occluder (new_occluder()), +inf elsewhere;
  // any_new_occluder_ says whether it holds one.
  bool mark_alone();
  // The fast path's candidates for the new occluders' ring: occluder_near_ (any: there are some).
  void near_occluders(bool any);
  // The point at this slot is a new occluder (PointCacheSettings::new_occluder_radius) now.
  bool new_occluder(size_t slot) const {
    return seeded_at_[slot] != 0 && projections_ - seeded_at_[slot] < uint32_t(settings_.new_occluder_frames);
  }
  bool new_occluder_rule() const {
    return settings_.new_occluder_radius > std::max(settings_.sparse_occlusion_radius, settings_.occlusion_radius) &&
           settings_.new_occluder_frames > 0;
  }
  // Runs pass(first row, end row, list) over bands of rows in parallel, each with its own cleared
  // list in band_lists_; remove_listed() then empties the listed pixels and counts them.
  template <class BandPass>
  void for_bands(int height, const BandPass& pass);
  // for_bands over the pixels where candidate(pixel index) holds: visit(x, y, list). The test runs
  // over a chunk of a row first, without branches (drawn and empty pixels alternate at random),
  // so the visits (rare) are the only branch taken. ahead(pixel index) is called for each of a
  // chunk's candidates before the first of them is visited (to prefetch what the visits read).
  template <class Candidate, class Visit, class Ahead>
  void for_candidates(const Candidate& candidate, const Visit& visit, const Ahead& ahead);
  size_t remove_listed();

  PointCacheSettings settings_;
  std::vector<CachePoint> points_;
  std::vector<PointColour> colours_;
  std::optional<PunctualSpecularModel> highlight_model_;
  std::vector<PunctualHighlight> highlights_;  // of points_[i] while a model is set
  std::vector<uint64_t> highlight_bits_;       // bit i: highlights_[i].lights != 0
  std::vector<uint32_t> free_slots_;
  size_t valid_points_ = 0;
  size_t cursor_ = 0;
  int evict_age_ = 1;                   // take_slot's sweep takes points at least this old
  std::vector<uint32_t> age_histogram_;  // of the last projection less the points evicted since (not drawn last)
  size_t hidden_removed_ = 0, refined_ = 0;
  PointImage image_;
  std::vector<uint64_t> zbuffer_;  // reference path: (depth bits << 32) | point index, min wins
  std::vector<int32_t> winners_;   // z-buffer result before the depth cull
  std::vector<PointBlock> point_blocks_;
  std::vector<TileBlock> tile_blocks_;
  // Per point drawn this frame: its record (point_projection.h: one record, so that the binning
  // scatters one stream per tile) and its tile, listed per block of the cloud from the block's
  // first slot (block b's PointBlock::projected records from b kPointBlock).
  std::vector<ProjectedPoint> projected_;
  std::vector<uint32_t> point_tile_;
  // The same, binned by tile: tile t's are binned_[tile_begin_[t], tile_begin_[t + 1]).
  std::vector<uint32_t> tile_begin_;
  std::vector<ProjectedPoint> binned_;
  // The EPI colour word and age bin of each pixel's z-buffer winner, made while the projection
  // streams the cloud (fill_epi then reads no point); the words are current until an insert.
  std::vector<uint32_t> pixel_word_;
  std::vector<uint16_t> pixel_age_bin_;
  bool pixel_words_current_ = false;
  std::vector<std::vector<uint32_t>> band_lists_;  // depth_cull, cull_behind_surfaces: pixels to empty
  std::vector<float> min_depth_;                    // window_min_depth
  std::vector<std::vector<float>> min_rings_;       // window_min: each band's ring of row minima
  std::vector<float> neighbour_min_depth_, alone_depth_, sparse_min_depth_;  // mark_alone
  // stray_cell_minima: per band of 2^kStrayCellShift rows and pixel column, at most the least
  // depth within the stray window's radius of the band's pixels there (stray_near_; the fast
  // path's candidates for the stray background rule); nothing when `any` is false.
  static constexpr int kStrayCellShift = 2;
  std::vector<float> stray_cells_, stray_near_;
  void stray_cell_minima(bool any);
  bool any_drawn_deeper(float floor) const;  // whether some drawn point lies at least `floor` deep
  std::vector<float> occluder_depth_;       // ... new occluders (+inf but at occluder_pixels_)
  std::vector<uint32_t> occluder_pixels_;
  bool any_new_occluder_ = false;
  std::vector<std::pair<uint32_t, uint32_t>> recent_occluders_;  // insert's marked slots and their stamps
  // near_occluders: per pixel, the least depth of the new occluders in its cell's 3x3 cells (+inf
  // where none); per cell, that depth; the cells set.
  std::vector<float> occluder_near_, occluder_cells_;
  std::vector<uint32_t> occluder_cells_reached_;
  // Per slot: 1 + the number of projections before the result that landed in front of the point
  // drawn at its pixel (a new occluder), 0 for other results; projections_ counts projections.
  std::vector<uint32_t> seeded_at_;
  uint32_t projections_ = 0;
  std::vector<glm::mat3> normal_to_world_;  // of the last projection's objects (project): the occlusion test's and highlight_now's
  std::vector<uint8_t> hidden_;             // ... and the reference path's verdicts
  std::vector<glm::vec3> eye_local_;        // the eye in each object's space (project)
  std::vector<glm::mat4> to_object_;  // insert: inverse object transforms
  std::vector<PreparedResult> prepared_;  // insert: per result (~200 bytes)
  // insert: slots and pixels whose record or z-buffer winner an earlier result of the batch
  // changed (1 byte per slot and per pixel), and their indices, to clear them after the batch.
  std::vector<uint8_t> slot_touched_, pixel_touched_;
  std::vector<uint32_t> touched_slots_, touched_pixels_;
  std::vector<uint8_t> no_refine_;  // see set_refine_mask
  float background_depth_ = 1e6f;  // where background points are placed along their direction
  std::optional<ViewFrame> last_frame_;
  std::vector<glm::mat4> last_transforms_;  // the placement of the last projection
};

}  // namespace epi::render

#include "render/point_cache.h"

#include "render/depth_windows.h"
#include "render/point_cache_detail.h"
#include "render/point_projection.h"
#include "shade/brdf.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace epi::render {

namespace {

using namespace detail;

constexpr float kMinLobeWidth = 0.02f;  // radians: narrower lobes age as if this wide
// The fast path's fixed work units: blocks of points, square tiles and bands of rows of the image.
constexpr size_t kPointBlock = 16384;
// The projection's tiles (a z-buffer of 4096 pixels each, in L1/L2): wide and short, so that the
// unpacking writes long runs of each image plane (256 x 16: the projection 1.07-1.11x faster
// than 64 x 64 at 1080p; docs/performance.md, "Point processing").
constexpr int kTileWidth = TileLayout::kWidth, kTileHeight = TileLayout::kHeight, kBandRows = 8;
constexpr uint16_t kShowsNothing = 0x8000;     // age bin flag: shows_nothing (fill_epi leaves the pixel empty)
constexpr uint16_t kHighlighted = 0x4000;      // age bin flag: a punctual highlight (fill_epi adds it)

}  // namespace

glm::vec3 epi_colour(const glm::vec3& color, const glm::vec3& view_dependent) {
  glm::vec3 base = glm::max(color - view_dependent, glm::vec3(0.0f));
  base *= epi_color_scale(base.r, base.g, base.b);
  return glm::min(base + view_dependent, glm::max(base, glm::vec3(1.0f)));
}

namespace {

uint32_t pack_srgb(const glm::vec3& color, const glm::vec3& view_dependent) {
  const glm::vec3 c = epi_colour(color, view_dependent);
  return uint32_t(encode_epi_color8(c.r)) | uint32_t(encode_epi_color8(c.g)) << 8 | uint32_t(encode_epi_color8(c.b)) << 16;
}

// Octahedral unit vector packing, 16 bits per coordinate.
uint32_t pack_unit(glm::vec3 n) {
  const float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
  if (!(l1 > 0.0f)) return 0;
  n /= l1;
  glm::vec2 e(n.x, n.y);
  if (n.z < 0.0f) e = (1.0f - glm::abs(glm::vec2(e.y, e.x))) * glm::vec2(e.x >= 0.0f ? 1.0f : -1.0f, e.y >= 0.0f ? 1.0f : -1.0f);
  const auto q = [](float v) { return uint32_t(std::lround((std::clamp(v, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f)); };
  return q(e.x) | q(e.y) << 16;
}

float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

bool shading_changed(const glm::vec3& before, const glm::vec3& after, float threshold) {
  const glm::vec3 d = glm::abs(after - before);
  const float scale = 0.5f * (before.r + before.g + before.b + after.r + after.g + after.b) + 0.03f;
  return (d.r + d.g + d.b) > threshold * scale;
}

}  // namespace

namespace {

// encode_epi_color8_by_steps' tables. steps[k]: the least float that encodes to k or more, by
// bisection over float bit patterns (a NaN after the last: no scan passes it). start[b]: the code
// of the least float of bucket b, the floats sharing their top 16 bits (128 buckets per octave)
// from steps[1]'s bucket up to kEpiColourMax's: a lower bound for every float of the bucket.
// scans: the most steps any bucket's floats lie above its start (its greatest float's; 1 here).
struct ColourSteps {
  std::array<float, 257> steps{};
  uint32_t first = 0;
  int scans = 0;
  std::vector<uint8_t> start;
  std::vector<int32_t> start_words;  // start, widened for fade_batch's gathers
};

const ColourSteps& colour_steps() {
  static const ColourSteps t = [] {
    ColourSteps t;
    for (int k = 1; k < 256; ++k) {
      uint32_t below = 0, at = std::bit_cast<uint32_t>(kEpiColourMax);  // encode(0) = 0, encode(kEpiColourMax) = 255
      while (at - below > 1) {
        const uint32_t mid = below + (at - below) / 2;
        (encode_epi_color8(std::bit_cast<float>(mid)) >= k ? at : below) = mid;
      }
      t.steps[size_t(k)] = std::bit_cast<float>(at);
    }
    t.steps[256] = std::numeric_limits<float>::quiet_NaN();
    t.first = std::bit_cast<uint32_t>(t.steps[1]) >> 16;
    auto code = [&](float v) { return int(std::count_if(t.steps.begin() + 1, t.steps.end() - 1, [&](float s) { return s <= v; })); };
    for (uint32_t b = t.first; b <= std::bit_cast<uint32_t>(kEpiColourMax) >> 16; ++b) {
      t.start.push_back(uint8_t(code(std::bit_cast<float>(b << 16))));
      t.scans = std::max(t.scans, code(std::bit_cast<float>(b << 16 | 0xffffu)) - t.start.back());
    }
    t.start_words.assign(t.start.begin(), t.start.end());
    return t;
  }();
  return t;
}

// Without branches on the value (colours below the first step, in one step and in the next
// alternate at random): a fixed number of scans, each adding 1 where the next step is passed.
inline uint8_t encode_by_steps(const ColourSteps& t, float linear) {
  const uint32_t shown = uint32_t(0) - uint32_t(linear >= t.steps[1]);  // 0: below the first step, negative, NaN
  const uint32_t bucket = std::min((std::bit_cast<uint32_t>(linear) >> 16) - t.first, uint32_t(t.start.size() - 1));
  uint32_t k = t.start[bucket];
  for (int s = 0; s < t.scans; ++s) k += uint32_t(t.steps[k + 1] <= linear);
  return uint8_t(k & shown);
}

uint32_t pack_srgb_by_steps(const glm::vec3& color, const glm::vec3& view_dependent) {
  const ColourSteps& t = colour_steps();
  const glm::vec3 c = epi_colour(color, view_dependent);
  return uint32_t(encode_by_steps(t, c.r)) | uint32_t(encode_by_steps(t, c.g)) << 8 | uint32_t(encode_by_steps(t, c.b)) << 16;
}

}  // namespace

uint8_t encode_epi_color8_by_steps(float linear) { return encode_by_steps(colour_steps(), linear); }

const ColourStepTables& colour_step_tables() {
  static const ColourStepTables tables = [] {
    const ColourSteps& t = colour_steps();
    return ColourStepTables{t.steps.data(), t.start_words.data(), t.first, uint32_t(t.start_words.size()), t.scans};
  }();
  return tables;
}

namespace {

// faded_srgb's colour and its view-dependent part (faded_colour_word's arithmetic, which
// fade_batch repeats in lanes in the same order).
void faded_colours(const glm::vec3& color, const glm::vec3& view_dependent, int staleness, bool rescaled, float transmission_now,
                   float fade_start, float fade_span, glm::vec3& shown, glm::vec3& shown_view) {
  const float fade = std::clamp((float(staleness) / 16.0f - fade_start) / fade_span, 0.0f, 1.0f);
  shown_view = view_dependent * (1.0f - fade);
  shown = rescaled ? (color - view_dependent) * transmission_now + shown_view : color - view_dependent * fade;
}

}  // namespace

uint32_t faded_colour_word(const glm::vec3& color, const glm::vec3& view_dependent, int staleness, bool rescaled,
                           float transmission_now, float fade_start, float fade_span) {
  glm::vec3 shown, shown_view;
  faded_colours(color, view_dependent, staleness, rescaled, transmission_now, fade_start, fade_span, shown, shown_view);
  return pack_srgb_by_steps(shown, shown_view);
}

PointCache::PointCache(int width, int height, const PointCacheSettings& settings) : settings_(settings) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("point cache: image size is not positive");
  if (settings.occlusion_radius > kMaxOcclusionRadius || settings.sparse_occlusion_radius > kMaxOcclusionRadius ||
      settings.new_occluder_radius > kMaxOcclusionRadius)
    throw std::invalid_argument("point cache: occlusion radius above 15");
  static_assert(kMaxOcclusionRadius == 15, "the message above names the limit");
  const double capacity = std::ceil(double(width) * double(height) * std::max(1.0, settings.capacity_factor));
  if (capacity > double(kIndexMask)) throw std::invalid_argument("point cache: image too large");
  points_.resize(size_t(capacity));
  colours_.resize(size_t(capacity));
  seeded_at_.assign(size_t(capacity), 0);
  free_slots_.reserve(points_.size());
  for (size_t i = points_.size(); i-- > 0;) free_slots_.push_back(uint32_t(i));
  const size_t pixels = size_t(width) * size_t(height);
  image_.width = width, image_.height = height;
  image_.point.assign(pixels, -1);
  image_.depth.assign(pixels, std::numeric_limits<float>::infinity());
  image_.region.assign(pixels, 0);
  winners_.assign(pixels, -1);
}

PointCache::ColourTerms PointCache::colour_terms(const PointColour& c) const {
  const float total = luminance(c.color);
  const float share = total > 0.0f ? std::clamp(luminance(c.view_dependent) / total, 0.0f, 1.0f) : 0.0f;
  // Sampling priority: relative standard error of the mean luminance, from the spread of the
  // results averaged so far (a single result: single_sample_error), over single_sample_error.
  float error = settings_.single_sample_error;
  if (c.count >= 2) {
    const float n = float(c.count), w = float(c.weight);
    error = std::sqrt(std::max(c.luminance_m2, 0.0f) / (w * (n - 1.0f))) / (luminance(c.color) + 0.02f);
  } else if (c.weight > 1) {
    error /= std::sqrt(float(c.weight));  // one result of effort w
  }
  const float factor = settings_.single_sample_error > 0.0f ? std::clamp(error / settings_.single_sample_error, 0.25f, 4.0f) : 1.0f;
  return {share, factor};
}

void PointCache::update_from_colour(CachePoint& p, const PointColour& c) const {
  // The colour as seen from the shading view: the diffuse part (kept divided by that view's
  // transmission, docs/render.md "Diffuse transmission") times it again.
  const uint32_t then = p.srgb >> 24;
  const glm::vec3 seen = then > 0 ? (c.color - c.view_dependent) * (float(then) / 255.0f) + c.view_dependent : c.color;
  p.srgb = pack_srgb(seen, c.view_dependent) | then << 24;
  const ColourTerms terms = colour_terms(c);
  p.view_share = terms.view_share, p.priority_factor = terms.priority_factor;
}

uint8_t PointCache::view_staleness(const CachePoint& p, float view_share, const glm::vec3& to_eye) const {
  if (!view_dependent(p, view_share)) return 0;
  const float length = glm::length(to_eye);
  if (!(length > 0.0f)) return 0;
  return staleness_steps(std::clamp(glm::dot(to_eye / length, unpack_unit(p.view)), -1.0f, 1.0f),
                         std::max(p.lobe_width, kMinLobeWidth));
}

ProjectionCounts PointCache::project(const ViewFrame& frame, std::span<const glm::mat4> object_to_world, bool depth_cull) {
  ++projections_;
  // New occluders' list: only the marks still current (slot not reused, within their frames).
  std::erase_if(recent_occluders_, [&](const std::pair<uint32_t, uint32_t>& e) {
    return seeded_at_[e.first] != e.second || !new_occluder(e.first);
  });
  // Normals back to world space, for this frame's occlusion test and highlights: the inverse
  // transpose of each object's matrix.
  normal_to_world_.resize(object_to_world.size());
  for (size_t o = 0; o < object_to_world.size(); ++o) normal_to_world_[o] = glm::inverse(glm::transpose(glm::mat3(object_to_world[o])));
  if (settings_.reference_path) return project_reference(frame, object_to_world, depth_cull);
  const int w = image_.width, h = image_.height;
  if (frame.view().width != w || frame.view().height != h)
    throw std::invalid_argument("point cache: view size differs from the cache's image size");
  const int max_age = settings_.max_age;
  const float fade_span = std::max(settings_.view_fade_end - settings_.view_fade_start, 1e-3f);  // as faded_srgb's
  // The eye in each object's space: a point's stored normal faces the eye it was shaded from, and
  // a point whose surface now faces away from the eye is not drawn (back_facing).
  eye_local_.resize(object_to_world.size());
  for (size_t o = 0; o < object_to_world.size(); ++o) eye_local_[o] = glm::vec3(glm::inverse(object_to_world[o]) * glm::vec4(frame.eye(), 1.0f));
  const int tiles_x = TileLayout::columns(w), tiles_y = (h + kTileHeight - 1) / kTileHeight;
  const size_t tiles = size_t(tiles_x) * size_t(tiles_y);
  // The batches' inputs are gathered from the cloud's words (gather_batch; the layout it assumes:)
  static_assert(sizeof(CachePoint) == 4 * CloudLayout::kWords && offsetof(CachePoint, local) == 4 * CloudLayout::kLocal &&
                offsetof(CachePoint, object) == 4 * CloudLayout::kObject && offsetof(CachePoint, normal) == 4 * CloudLayout::kNormal &&
                offsetof(CachePoint, view) == 4 * CloudLayout::kView && offsetof(CachePoint, lobe_width) == 4 * CloudLayout::kLobeWidth);
  static_assert(sizeof(glm::mat4) == 16 * sizeof(float) && sizeof(glm::vec3) == 3 * sizeof(float));
  const uint32_t* const cloud = reinterpret_cast<const uint32_t*>(points_.data());
  const BatchPlacement placement{object_to_world.empty() ? nullptr : &object_to_world[0][0][0],
                                 eye_local_.empty() ? nullptr : &eye_local_[0][0], uint32_t(object_to_world.size()),
                                 frame.eye(), background_depth_, kMinLobeWidth};

  // 1. Aging and projection (blocks of points in parallel): each point's record (z-buffer key,
  // EPI colour word, age bin, pixel within its tile) and tile, listed in slot order from the
  // block's first slot (only the points drawn: the binning reads no other), counted per tile.
  const size_t n = points_.size();
  point_blocks_.resize((n + kPointBlock - 1) / kPointBlock);
  projected_.resize(n), point_tile_.resize(n);
  tbb::parallel_for(size_t(0), point_blocks_.size(), [&](size_t b) {
    PointBlock& block = point_blocks_[b];
    std::array<uint32_t, kAgeBins> ages{};
    size_t projected = 0, expired = 0, back_facing_points = 0;
    block.free.clear();
    block.tile_count.assign(tiles, 0);
    // In batches: the valid points' slots listed, their world positions and the rest of the
    // projection's inputs gathered (gather_batch, vectors), the projections, where they land
    // (pixel, tile, sub-pixel region), the staleness, the back-face test and the diffuse
    // transmission (project_batch, vectors), then the rest, ages first (scalar), then the free
    // slots listed. Valid and free slots alternate at random: the listings are branch-free, and
    // the passes between see valid points only.
    ProjectionBatch batch;
    FadeBatch fade;
    std::array<uint32_t, ProjectionBatch::kSize> slots, faded_slots;
    for (size_t first = b * kPointBlock, block_end = std::min(n, first + kPointBlock); first < block_end;
         first += ProjectionBatch::kSize) {
      const size_t count = std::min(ProjectionBatch::kSize, block_end - first);
      size_t valid = 0;
      for (size_t k = 0; k < count; ++k) {
        slots[valid] = uint32_t(first + k);
        valid += size_t(points_[first + k].valid);
      }
      // The lanes past the last valid point, to the widest vector's 16, project it again (unused).
      for (size_t k = valid; k < std::min(ProjectionBatch::kSize, valid + 16) && valid > 0; ++k) slots[k] = slots[valid - 1];
      gather_batch(cloud, uint32_t(first), slots.data(), valid, placement, batch);
      project_batch(frame, batch, valid);
      // The next batch's records, a cache line per point of this one, the rest after: spread over
      // the work (a burst of prefetches before it waited for the line fill buffers as the loads
      // did: docs/performance.md, "Point processing").
      const char* ahead = reinterpret_cast<const char*>(points_.data() + std::min(n, first + ProjectionBatch::kSize));
      const char* const ahead_end = reinterpret_cast<const char*>(points_.data() + std::min(n, first + 2 * ProjectionBatch::kSize));
      size_t faded = 0;
      for (size_t k = 0; k < valid; ++k) {
        const size_t i = slots[k];
        if (ahead < ahead_end) __builtin_prefetch(ahead, 1), ahead += 64;
        // The colour record 16 points ahead (read below for fade_batch: 37 % of faded_srgb's
        // samples waited on it when it read the record)
        __builtin_prefetch(&colours_[slots[std::min(k + 16, valid - 1)]]);
        CachePoint& p = points_[i];
        p.age = uint16_t(std::min(p.age + 1, 0xffff));
        const glm::vec3 world(batch.x[k], batch.y[k], batch.z[k]);
        p.staleness = !view_dependent(p, p.view_share) ? uint8_t(0)
                      : batch.staleness[k] >= 0                ? uint8_t(batch.staleness[k])
                                                               : view_staleness(p, p.view_share, frame.eye() - world);
        const int32_t pixel = batch.pixel[k];  // place(): -1 outside the view
        if (pixel < 0) penalise_offscreen(p);
        if (p.age > max_age) {
          p.valid = false, p.image_id = -1;
          ++expired;
          continue;
        }
        ++ages[kAgeBins - 1];  // as not drawn; the drawn ones move to their age's bin after the cull
        if (pixel < 0) continue;
        if (batch.back_facing[k]) {
          p.image_id = -1;
          ++back_facing_points;
          continue;
        }
        p.image_id = pixel;
        const uint32_t tile = batch.tile[k], spot = batch.spot[k];
        const float transmission = p.srgb >> 24 ? batch.transmission[k] : 1.0f;
        // epi_color_word: the stored colour, or for a faded one (most drawn points of a glossy
        // scene in motion) fade_batch's after the loop, whose inputs are listed without a branch.
        const bool fades = shows_faded(p, transmission);
        const PointColour& c = colours_[i];
        fade.r[faded] = c.color.r, fade.g[faded] = c.color.g, fade.b[faded] = c.color.b;
        fade.vr[faded] = c.view_dependent.r, fade.vg[faded] = c.view_dependent.g, fade.vb[faded] = c.view_dependent.b;
        fade.staleness[faded] = p.staleness, fade.rescaled[faded] = int32_t((p.srgb >> 24) != 0);
        const size_t at = b * kPointBlock + projected;  // the block's list
        fade.transmission[faded] = transmission, faded_slots[faded] = uint32_t(at);
        faded += size_t(fades);
        projected_[at] = {zkey(batch.depth[k], int(spot >> 16), uint32_t(i)), (fades ? 0u : p.srgb & 0xffffffu) | priority_bits(p),
                         uint16_t(std::min<size_t>(p.age, kAgeBins - 2) | (shows_nothing(p, p.view_share) ? kShowsNothing : 0) |
                                  (has_highlight(i) ? kHighlighted : 0)),
                         uint16_t(spot)};
        point_tile_[at] = tile;
        ++block.tile_count[tile];
        ++projected;
      }
      for (; ahead < ahead_end; ahead += 64) __builtin_prefetch(ahead, 1);
      if (faded > 0) {
        // The lanes past the last faded point, to the widest vector's 16, compute zeros (unused).
        for (size_t k = faded; k < std::min(FadeBatch::kSize, faded + 16); ++k) {
          fade.r[k] = fade.g[k] = fade.b[k] = fade.vr[k] = fade.vg[k] = fade.vb[k] = fade.transmission[k] = 0.0f;
          fade.staleness[k] = fade.rescaled[k] = 0;
        }
        fade_batch(settings_.view_fade_start, fade_span, fade, faded);
        for (size_t k = 0; k < faded; ++k) projected_[faded_slots[k]].word |= fade.word[k];
      }
      // The free slots (expired ones included), ascending.
      size_t free = 0;
      for (size_t k = 0; k < count; ++k) {
        slots[free] = uint32_t(first + k);
        free += size_t(!points_[first + k].valid);
      }
      block.free.insert(block.free.end(), slots.begin(), slots.begin() + ptrdiff_t(free));
    }
    block.projected = projected, block.expired = expired, block.back_facing = back_facing_points;
    block.ages.assign(ages.begin(), ages.end());
  });
  size_t projected = 0, expired = 0, back_facing_points = 0;
  age_histogram_.assign(kAgeBins, 0);
  for (const PointBlock& block : point_blocks_) {
    projected += block.projected, expired += block.expired, back_facing_points += block.back_facing;
    for (size_t k = 0; k < kAgeBins; ++k) age_histogram_[k] += block.ages[k];
  }

  // 2. Binning by tile (a counting sort: tile-major, then block order): tile_begin_[t] is where
  // tile t's records start in binned_; each block's tile_count becomes its write cursor. One
  // 16-byte record per point: one write stream per tile.
  tile_begin_.assign(tiles + 1, 0);
  for (size_t t = 0; t < tiles; ++t) {
    uint32_t at = tile_begin_[t];
    for (PointBlock& block : point_blocks_) {
      const uint32_t count = block.tile_count[t];
      block.tile_count[t] = at;
      at += count;
    }
    tile_begin_[t + 1] = at;
  }
  binned_.resize(projected);
  tbb::parallel_for(size_t(0), point_blocks_.size(), [&](size_t b) {
    uint32_t* cursor = point_blocks_[b].tile_count.data();
    for (size_t i = b * kPointBlock, end = i + point_blocks_[b].projected; i != end; ++i)
      binned_[cursor[point_tile_[i]]++] = projected_[i];
  });

  // 3. Per tile (in parallel; a tile owns its pixels): the minimum keys in a z-buffer of the
  // tile's own (on the stack, in L1/L2), unpacked into the image with the winners' colour words;
  // without a depth cull, the drawn points' ages are counted in the same pass.
  tile_blocks_.resize(tiles);
  static constexpr ProjectedPoint kNoRecord{kEmptyKey, 0, 0, 0};  // an empty pixel's winner when nothing projected
  pixel_word_.resize(image_.point.size()), pixel_age_bin_.resize(image_.point.size());
  tbb::parallel_for(size_t(0), tiles, [&](size_t t) {
    const int x0 = int(t % size_t(tiles_x)) * kTileWidth, y0 = int(t / size_t(tiles_x)) * kTileHeight;
    const int x1 = std::min(w, x0 + kTileWidth), y1 = std::min(h, y0 + kTileHeight);
    std::array<uint64_t, kTileWidth * kTileHeight> zbuffer;
    std::array<uint32_t, kTileWidth * kTileHeight> winner;
    zbuffer.fill(kEmptyKey);
    winner.fill(0);
    // Selects by masks, not branches (the compiler made a branch of `nearer ? k : winner`,
    // mispredicted: a record is nearer about half the time).
    for (uint32_t k = tile_begin_[t]; k != tile_begin_[t + 1]; ++k) {
      const ProjectedPoint& r = binned_[k];
      const uint64_t current = zbuffer[r.tile_pixel];
      const uint32_t take = uint32_t(0) - uint32_t(r.key < current);  // all ones when nearer
      zbuffer[r.tile_pixel] = std::min(r.key, current);
      winner[r.tile_pixel] = (k & take) | (winner[r.tile_pixel] & ~take);
    }
    // Unpacked a vector of pixels at a time (unpack_winners); an empty pixel keeps its region, and
    // its colour word is not read.
    const ProjectedPoint* const records = binned_.empty() ? &kNoRecord : binned_.data();
    const size_t first = image_.index(x0, y0);
    const WinnerPlanes planes{image_.point.data() + first, winners_.data() + first,     image_.depth.data() + first,
                              image_.region.data() + first, pixel_word_.data() + first, pixel_age_bin_.data() + first};
    unpack_winners(zbuffer.data(), winner.data(), kTileWidth, records, size_t(x1 - x0), size_t(y1 - y0), planes, size_t(w));
    if (!depth_cull) count_drawn(t, x0, y0, x1, y1);
  });
  size_t culled = 0;
  if (depth_cull) {
    culled = this->depth_cull({});
    tbb::parallel_for(size_t(0), tiles, [&](size_t t) {
      const int x0 = int(t % size_t(tiles_x)) * kTileWidth, y0 = int(t / size_t(tiles_x)) * kTileHeight;
      count_drawn(t, x0, y0, std::min(w, x0 + kTileWidth), std::min(h, y0 + kTileHeight));
    });
  }

  // Free the slots of expired points (all free slots, in descending order).
  valid_points_ -= expired;
  if (expired > 0) {
    free_slots_.clear();
    for (size_t b = point_blocks_.size(); b-- > 0;)
      free_slots_.insert(free_slots_.end(), point_blocks_[b].free.rbegin(), point_blocks_[b].free.rend());
  }
  size_t drawn = 0;
  for (const TileBlock& block : tile_blocks_) {
    drawn += block.drawn;
    age_histogram_[kAgeBins - 1] -= uint32_t(block.drawn);
    for (size_t k = 0; k + 1 < kAgeBins; ++k) age_histogram_[k] += block.ages[k];
  }
  last_frame_.emplace(frame);
  last_transforms_.assign(object_to_world.begin(), object_to_world.end());
  pixel_words_current_ = true;
  return {projected, drawn, culled, 0, expired, back_facing_points};
}

void PointCache::count_drawn(size_t tile, int x0, int y0, int x1, int y1) {
  // Empty pixels count in the last bin, chosen with a mask (the compiler made a branch of a select,
  // mispredicted where drawn and empty pixels alternate); two histograms, even and odd pixels, so
  // that neighbours of one age do not wait on each other's increment.
  std::array<std::array<uint32_t, kAgeBins + 1>, 2> ages{};
  for (int y = y0; y < y1; ++y)
    for (size_t i = image_.index(x0, y), end = i + size_t(x1 - x0); i != end; ++i) {
      const uint32_t empty = uint32_t(image_.point[i] >> 31);  // all ones for -1
      ++ages[i & 1][(uint32_t(pixel_age_bin_[i] & ~(kShowsNothing | kHighlighted)) & ~empty) | (uint32_t(kAgeBins) & empty)];
    }
  for (size_t k = 0; k <= kAgeBins; ++k) ages[0][k] += ages[1][k];
  tile_blocks_[tile].drawn = size_t((x1 - x0) * (y1 - y0)) - ages[0][kAgeBins];
  tile_blocks_[tile].ages.assign(ages[0].begin(), ages[0].end() - 1);
}

bool PointCache::back_facing(const CachePoint& p) const {
  // The stored normal faces the eye the point was shaded from; seen from the other side of its
  // surface, the point is either hidden (closed surfaces) or shows the other side's shading.
  if (p.object == kNone || p.object >= eye_local_.size()) return false;
  return faces_away(p.normal, eye_local_[p.object] - p.local);
}

bool PointCache::drawn(size_t slot) const {
  const int32_t pixel = points_[slot].image_id;
  return pixel >= 0 && image_.point[size_t(pixel)] == int32_t(slot);
}

// Near a silhouette or border the far side is visible: the depth cull's mean would remove it.
bool PointCache::near_depth_edge(std::span<const uint8_t> edge_pixels, int x, int y) const {
  if (edge_pixels.size() != image_.point.size()) return false;
  const int w = image_.width, h = image_.height;
  for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
    for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx)
      if (edge_pixels[image_.index(qx, qy)] & kDepthEdge) return true;
  return false;
}

size_t PointCache::depth_cull(std::span<const uint8_t> edge_pixels) {
  if (settings_.reference_path) return depth_cull_reference(edge_pixels);
  const int w = image_.width, h = image_.height;
  const float cull_scale = 1.0f + settings_.depth_cull_offset;
  // The 3x3 mean is at least the 3x3 minimum (also as rounded), so a pixel no deeper than the
  // minimum x (1 + offset) (most of them) keeps its point without the mean.
  window_min_depth(1);
  // The means see the z-buffer's winners: culled pixels are listed per band, removed after.
  const float *depth = image_.depth.data(), *min_depth = min_depth_.data();
  const int32_t* point = image_.point.data();
  for_candidates([=](size_t i, int, int) { return (depth[i] > min_depth[i] * cull_scale) & (point[i] >= 0); },
                 [&](int x, int y, std::vector<uint32_t>& culled) {
        const size_t i = image_.index(x, y);
        double sum = 0.0;
        int n = 0;
        for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
          for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) {
            const size_t q = image_.index(qx, qy);
            if (image_.point[q] < 0) continue;
            sum += image_.depth[q];
            ++n;
          }
        if (image_.depth[i] > float(sum / n) * cull_scale && !near_depth_edge(edge_pixels, x, y)) culled.push_back(uint32_t(i));
  }, [](size_t) {});
  return remove_listed();
}

size_t PointCache::take_slot() {
  while (!free_slots_.empty()) {
    const uint32_t slot = free_slots_.back();
    free_slots_.pop_back();
    if (!points_[slot].valid) return slot;
  }
  // Clock sweep from the round-robin cursor: the first slot that is free, off screen, or at least
  // evict_age_ old. Points inserted since the last projection (age 0) are never taken. After a
  // full turn without one (replacements made the old points fresh) any point not inserted this
  // frame will do, also for the rest of the frame (so the futile turn is not repeated), and
  // after a second turn the cursor's slot.
  const size_t n = points_.size();
  auto evict = [&](size_t slot) {  // the histogram follows, so the next insert's threshold is right
    const CachePoint& p = points_[slot];
    const size_t bin = drawn(slot) ? std::min<size_t>(p.age, age_histogram_.size() - 2) : age_histogram_.size() - 1;
    if (p.valid && bin < age_histogram_.size() && age_histogram_[bin] > 0) --age_histogram_[bin];
    return slot;
  };
  for (size_t scanned = 0; scanned < 2 * n; ++scanned) {
    if (scanned == n) evict_age_ = 1;
    const size_t slot = cursor_;
    cursor_ = cursor_ + 1 == n ? 0 : cursor_ + 1;
    const CachePoint& p = points_[slot];
    if (!p.valid) return slot;
    if (p.age == 0) continue;
    if (!drawn(slot) || p.age >= evict_age_) return evict(slot);
  }
  const size_t slot = cursor_;
  cursor_ = cursor_ + 1 == n ? 0 : cursor_ + 1;
  return evict(slot);
}

void PointCache::choose_evict_age(size_t needed) {
  // The largest age such that at least `needed` points are that old or older (off-screen points
  // count as oldest), from the histogram of the last projection less the points evicted since.
  size_t count = 0;
  evict_age_ = 1;
  for (int a = int(age_histogram_.size()) - 1; a >= 1; --a) {
    count += age_histogram_[size_t(a)];
    if (count >= needed) {
      evict_age_ = a;
      break;
    }
  }
}

int32_t PointCache::find_hidden(const ViewFrame& shot, const ShadeResult& r, const glm::vec3& last_world,
                                std::span<const glm::mat4> object_to_world, HiddenSearch* trace) const {
  HiddenSearch local;
  HiddenSearch& search = trace ? *trace : local;
  const int listed = hidden_candidates(shot, r, last_frame_->project(last_world), search.pixels);
  first_hidden(shot, r, object_to_world, listed, search);
  return search.found;
}

int PointCache::hidden_candidates(const ViewFrame& shot, const ShadeResult& r, const Projection& p0,
                                  std::array<uint32_t, HiddenSearch::kMaxPixels>& pixels) const {
  // Candidates: the z-buffer winners of the last projection near where the shot's ray runs in it,
  // from the hit (3x3 around it, p0) along the ray's image towards its vanishing point (parallax
  // when the eye moved), at most kMaxWalk pixels.
  constexpr float kMaxWalk = 8.0f;
  const int w = image_.width, h = image_.height;
  int listed = 0;
  auto list = [&](int x, int y) {
    if (x >= 0 && y >= 0 && x < w && y < h) pixels[size_t(listed++)] = uint32_t(image_.index(x, y));
  };
  // In front, and near the image (a hit close to the last eye's plane projects far away, or to
  // non-finite pixels: converting those to int would be undefined).
  if (!p0.in_front() || !(p0.pixel.x > -2.0f && p0.pixel.y > -2.0f && p0.pixel.x < float(w) + 2.0f &&
                          p0.pixel.y < float(h) + 2.0f))
    return 0;
  const int x0 = int(std::floor(p0.pixel.x)), y0 = int(std::floor(p0.pixel.y));
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) list(x0 + dx, y0 + dy);
  const glm::vec3 dir = shot.ray(r.x, r.y).direction;
  const Projection p1 = last_frame_->project(last_frame_->eye() + dir * background_depth_);
  if (!p1.in_front()) return listed;
  glm::vec2 d = p1.pixel - p0.pixel;
  if (!std::isfinite(d.x) || !std::isfinite(d.y)) return listed;
  const float length = std::min(glm::length(d), kMaxWalk);
  if (!(length >= 1.0f)) return listed;
  d = glm::normalize(d);
  int last_x = x0, last_y = y0;
  for (float t = 0.5f; t <= length; t += 0.5f) {
    const glm::vec2 c = p0.pixel + d * t;
    const int x = int(std::floor(c.x)), y = int(std::floor(c.y));
    if (x == last_x && y == last_y) continue;
    last_x = x, last_y = y;
    if (std::abs(x - x0) <= 1 && std::abs(y - y0) <= 1) continue;
    list(x, y);
  }
  return listed;
}

void PointCache::first_hidden(const ViewFrame& shot, const ShadeResult& r, std::span<const glm::mat4> object_to_world,
                              int listed, HiddenSearch& search) const {
  constexpr float kRadius = 0.35f;  // the ray's evidence covers this far around it, pixels
  constexpr float kMargin = 0.05f;  // relative depth behind the hit
  const Projection hit_shot = shot.project(r.position);
  const glm::vec2 sample(r.x, r.y);
  auto hidden = [&](int32_t q) {
    if (q < 0) return false;
    const CachePoint& p = points_[size_t(q)];
    if (!p.valid || p.age == 0) return false;
    const Projection pq = shot.project(world_position(p, shot, object_to_world));
    return pq.depth > hit_shot.depth * (1.0f + kMargin) && glm::distance(pq.pixel, sample) <= kRadius;
  };
  search.found = -1, search.count = listed;
  for (int k = 0; k < listed; ++k)
    if (const int32_t q = winners_[search.pixels[size_t(k)]]; hidden(q)) {
      search.found = q, search.count = k + 1;
      return;
    }
}

void PointCache::prepare_result(const ViewFrame& shot, const ShadeResult& r, std::span<const glm::mat4> object_to_world,
                                uint16_t epoch, bool search_hidden, PreparedResult& out) const {
  CachePoint& point = out.point;
  PointColour& colour = out.colour;
  point = CachePoint{}, colour = PointColour{};
  colour.color = glm::max(r.color, glm::vec3(0.0f));
  colour.view_dependent = glm::clamp(r.view_dependent, glm::vec3(0.0f), colour.color);
  colour.epoch = epoch;
  colour.weight = std::max<uint16_t>(r.effort, 1);
  // A punctual highlight kept apart: the colour keeps the rest.
  out.highlight = PunctualHighlight{};
  const float highlight = luminance(r.punctual_specular);
  if (highlight_model_ && r.hit && r.object < object_to_world.size() && r.punctual_lights != 0 && highlight > 0.0f &&
      highlight >= settings_.punctual_highlight_share * luminance(colour.color)) {
    colour.color = glm::max(colour.color - r.punctual_specular, glm::vec3(0.0f));
    colour.view_dependent = glm::clamp(colour.view_dependent - r.punctual_specular, glm::vec3(0.0f), colour.color);
    out.highlight = {pack_unit(glm::transpose(glm::mat3(object_to_world[r.object])) * r.shading_normal), r.punctual_lights, r.material};
  }
  // The diffuse part is kept divided by the shading view's transmission (its byte in srgb, at
  // least 13/255: nearer grazing the division would amplify what the shading normal and the
  // geometric one disagree on), so that results from different views average to one quantity.
  if (r.hit && r.object < object_to_world.size() && r.diffuse_transmission > 0.0f) {
    const uint32_t then = uint32_t(std::clamp(std::lround(r.diffuse_transmission * 255.0f), 13l, 255l));
    point.srgb = then << 24;
    colour.color = colour.view_dependent + (colour.color - colour.view_dependent) / (float(then) / 255.0f);
  }
  update_from_colour(point, colour);
  point.lobe_width = r.hit ? r.lobe_width : 0.0f;
  point.view = r.hit ? pack_unit(shot.eye() - r.position) : 0;
  point.valid = true;
  if (r.hit && r.object < object_to_world.size()) {
    point.object = r.object;
    point.local = glm::vec3(to_object_[r.object] * glm::vec4(r.position, 1.0f));
    // Normals go to object space with the transpose of the object-to-world matrix.
    point.normal = pack_unit(glm::transpose(glm::mat3(object_to_world[r.object])) * r.normal);
    // Where the point was at the last projection (its object may have moved since the shot).
    out.world = r.object < last_transforms_.size() ? glm::vec3(last_transforms_[r.object] * glm::vec4(point.local, 1.0f))
                                                   : r.position;
  } else {
    point.object = kNone;
    point.local = shot.ray(r.x, r.y).direction;
    out.world = shot.eye() + point.local * background_depth_;
  }
  out.last_pixel = -1, out.listed = 0;
  if (last_frame_) {
    out.last = last_frame_->project(out.world);
    const Projection& p = out.last;
    const int w = image_.width, h = image_.height;
    if (p.in_front() && p.pixel.x >= 0.0f && p.pixel.y >= 0.0f && p.pixel.x < float(w) && p.pixel.y < float(h))
      out.last_pixel = int32_t(image_.index(std::min(w - 1, int(p.pixel.x)), std::min(h - 1, int(p.pixel.y))));
  }
  // The hidden point's search: its pixels listed here, read by first_hidden (insert).
  out.hidden.found = -1, out.hidden.count = 0;
  if (search_hidden && last_frame_ && r.hit && point.object != kNone)
    out.listed = hidden_candidates(shot, r, out.last, out.hidden.pixels);
}

bool PointCache::search_outdated(const HiddenSearch& search) const {
  for (int k = 0; k < search.count; ++k) {
    const uint32_t pixel = search.pixels[size_t(k)];
    const int32_t winner = winners_[pixel];
    if (pixel_touched_[pixel] || (winner >= 0 && slot_touched_[size_t(winner)])) return true;
  }
  return false;
}

size_t PointCache::insert(const ViewFrame& shot, const ShadeBatch& batch, std::span<const glm::mat4> object_to_world,
                          uint16_t epoch) {
  pixel_words_current_ = false;  // ages and colours may change
  to_object_.resize(object_to_world.size());
  for (size_t k = 0; k < object_to_world.size(); ++k) to_object_[k] = glm::inverse(object_to_world[k]);
  const int w = image_.width, h = image_.height;
  if (free_slots_.size() < batch.results.size()) choose_evict_age(batch.results.size() - free_slots_.size());

  // First, each result on its own, in parallel: its point, and (the fast path) the hidden point
  // its ray shows, searched in the cloud as the batch found it. Then the results in order, as one
  // serial loop would take them: a search that read a winner or a record an earlier result has
  // changed since is made again, so the cache ends as the serial loop leaves it (docs/render.md,
  // "Points": insertion in two phases).
  const bool search_ahead = !settings_.reference_path;
  const size_t results = batch.results.size();
  prepared_.resize(results);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, results, 256), [&](const tbb::blocked_range<size_t>& range) {
    // A few results at a time, each step over all of them: their points and the pixels their
    // searches may read, then those pixels' winners, then the winners' records (both read at
    // random: each step prefetches what the next reads, so the misses overlap), then the verdicts.
    constexpr size_t kChunk = 16;
    for (size_t c = range.begin(); c < range.end(); c += kChunk) {
      const size_t e = std::min(c + kChunk, range.end());
      for (size_t k = c; k < e; ++k) {
        prepare_result(shot, batch.results[k], object_to_world, epoch, search_ahead, prepared_[k]);
        for (int i = 0; i < prepared_[k].listed; ++i) __builtin_prefetch(&winners_[prepared_[k].hidden.pixels[size_t(i)]]);
      }
      for (size_t k = c; k < e; ++k)
        for (int i = 0; i < prepared_[k].listed; ++i)
          if (const int32_t q = winners_[prepared_[k].hidden.pixels[size_t(i)]]; q >= 0) __builtin_prefetch(&points_[size_t(q)]);
      for (size_t k = c; k < e; ++k)
        if (prepared_[k].listed > 0) first_hidden(shot, batch.results[k], object_to_world, prepared_[k].listed, prepared_[k].hidden);
    }
  });
  slot_touched_.resize(points_.size());
  pixel_touched_.resize(winners_.size());
  auto touch_pixel = [&](size_t pixel) {
    if (!pixel_touched_[pixel]) pixel_touched_[pixel] = 1, touched_pixels_.push_back(uint32_t(pixel));
  };

  size_t inserted = 0;
  for (size_t k = 0; k < results; ++k) {
    // The records this loop reads lie at random: the pixels a result lands in are prefetched 32
    // results ahead, the points they hold 16 ahead (results in between may change which: only a
    // prefetch). Written in the loop: GCC 12 dropped the calls to a lambda holding only these.
    if (k + 32 < results)
      if (const int32_t pixel = prepared_[k + 32].last_pixel; pixel >= 0) {
        __builtin_prefetch(&image_.point[size_t(pixel)]);
        __builtin_prefetch(&image_.depth[size_t(pixel)]);
        __builtin_prefetch(&winners_[size_t(pixel)]);
      }
    if (k + 16 < results) {
      const PreparedResult& next = prepared_[k + 16];
      if (next.last_pixel >= 0) {
        if (const int32_t old = image_.point[size_t(next.last_pixel)]; old >= 0)
          __builtin_prefetch(&points_[size_t(old)]), __builtin_prefetch(&colours_[size_t(old)]);
        if (const int32_t winner = winners_[size_t(next.last_pixel)]; winner >= 0) __builtin_prefetch(&points_[size_t(winner)]);
      }
      if (next.hidden.found >= 0) __builtin_prefetch(&points_[size_t(next.hidden.found)]);
    }
    const ShadeResult& r = batch.results[k];
    const CachePoint& point = prepared_[k].point;
    const PointColour& colour = prepared_[k].colour;
    const glm::vec3 world = prepared_[k].world;

    // The point drawn where this result lands in the last projection: replaced if it is the same surface.
    int32_t replace = -1;
    bool in_front_of_drawn = false;  // a new occluder (PointCacheSettings::new_occluder_radius)
    if (last_frame_) {
      const Projection& proj = prepared_[k].last;
      if (prepared_[k].last_pixel >= 0) {
        const size_t pixel = size_t(prepared_[k].last_pixel);
        const int32_t old = image_.point[pixel];
        // The z-buffer's winner, before the culls: where the occlusion test emptied a pixel behind a
        // new occluder's earlier samples, the result still lands in front of what was there.
        // (Where the winner is still drawn, the image holds its depth: no projection needed.)
        const int32_t winner = winners_[pixel];
        if (winner >= 0 && r.hit && point.object != kNone && points_[size_t(winner)].valid && points_[size_t(winner)].age != 0) {
          const float winner_depth =
              old == winner ? image_.depth[pixel]
                            : last_frame_->project(world_position(points_[size_t(winner)], *last_frame_, last_transforms_)).depth;
          in_front_of_drawn = proj.depth * (1.0f + kNewOccluderMargin) < winner_depth;
        }
        // (age 0: the slot was given to a result since the projection: not the point drawn there)
        if (old >= 0 && points_[size_t(old)].valid && points_[size_t(old)].age != 0 &&
            points_[size_t(old)].object == point.object &&
            (point.object == kNone || std::abs(image_.depth[pixel] - proj.depth) <= 0.05f * proj.depth)) {
          replace = old;
          CachePoint& cached = points_[size_t(old)];
          PointColour& stats = colours_[size_t(old)];
          const bool alike = has_highlight(size_t(old)) == (prepared_[k].highlight.lights != 0);  // the same quantity
          if ((no_refine_.size() != image_.point.size() || !no_refine_[pixel]) && alike && refines(cached, stats, point, colour)) {
            // The same surface point under the same placement: one more sample of the same
            // quantity. A running mean (Welford for the luminance's variance), not a replacement.
            // Weighted by effort (a result of effort w counts as w results of effort 1; with
            // every effort 1, the plain running mean's arithmetic).
            const float w = float(colour.weight), n = float(stats.weight) + w;
            const float before = luminance(stats.color);
            stats.color += (colour.color - stats.color) * w / n;
            stats.view_dependent += (colour.view_dependent - stats.view_dependent) * w / n;
            stats.luminance_m2 += w * (luminance(colour.color) - before) * (luminance(colour.color) - luminance(stats.color));
            stats.count = uint16_t(std::min<int>(stats.count + 1, 0xffff));
            stats.weight = uint16_t(std::min<int>(stats.weight + colour.weight, 0xffff));
            update_from_colour(cached, stats);
            if (!highlights_.empty()) set_highlight(size_t(old), prepared_[k].highlight);
            cached.age = 0;
            touch_slot(size_t(old));
            ++refined_;
            ++inserted;
            continue;
          }
          if (stats.epoch != colour.epoch && shading_changed(stats.color, colour.color, settings_.change_threshold)) {
            const int r0 = settings_.change_radius, px = int(pixel % size_t(w)), py = int(pixel / size_t(w));
            for (int qy = std::max(0, py - r0); qy <= std::min(h - 1, py + r0); ++qy)
              for (int qx = std::max(0, px - r0); qx <= std::min(w - 1, px + r0); ++qx) {
                const int32_t q = image_.point[image_.index(qx, qy)];
                if (q >= 0) {
                  points_[size_t(q)].age = uint16_t(std::min(points_[size_t(q)].age + settings_.change_penalty, 0xffff));
                  touch_slot(size_t(q));  // (implied today: a search asks only whether an age is 0)
                }
              }
          }
        }
      } else {
        // Outside the last projection's image: a surface coming into view (an object sweeping in
        // from the image's side) stands in front of whatever this projection draws there.
        in_front_of_drawn = r.hit && point.object != kNone;
      }
      // The ray is evidence that what lies behind its hit along it is hidden from the shot's eye:
      // a point of the last projection there (within kRadius of the ray, farther by a margin)
      // gives its slot to this result (or is freed when the result already has one).
      if (r.hit && point.object != kNone) {
        const HiddenSearch& ahead = prepared_[k].hidden;
        const int32_t hidden =
            search_ahead && !search_outdated(ahead) ? ahead.found : find_hidden(shot, r, world, object_to_world);
        if (hidden >= 0) {
          CachePoint& q = points_[size_t(hidden)];
          touch_slot(size_t(hidden));  // (implied today by its pixel's flag below, or by its slot's reuse)
          if (q.image_id >= 0 && winners_[size_t(q.image_id)] == hidden) {
            winners_[size_t(q.image_id)] = -1;
            touch_pixel(size_t(q.image_id));
            image_.point[size_t(q.image_id)] = -1;
          }
          ++hidden_removed_;
          if (replace < 0) {
            replace = hidden;
          } else {
            q.valid = false, q.image_id = -1;
            --valid_points_;
            free_slots_.push_back(uint32_t(hidden));
          }
        }
      }
    }
    const size_t slot = replace >= 0 ? size_t(replace) : take_slot();
    touch_slot(slot);
    valid_points_ += size_t(!points_[slot].valid);
    points_[slot] = point, colours_[slot] = colour;
    if (!highlights_.empty()) set_highlight(slot, prepared_[k].highlight);
    seeded_at_[slot] = in_front_of_drawn ? projections_ + 1 : 0;
    if (in_front_of_drawn && new_occluder_rule()) recent_occluders_.push_back({uint32_t(slot), projections_ + 1});
    ++inserted;
  }
  for (const uint32_t slot : touched_slots_) slot_touched_[slot] = 0;
  for (const uint32_t pixel : touched_pixels_) pixel_touched_[pixel] = 0;
  touched_slots_.clear(), touched_pixels_.clear();
  return inserted;
}

bool PointCache::refines(const CachePoint& cached, const PointColour& cached_colour, const CachePoint& result,
                         const PointColour& result_colour) const {
  if (!settings_.refine || cached_colour.epoch != result_colour.epoch || cached.object != result.object ||
      result.object == kNone)
    return false;
  if (cached_colour.count == 0xffff || int(cached_colour.weight) + int(result_colour.weight) > 0xffff) return false;
  // View-dependent shading is one quantity only from about the same direction.
  const float total = luminance(result_colour.color) + luminance(cached_colour.color);
  const float share =
      total > 0.0f ? (luminance(result_colour.view_dependent) + luminance(cached_colour.view_dependent)) / total : 0.0f;
  if (share > 0.05f && result.lobe_width > 0.0f) {
    const float turned = std::acos(std::clamp(glm::dot(unpack_unit(cached.view), unpack_unit(result.view)), -1.0f, 1.0f));
    if (turned > 0.1f * std::max(result.lobe_width, kMinLobeWidth)) return false;
  }
  return true;
}

bool PointCache::stray_background(const EdgeCrossings& crossings, int x, int y) const {
  const size_t i = image_.index(x, y);
  const int r = stray_background_radius();
  // The point's record last: most background pixels near a surface have its outline near.
  return image_.depth[i] >= background_depth_ * kBackgroundDepthShare && !crossings.any_piece_near(x - r, y - r, x + r, y + r) &&
         points_[size_t(image_.point[i])].object == kNone;
}

bool PointCache::hidden_behind_a_neighbour(const ViewFrame& frame, std::span<const glm::mat4> object_to_world,
                                           const EdgeCrossings& crossings, int x, int y, bool dense_window,
                                           bool sparse_ring, bool occluder_ring, bool background_ring) const {
  const int w = image_.width, h = image_.height, dense = std::max(1, settings_.occlusion_radius);
  const int radius = std::max(dense, settings_.sparse_occlusion_radius);
  const float scale = 1.0f + settings_.occlusion_margin;
  const size_t i = image_.index(x, y);
  const float depth = image_.depth[i];

  // Where a drawn point lies in the image, exactly (the image keeps only its 4x4 region).
  auto position = [&](size_t pixel) {
    return glm::dvec2(frame.project(world_position(points_[size_t(image_.point[pixel])], frame, object_to_world)).pixel);
  };
  Ray ray;
  float ray_depth = 0.0f;  // depth per unit along the ray; the ray is made when first needed
  glm::dvec2 at_p{0.0};
  // Whether p lies behind the tangent plane of the nearer point at q with no edge between them.
  auto behind = [&](size_t q) {
    const CachePoint& near = points_[size_t(image_.point[q])];
    if (near.object == kNone || near.object >= object_to_world.size()) return false;
    if (ray_depth == 0.0f) {
      at_p = position(i);
      ray = frame.ray(float(at_p.x), float(at_p.y));
      ray_depth = glm::dot(ray.direction, frame.forward());
    }
    // Depth of the near point's tangent plane along p's ray; a plane seen edge-on predicts nothing.
    const glm::vec3 n = glm::normalize(normal_to_world_[near.object] * unpack_unit(near.normal));
    const glm::vec3 at = glm::vec3(object_to_world[near.object] * glm::vec4(near.local, 1.0f));
    const float facing = glm::dot(n, ray.direction);
    if (std::abs(facing) < 0.1f) return false;
    const float plane_depth = glm::dot(n, at - ray.origin) / facing * ray_depth;
    if (!(plane_depth > 0.0f) || !(depth > plane_depth * scale)) return false;
    // Hidden unless a silhouette, border or sharp edge passes between the two points. Between a
    // new occluder and p only an edge nearer than halfway between their depths counts: one
    // farther lies behind the surface that has just come in front (the far objects' own
    // silhouettes), where the occluder's own edges lie near its depth (docs/render.md, "New occluders").
    const double edge_limit = new_occluder(size_t(image_.point[q])) ? 0.5 * (double(depth) + double(image_.depth[q]))
                                                                    : std::numeric_limits<double>::infinity();
    return !crossings.separated(at_p, position(q), edge_limit);
  };
  // The nearer points' records lie in the cloud at random: a window's are listed and prefetched
  // before any is read, so that their cache misses overlap (the verdict, whether any of them
  // hides p, does not depend on the order; the first hit ends the test).
  constexpr size_t kListed = 64;
  uint32_t listed[kListed];
  size_t count = 0;
  auto any_behind = [&] {
    __builtin_prefetch(&points_[size_t(image_.point[i])]);  // p's own, for its exact position
    for (size_t k = 0; k < count; ++k) __builtin_prefetch(&points_[size_t(image_.point[listed[k]])]);
    const size_t n = count;
    count = 0;
    for (size_t k = 0; k < n; ++k)
      if (behind(listed[k])) return true;
    return false;
  };
  auto consider = [&](size_t q) {  // true: q hides p, or one listed before it does
    listed[count++] = uint32_t(q);
    return count == kListed && any_behind();
  };
  // Each window row is tested in one branch-free pass into a bit mask (bit k: the pixel q0 + k),
  // then its set bits are considered in ascending order: the same points in the same order as a
  // pixel-by-pixel scan, without a branch per pixel (most of a window holds no nearer point).
  auto consider_bits = [&](size_t q0, uint32_t bits) {
    for (; bits != 0; bits &= bits - 1)
      if (consider(q0 + size_t(std::countr_zero(bits)))) return true;
    return false;
  };
  // The drawn points nearer than p by the margin among the n pixels from q0, as a mask.
  auto nearer_bits = [&, point = image_.point.data(), depths = image_.depth.data()](size_t q0, int n) {
    uint32_t bits = 0;
    for (int k = 0; k < n; ++k) bits |= uint32_t((point[q0 + size_t(k)] >= 0) & (depths[q0 + size_t(k)] * scale < depth)) << k;
    return bits;
  };
  if (dense_window) {
    const int x0 = std::max(0, x - dense), x1 = std::min(w - 1, x + dense);
    for (int qy = std::max(0, y - dense); qy <= std::min(h - 1, y + dense); ++qy) {
      const size_t q0 = image_.index(x0, qy);
      if (consider_bits(q0, nearer_bits(q0, x1 - x0 + 1))) return true;
    }
    if (any_behind()) return true;
  }
  if (radius == dense) return false;
  if (background_ring && stray_background(crossings, x, y)) {
    // A stray background point (where a surface the camera has just revealed is sampled sparsely
    // among the background points it used to show): every nearer point of a wider window
    // counts, not only the lone ones. The window holds the rings below (lone points, new occluders).
    const int r = stray_background_radius();
    const int bx0 = std::max(0, x - r), bx1 = std::min(w - 1, x + r);
    uint32_t skip = 0;  // the dense window's columns in its rows
    for (int qx = std::max(bx0, x - dense); qx <= std::min(bx1, x + dense); ++qx) skip |= uint32_t(1) << (qx - bx0);
    for (int qy = std::max(0, y - r); qy <= std::min(h - 1, y + r); ++qy) {
      const size_t q0 = image_.index(bx0, qy);
      if (consider_bits(q0, nearer_bits(q0, bx1 - bx0 + 1) & ~(std::abs(qy - y) <= dense ? skip : 0))) return true;
    }
    return any_behind();
  }
  if (!sparse_ring) return false;
  const int x0 = std::max(0, x - radius), x1 = std::min(w - 1, x + radius);
  const int y0 = std::max(0, y - radius), y1 = std::min(h - 1, y + radius);
  // The dense window's columns, skipped in its rows (tested above, or not wanted).
  uint32_t inner = 0;
  for (int qx = std::max(x0, x - dense); qx <= std::min(x1, x + dense); ++qx) inner |= uint32_t(1) << (qx - x0);
  // Beyond the dense radius a nearer point counts only where it stands alone: no other drawn
  // point in its 3x3 is nearer than this one by the margin (mark_alone; alone_depth_ is +inf
  // where no point is, or none that could stand alone).
  uint32_t masks[2 * kMaxOcclusionRadius + 1];
  lone_window_masks(&alone_depth_[image_.index(x0, y0)], &neighbour_min_depth_[image_.index(x0, y0)], size_t(w),
                    y1 - y0 + 1, x1 - x0 + 1, scale, depth, masks);
  for (int qy = y0; qy <= y1; ++qy)
    if (consider_bits(image_.index(x0, qy), masks[qy - y0] & ~(std::abs(qy - y) <= dense ? inner : 0))) return true;
  if (any_behind()) return true;
  if (!occluder_ring || !any_new_occluder_) return false;
  // Beyond the sparse radius, up to new_occluder_radius: the lone points that are new occluders
  // (mark_alone's occluder_depth_), the sparse window's pixels skipped (tested above).
  const int far = settings_.new_occluder_radius;
  const int fx0 = std::max(0, x - far), fx1 = std::min(w - 1, x + far);
  const int fy0 = std::max(0, y - far), fy1 = std::min(h - 1, y + far);
  lone_window_masks(&occluder_depth_[image_.index(fx0, fy0)], &neighbour_min_depth_[image_.index(fx0, fy0)], size_t(w),
                    fy1 - fy0 + 1, fx1 - fx0 + 1, scale, depth, masks);
  uint32_t sparse_columns = 0;
  for (int qx = x0; qx <= x1; ++qx) sparse_columns |= uint32_t(1) << (qx - fx0);
  for (int qy = fy0; qy <= fy1; ++qy)
    if (consider_bits(image_.index(fx0, qy), masks[qy - fy0] & ~(qy >= y0 && qy <= y1 ? sparse_columns : 0))) return true;
  return any_behind();
}

size_t PointCache::cull_behind_surfaces(const ViewFrame& frame, std::span<const glm::mat4> object_to_world,
                                        const EdgeCrossings& crossings) {
  if (settings_.reference_path) return cull_behind_surfaces_reference(frame, object_to_world, crossings);
  const int radius = std::max(1, settings_.occlusion_radius);
  const float scale = 1.0f + settings_.occlusion_margin;
  // The nearest depth in each pixel's window: a pixel with no neighbour nearer by the margin
  // (most of them) is skipped without looking at its neighbours. Farther than the dense radius,
  // only the points that stand alone count: the least depth of those over the sparse radius.
  window_min_depth(radius);
  const bool sparse = mark_alone();
  if (sparse) window_min(alone_depth_, settings_.sparse_occlusion_radius, sparse_min_depth_);
  // Stray background points (stray_background; the rule needs the sparse one): where a nearer
  // point may lie within their window. Most frames of closed scenes draw no background point:
  // then nothing of it is computed.
  const float background_floor = background_depth_ * kBackgroundDepthShare;
  const bool strays = sparse && any_drawn_deeper(background_floor);
  stray_cell_minima(strays);
  near_occluders(sparse && any_new_occluder_);
  // The test sees the image before the pass: hidden pixels are listed per band, removed after.
  const float *depth = image_.depth.data(), *min_depth = min_depth_.data();
  const float* sparse_min = sparse ? sparse_min_depth_.data() : min_depth;
  const float* occluder_near = occluder_near_.data();
  const int32_t* point = image_.point.data();
  // A background-deep point with a nearer point in the cells around its own: stray_background decides.
  const float* stray_near = strays ? stray_near_.data() : nullptr;
  const size_t w = size_t(image_.width);
  auto background_ring = [=](size_t i, int x, int y) {
    return (depth[i] >= background_floor) & (stray_near[size_t(y >> kStrayCellShift) * w + size_t(x)] * scale < depth[i]);
  };
  // Two forms of the pass, with and without the stray rule's candidates.
  auto pass = [&](auto with_strays) {
    for_candidates([=](size_t i, int x, int y) {
      bool candidate = std::min({min_depth[i], sparse_min[i], occluder_near[i]}) * scale < depth[i];
      if constexpr (with_strays) candidate |= background_ring(i, x, y);
      return candidate & (point[i] >= 0);
    }, [&](int x, int y, std::vector<uint32_t>& hidden) {
      // A window whose least depth is not nearer by the margin cannot hold the nearer point.
      const size_t i = image_.index(x, y);
      const bool occluder_ring = occluder_near[i] * scale < depth[i];
      if (hidden_behind_a_neighbour(frame, object_to_world, crossings, x, y, min_depth[i] * scale < depth[i],
                                    sparse_min[i] * scale < depth[i] || occluder_ring, occluder_ring,
                                    with_strays && background_ring(i, x, y)))
        hidden.push_back(uint32_t(i));
    }, [&](size_t i) { __builtin_prefetch(&points_[size_t(point[i])]); });  // the record p's exact position is made from
  };
  if (strays) {
    pass(std::true_type{});
  } else {
    pass(std::false_type{});
  }
  return remove_listed();
}

bool PointCache::any_drawn_deeper(float floor) const {
  // Bands in parallel, each a plain branch-free loop (empty pixels are +inf deep).
  std::atomic<bool> found{false};
  const int w = image_.width;
  tbb::parallel_for(tbb::blocked_range<int>(0, image_.height, 64), [&](const tbb::blocked_range<int>& rows) {
    if (found.load(std::memory_order_relaxed)) return;
    const float* depth = &image_.depth[image_.index(0, rows.begin())];
    const size_t n = size_t(rows.size()) * size_t(w);
    bool any = false;
    for (size_t i = 0; i < n; ++i) any |= (depth[i] >= floor) & (depth[i] < std::numeric_limits<float>::infinity());
    if (any) found.store(true, std::memory_order_relaxed);
  });
  return found.load();
}

void PointCache::stray_cell_minima(bool any) {
  // Per band of 2^kStrayCellShift rows and per pixel column: at most the least depth within the
  // stray window's radius of any pixel of the band in that column (a superset of the candidates
  // is fine: the window scan decides). From min_depth_ (windows of the occlusion radius, made
  // first by cull_behind_surfaces) on rows whose windows hold the band, then windows along rows
  // (row_window_min) and the bands within reach.
  if (!any) return;  // cull_behind_surfaces reads none of it
  const int w = image_.width, h = image_.height, side = 1 << kStrayCellShift, r = stray_background_radius();
  const int bands = (h + side - 1) / side, k = (r + side - 1) / side;
  // The rows of a band whose windows hold it: its middle row (radius 2 or more), or rows 1 and 3.
  static_assert(1 << kStrayCellShift == 4);
  const bool one_row = std::max(1, settings_.occlusion_radius) >= 2;
  const int at[2] = {one_row ? 2 : 1, 3};
  stray_cells_.resize(size_t(bands) * size_t(w)), stray_near_.resize(stray_cells_.size());
  tbb::parallel_for(0, bands, [&](int b) {
    const float* rows[2];
    for (int j = 0; j < 2; ++j) rows[j] = &min_depth_[image_.index(0, std::min(h - 1, b * side + at[j]))];
    float* near = &stray_near_[size_t(b) * size_t(w)];
    rows_min(rows, one_row ? 1 : 2, near, w);
    row_window_min(near, &stray_cells_[size_t(b) * size_t(w)], w, r);
  });
  tbb::parallel_for(0, bands, [&](int b) {
    const float* rows[2 * kMaxOcclusionRadius + 1];
    int count = 0;
    for (int n = std::max(0, b - k); n <= std::min(bands - 1, b + k); ++n) rows[count++] = &stray_cells_[size_t(n) * size_t(w)];
    rows_min(rows, count, &stray_near_[size_t(b) * size_t(w)], w);
  });
}

void PointCache::near_occluders(bool any) {
  // New occluders are few: each one's depth goes to the 3x3 cells around its own (cells of 8 or
  // 16 pixels, at least the radius: they hold every pixel within it), and each cell so reached is
  // filled with its least depth. Only the cells reached last time are reset, and nothing else of
  // the plane is touched: no pass over the image.
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const int w = image_.width, h = image_.height, shift = settings_.new_occluder_radius <= 8 ? 3 : 4;
  const int cells_x = ((w - 1) >> shift) + 1, cells_y = ((h - 1) >> shift) + 1;
  occluder_near_.resize(image_.point.size(), kInf);
  occluder_cells_.resize(size_t(cells_x) * size_t(cells_y), kInf);
  auto fill = [&](uint32_t cell, float value) {
    const int cx = int(cell % uint32_t(cells_x)) << shift, cy = int(cell / uint32_t(cells_x)) << shift;
    for (int y = cy; y < std::min(h, cy + (1 << shift)); ++y)
      std::fill_n(&occluder_near_[image_.index(cx, y)], std::min(w, cx + (1 << shift)) - cx, value);
  };
  for (const uint32_t cell : occluder_cells_reached_) fill(cell, kInf), occluder_cells_[cell] = kInf;
  occluder_cells_reached_.clear();
  if (!any) return;
  for (const uint32_t i : occluder_pixels_) {
    const int cx = int(i % uint32_t(w)) >> shift, cy = int(i / uint32_t(w)) >> shift;
    for (int ny = std::max(0, cy - 1); ny <= std::min(cells_y - 1, cy + 1); ++ny)
      for (int nx = std::max(0, cx - 1); nx <= std::min(cells_x - 1, cx + 1); ++nx) {
        const uint32_t cell = uint32_t(ny * cells_x + nx);
        if (occluder_cells_[cell] == kInf) occluder_cells_reached_.push_back(cell);
        occluder_cells_[cell] = std::min(occluder_cells_[cell], occluder_depth_[i]);
      }
  }
  for (const uint32_t cell : occluder_cells_reached_) fill(cell, occluder_cells_[cell]);
}

bool PointCache::mark_alone() {
  const int w = image_.width, h = image_.height;
  const size_t n = image_.point.size();
  any_new_occluder_ = false;
  if (settings_.sparse_occlusion_radius <= std::max(1, settings_.occlusion_radius)) return false;
  // Padded: lone_window_masks reads past a window's last pixel (the padding's values are unused).
  constexpr float kInf = std::numeric_limits<float>::infinity();
  neighbour_min_depth_.resize(n + kWindowPad, kInf), alone_depth_.resize(n + kWindowPad, kInf);
  // A point can stand alone for some farther point only if it is nearer than all the other points
  // of its 3x3 (empty pixels: +inf either way).
  tbb::parallel_for(tbb::blocked_range<int>(0, h, kBandRows), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      lone_depths(y > 0 ? &image_.depth[image_.index(0, y - 1)] : nullptr, &image_.depth[image_.index(0, y)],
                  y + 1 < h ? &image_.depth[image_.index(0, y + 1)] : nullptr, &neighbour_min_depth_[image_.index(0, y)],
                  &alone_depth_[image_.index(0, y)], w);
  });
  // New occluders: of the results marked in the last new_occluder_frames projections (project keeps
  // that list), those drawn and standing alone; the last frame's are reset first.
  for (const uint32_t i : occluder_pixels_) occluder_depth_[i] = kInf;
  occluder_pixels_.clear();
  if (!new_occluder_rule()) return true;
  occluder_depth_.resize(n + kWindowPad, kInf);
  for (const auto& [slot, stamp] : recent_occluders_) {
    const int32_t pixel = points_[slot].image_id;
    if (points_[slot].valid && pixel >= 0 && image_.point[size_t(pixel)] == int32_t(slot) && alone_depth_[size_t(pixel)] != kInf) {
      occluder_depth_[size_t(pixel)] = alone_depth_[size_t(pixel)];
      occluder_pixels_.push_back(uint32_t(pixel));
    }
  }
  any_new_occluder_ = !occluder_pixels_.empty();
  return true;
}

void PointCache::window_min_depth(int radius) { window_min(image_.depth, radius, min_depth_); }

void PointCache::window_min(const std::vector<float>& depth, int radius, std::vector<float>& min_depth) {
  const int w = image_.width, h = image_.height;
  min_depth.resize(depth.size());
  // Bands of rows in parallel, each keeping the row minima of the 2r + 1 rows its current output
  // row reads in a ring of its own (cache-resident: no image-sized intermediate goes through
  // memory); a band recomputes the r rows beyond each of its ends. The minimum of depths, never
  // NaN, does not depend on the order, so the result is that of any other order.
  constexpr int kRows = 32;
  const int span = 2 * radius + 1;
  min_rings_.resize(size_t((h + kRows - 1) / kRows));
  tbb::parallel_for(0, int(min_rings_.size()), [&](int band) {
    std::vector<float>& ring = min_rings_[size_t(band)];
    ring.resize(size_t(span) * size_t(w));
    auto ring_row = [&](int y) { return ring.data() + size_t(y % span) * size_t(w); };
    const int y0 = band * kRows, y1 = std::min(h, y0 + kRows);
    int next = std::max(0, y0 - radius);  // the next row to take into the ring
    for (int y = y0; y < y1; ++y) {
      for (; next <= std::min(h - 1, y + radius); ++next) row_window_min(&depth[image_.index(0, next)], ring_row(next), w, radius);
      const float* rows[2 * kMaxOcclusionRadius + 1];
      int count = 0;
      for (int qy = std::max(0, y - radius); qy <= std::min(h - 1, y + radius); ++qy) rows[count++] = ring_row(qy);
      rows_min(rows, count, &min_depth[image_.index(0, y)], w);
    }
  });
}

template <class BandPass>
void PointCache::for_bands(int height, const BandPass& pass) {
  band_lists_.resize(size_t((height + kBandRows - 1) / kBandRows));
  tbb::parallel_for(size_t(0), band_lists_.size(), [&](size_t b) {
    band_lists_[b].clear();
    pass(int(b) * kBandRows, std::min(height, int(b + 1) * kBandRows), band_lists_[b]);
  });
}

template <class Candidate, class Visit, class Ahead>
void PointCache::for_candidates(const Candidate& candidate, const Visit& visit, const Ahead& ahead) {
  const int w = image_.width;
  constexpr int kChunk = 256;
  for_bands(image_.height, [&](int y0, int y1, std::vector<uint32_t>& list) {
    for (int y = y0; y != y1; ++y)
      for (int x0 = 0; x0 < w; x0 += kChunk) {
        const int n = std::min(kChunk, w - x0);
        const size_t row = image_.index(x0, y);
        std::array<uint8_t, kChunk + 8> flags{};  // zero past n
        for (int k = 0; k < n; ++k) flags[size_t(k)] = uint8_t(candidate(row + size_t(k), x0 + k, y));
        std::array<uint16_t, kChunk> found;  // the chunk's candidates, in order
        size_t count = 0;
        for (int k = 0; k < n; k += 8) {
          uint64_t any;
          std::memcpy(&any, &flags[size_t(k)], 8);
          if (any == 0) continue;
          for (int j = k; j < std::min(n, k + 8); ++j)
            if (flags[size_t(j)]) found[count++] = uint16_t(j);
        }
        for (size_t c = 0; c < count; ++c) ahead(row + found[c]);
        for (size_t c = 0; c < count; ++c) visit(x0 + int(found[c]), y, list);
      }
  });
}

size_t PointCache::remove_listed() {
  size_t removed = 0;
  for (const std::vector<uint32_t>& list : band_lists_) {
    for (const uint32_t i : list) image_.point[i] = -1, image_.depth[i] = std::numeric_limits<float>::infinity();
    removed += list.size();
  }
  return removed;
}

uint32_t PointCache::faded_srgb(const CachePoint& p, const PointColour& c, float transmission_now, bool by_steps,
                                const glm::vec3& highlight) const {
  const float fade_span = std::max(settings_.view_fade_end - settings_.view_fade_start, 1e-3f);
  const bool rescaled = (p.srgb >> 24) != 0;
  const bool plain = highlight == glm::vec3(0.0f);
  if (by_steps && plain)
    return faded_colour_word(c.color, c.view_dependent, p.staleness, rescaled, transmission_now, settings_.view_fade_start, fade_span);
  glm::vec3 shown, shown_view;
  faded_colours(c.color, c.view_dependent, p.staleness, rescaled, transmission_now, settings_.view_fade_start, fade_span, shown, shown_view);
  if (!plain) shown += highlight, shown_view += highlight;  // (a highlight is all view-dependent)
  return by_steps ? pack_srgb_by_steps(shown, shown_view) : pack_srgb(shown, shown_view);
}

void PointCache::set_highlight_model(std::optional<PunctualSpecularModel> model) {
  highlight_model_ = std::move(model);
  if (highlight_model_) highlights_.assign(points_.size(), PunctualHighlight{}), highlight_bits_.assign((points_.size() + 63) / 64, 0);
  else highlights_.clear(), highlight_bits_.clear();
}

glm::vec3 PointCache::highlight_now(size_t slot) const {
  if (!has_highlight(slot) || !last_frame_) return glm::vec3(0.0f);
  const CachePoint& p = points_[slot];
  if (p.object >= last_transforms_.size() || p.object >= normal_to_world_.size()) return glm::vec3(0.0f);
  const PunctualHighlight& h = highlights_[slot];
  const glm::mat3& to_world = normal_to_world_[p.object];
  const PunctualSurface surface{glm::vec3(last_transforms_[p.object] * glm::vec4(p.local, 1.0f)),
                                glm::normalize(to_world * unpack_unit(h.shading_normal)),
                                glm::normalize(to_world * unpack_unit(p.normal)), h.material, h.lights};
  return highlight_model_->specular(surface, last_frame_->eye());
}

void PointCache::move_highlight_light(size_t light, const glm::vec3& position) {
  if (highlight_model_ && light < highlight_model_->lights.size()) highlight_model_->lights[light].position = position;
}

float PointCache::transmission_now(const CachePoint& p) const {
  if (p.normal == 0 || p.object >= eye_local_.size()) return 1.0f;
  return diffuse_transmission(facing_cosine(p.normal, eye_local_[p.object] - p.local));
}

void PointCache::fill_epi(EpiImage& epi) const {
  if (settings_.reference_path) return fill_epi_reference(epi);
  if (epi.width != image_.width || epi.height != image_.height)
    throw std::invalid_argument("point cache: EPI size differs from the cache's image size");
  tbb::parallel_for(tbb::blocked_range<size_t>(0, image_.point.size(), 16384), [&](const tbb::blocked_range<size_t>& r) {
    if (pixel_words_current_) {  // a copy, masked without branches (drawn and empty pixels alternate at random)
      const int32_t* const point = image_.point.data();
      const uint16_t* const age_bins = pixel_age_bin_.data();
      const uint8_t* const region = image_.region.data();
      const uint32_t* const words = pixel_word_.data();
      uint16_t* const edge = epi.edge.data();
      uint32_t* const color = epi.color.data();
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const uint32_t shown = uint32_t(0) - (uint32_t(point[i] >= 0) & uint32_t((age_bins[i] & kShowsNothing) == 0));
        edge[i] = uint16_t((uint32_t(region[i]) << bits::kRegionShift | bits::kHasSample) & shown);
        color[i] = words[i] & shown;
      }
      // The punctual highlights, recomputed for this eye (the words hold the rest of the colour):
      // the range's highlighted pixels listed, then their words, the three records each reads (at
      // random) prefetched 8 pixels ahead.
      if (!highlights_.empty()) {
        thread_local std::vector<uint32_t> listed;
        listed.clear();
        for (size_t i = r.begin(); i != r.end(); ++i)
          if ((age_bins[i] & (kHighlighted | kShowsNothing)) == kHighlighted && point[i] >= 0) listed.push_back(uint32_t(i));
        for (size_t k = 0; k < listed.size(); ++k) {
          if (k + 8 < listed.size()) {
            const size_t ahead = size_t(point[listed[k + 8]]);
            __builtin_prefetch(&points_[ahead]), __builtin_prefetch(&colours_[ahead]), __builtin_prefetch(&highlights_[ahead]);
          }
          const size_t slot = size_t(point[listed[k]]);
          color[listed[k]] = epi_color_word(slot, transmission_now(points_[slot]));
        }
      }
      return;
    }
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const int32_t p = image_.point[i];
      if (p < 0 || shows_nothing(points_[size_t(p)], points_[size_t(p)].view_share)) {
        epi.edge[i] = 0;
        epi.color[i] = 0;
        continue;
      }
      epi.edge[i] = uint16_t(uint16_t(image_.region[i]) << bits::kRegionShift | bits::kHasSample);
      epi.color[i] = epi_color_word(size_t(p), transmission_now(points_[size_t(p)]));
    }
  });
}

}  // namespace epi::render

// The point cache's projection kernels (issue 11), with Highway (dynamic dispatch, every target
// Highway builds):
// - project_batch: world positions to depth and pixel position, where that lands in the image's
//   tiles, the view staleness of view-dependent points, whether a point's surface faces away from
//   the eye and the diffuse transmission towards it, for a batch of points at once. The same
//   operations in the same order as ViewFrame::project, place, PointCache::view_staleness,
//   detail::faces_away and brdf.h's diffuse_transmission, without fused multiply-add
//   (-ffp-contract=off): bit-identical results (tests/render/point_projection_test.cpp).
// - gather_batch: a batch's inputs from the cloud (positions placed in the world by their
//   object's transform, the eye in the object's space), as gather_input does one point.
// - unpack_winners: a tile's z-buffer winners into the image's planes, as unpack_winner does
//   one pixel (the same test file).
// - fade_batch: the faded colour words of a batch of points, as faded_colour_word makes one (the
//   same test file).
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

#include "render/point_cache_detail.h"

#include "shade/view.h"

namespace epi::render {

// The point cache's z-buffer tiles (PointCache::project): a tile owns kWidth x kHeight pixels.
struct TileLayout {
  static constexpr int kWidthShift = 8, kHeightShift = 4;  // 256 x 16
  static constexpr int kWidth = 1 << kWidthShift, kHeight = 1 << kHeightShift;
  static int columns(int image_width) { return (image_width + kWidth - 1) / kWidth; }
};

// Where a projection lands in a width x height image of such tiles: the pixel index y width + x
// where it lies in the view (depth beyond znear, pixel inside the image; -1 elsewhere), its tile,
// and its spot: the pixel within the tile (bits 0-15) and the sub-pixel region rx + 4 ry on the
// 4x4 grid (bits 16-19); tile and spot 0 outside the view.
struct Placement {
  int32_t pixel;
  uint32_t tile, spot;
};
inline Placement place(float depth, float pixel_x, float pixel_y, int width, int height, float znear) {
  const bool inside = depth > znear && pixel_x >= 0.0f && pixel_y >= 0.0f && pixel_x < float(width) && pixel_y < float(height);
  if (!inside) return {-1, 0, 0};
  const int px = std::min(width - 1, int(pixel_x)), py = std::min(height - 1, int(pixel_y));
  const int rx = std::min(3, int((pixel_x - float(px)) * 4.0f));
  const int ry = std::min(3, int((pixel_y - float(py)) * 4.0f));
  return {py * width + px,
          uint32_t(py / TileLayout::kHeight * TileLayout::columns(width) + px / TileLayout::kWidth),
          uint32_t(py % TileLayout::kHeight * TileLayout::kWidth + px % TileLayout::kWidth) | uint32_t(rx + 4 * ry) << 16};
}

struct ProjectionBatch {
  static constexpr size_t kSize = 256;  // a multiple of every target's lane count
  // In: world position, the packed direction to the eye the point was shaded from (octahedral,
  // point_cache_detail.h's unpack_unit) and the lobe width (at least the minimum).
  alignas(64) float x[kSize], y[kSize], z[kSize];
  alignas(64) uint32_t view[kSize];
  alignas(64) float lobe_width[kSize];
  // In: the packed normal in the point's object space (0: no back-face test) and the eye in that
  // space less the point's position there.
  alignas(64) uint32_t normal[kSize];
  alignas(64) float eye_x[kSize], eye_y[kSize], eye_z[kSize];
  // Out: ViewFrame::project's depth and pixel; the staleness in 1/16 lobe widths where the
  // kernel settles it (detail::staleness_steps' estimate), -1 where PointCache::view_staleness
  // must (near a rounding boundary, a zero distance to the eye, a NaN).
  alignas(64) float depth[kSize], pixel_x[kSize], pixel_y[kSize];
  alignas(64) int32_t staleness[kSize];
  alignas(64) int32_t back_facing[kSize];  // detail::faces_away: 1 or 0
  // brdf.h's diffuse_transmission of detail::facing_cosine (points with a normal).
  alignas(64) float transmission[kSize];
  // place() of the depth and pixel, in the frame's image, beyond its camera's znear (at least 0).
  alignas(64) int32_t pixel[kSize];
  alignas(64) uint32_t tile[kSize], spot[kSize];
};

// Fills the outputs of the first n entries of the batch (n <= kSize); the inputs must be set up
// to n rounded up to 16 (a vector's lanes), or kSize.
void project_batch(const ViewFrame& frame, ProjectionBatch& batch, size_t n);

// The cloud as gather_batch reads it: a point is kWords 32-bit words, its object-space position
// (or background direction) at kLocal..kLocal+2, then its object, packed normal, packed view
// direction and lobe width (PointCache's CachePoint; point_cache.cpp asserts the layout).
struct CloudLayout {
  static constexpr size_t kWords = 12, kLocal = 0, kObject = 3, kNormal = 4, kView = 5, kLobeWidth = 6;
};

// Where the batch's points are this frame: object o's transform (column-major, as glm::mat4) at
// object_to_world[16 o], the eye in its space at eye_local[3 o]; a point whose object is not
// below `objects` (the background) lies at eye + background_depth x its direction.
struct BatchPlacement {
  const float* object_to_world;
  const float* eye_local;
  uint32_t objects;
  glm::vec3 eye;
  float background_depth;
  float min_lobe_width;  // lobes narrower than this age as if this wide
};

// One entry of a batch's inputs, k, from the point at `slot` (PointCache::world_position's
// arithmetic, in the same order).
inline void gather_input(const uint32_t* cloud, uint32_t slot, const BatchPlacement& at, ProjectionBatch& batch, size_t k) {
  const uint32_t* w = cloud + size_t(slot) * CloudLayout::kWords;
  const glm::vec3 local(std::bit_cast<float>(w[CloudLayout::kLocal]), std::bit_cast<float>(w[CloudLayout::kLocal + 1]),
                        std::bit_cast<float>(w[CloudLayout::kLocal + 2]));
  const uint32_t object = w[CloudLayout::kObject];
  glm::vec3 world = at.eye + local * at.background_depth, to_eye(0.0f);
  batch.normal[k] = 0;
  if (object < at.objects) {
    glm::mat4 m;
    std::copy_n(at.object_to_world + 16 * size_t(object), 16, &m[0][0]);
    world = glm::vec3(m * glm::vec4(local, 1.0f));
    const float* e = at.eye_local + 3 * size_t(object);
    to_eye = glm::vec3(e[0], e[1], e[2]) - local;
    batch.normal[k] = w[CloudLayout::kNormal];
  }
  batch.x[k] = world.x, batch.y[k] = world.y, batch.z[k] = world.z;
  batch.eye_x[k] = to_eye.x, batch.eye_y[k] = to_eye.y, batch.eye_z[k] = to_eye.z;
  batch.view[k] = w[CloudLayout::kView];
  batch.lobe_width[k] = std::max(std::bit_cast<float>(w[CloudLayout::kLobeWidth]), at.min_lobe_width);
}

// gather_input for entries 0..n-1 from slots[0..n), and on to n rounded up to 16 (a vector's
// lanes; those slots must name points of the cloud too). Every slot is at least `first` and
// less than first + 2^27 (the kernel indexes 32-bit words from the first slot's).
void gather_batch(const uint32_t* cloud, uint32_t first, const uint32_t* slots, size_t n, const BatchPlacement& at,
                  ProjectionBatch& batch);

// A projected point's record for the z-buffer (16 bytes, binned by tile): its z-buffer key
// (detail::zkey), EPI colour word, age bin and pixel within its tile.
struct ProjectedPoint {
  uint64_t key;
  uint32_t word;
  uint16_t age_bin, tile_pixel;
};
static_assert(sizeof(ProjectedPoint) == 16);

// encode_epi_color8_by_steps' tables (point_cache.cpp builds them once): steps[k] the least
// float that encodes to k or more, start[b] the code of bucket b's least float (the floats whose
// top 16 bits are first + b), `scans` the most steps any bucket's floats lie above its start.
struct ColourStepTables {
  const float* steps;    // 257 entries
  const int32_t* start;  // `buckets` entries
  uint32_t first, buckets;
  int scans;
};
const ColourStepTables& colour_step_tables();

// A faded colour (PointCache::faded_srgb): the view-dependent part of a point's colour faded by
// its staleness, the diffuse part times the current view's transmission where the point keeps it
// divided by the shading view's, encoded by steps. `fade_span`: max(view_fade_end -
// view_fade_start, 1e-3), as faded_srgb computes it.
uint32_t faded_colour_word(const glm::vec3& color, const glm::vec3& view_dependent, int staleness, bool rescaled,
                           float transmission_now, float fade_start, float fade_span);

// faded_colour_word for a batch of points at once (the points the projection finds faded: most
// of the drawn ones on glossy scenes in motion), bit-identical.
struct FadeBatch {
  static constexpr size_t kSize = ProjectionBatch::kSize;
  alignas(64) float r[kSize], g[kSize], b[kSize];     // PointColour::color
  alignas(64) float vr[kSize], vg[kSize], vb[kSize];  // PointColour::view_dependent
  alignas(64) int32_t staleness[kSize];               // CachePoint::staleness
  alignas(64) int32_t rescaled[kSize];                // 1: the diffuse part is kept divided by the shading view's transmission
  alignas(64) float transmission[kSize];              // the current view's diffuse transmission
  alignas(64) uint32_t word[kSize];                   // out: faded_colour_word
};
// Fills word[0..n); the inputs must be set up to n rounded up to 16 (a vector's lanes), or kSize.
void fade_batch(float fade_start, float fade_span, FadeBatch& batch, size_t n);

// The image planes a z-buffer's winners are unpacked into, at one pixel or the first of a run.
struct WinnerPlanes {
  int32_t* point;     // the winner's slot (the key's index), -1: empty
  int32_t* winners;   // the same (kept apart from the depth cull's removals)
  float* depth;       // the key's depth, +inf: empty
  uint8_t* region;    // the key's sub-pixel region; an empty pixel keeps its own
  uint32_t* word;     // the winning record's EPI colour word
  uint16_t* age_bin;  // ... and age bin
};

// One pixel: its z-buffer key (detail::kEmptyKey: nothing landed) and the record that won it
// (any record for an empty pixel: its word and age bin are not read).
inline void unpack_winner(uint64_t key, const ProjectedPoint& won, const WinnerPlanes& out, size_t i) {
  const uint32_t empty = uint32_t(0) - uint32_t(key == detail::kEmptyKey);  // all ones when empty
  constexpr uint32_t kInfinity = 0x7f800000u;
  out.winners[i] = out.point[i] = int32_t((uint32_t(key) & detail::kIndexMask) | empty);
  out.depth[i] = std::bit_cast<float>((uint32_t(key >> 32) & ~empty) | (kInfinity & empty));
  out.region[i] = uint8_t((((uint32_t(key) >> 28) & 15) & ~empty) | (out.region[i] & empty));
  out.word[i] = won.word, out.age_bin[i] = won.age_bin;
}

// unpack_winner over a block of `rows` x `columns` pixels: at row r, column k, the key
// keys[r pitch + k] and the record records[winner[r pitch + k]] (every winner an index into
// records), into out's planes at r out_pitch + k.
void unpack_winners(const uint64_t* keys, const uint32_t* winner, size_t pitch, const ProjectedPoint* records,
                    size_t columns, size_t rows, const WinnerPlanes& out, size_t out_pitch);

}  // namespace epi::render

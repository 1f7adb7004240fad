// The render cache's point processing (docs/render.md, "Points"): a fixed-size cloud of shaded
// points, projected every frame with a z-buffer and 4-bit sub-pixel positions, the depth-cull
// filter, aging, and new shading results overwriting old points. Points are stored in their
// object's space, so points on a moving object move with it.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "epi/epi_pixel.h"
#include "scene/scene.h"
#include "shade/shader.h"
#include "shade/view.h"

namespace epi::render {

struct PointCacheSettings {
  double capacity_factor = 1.15;   // cloud size as a multiple of the pixel count
  int max_age = 240;               // points older than this are not drawn (and their slot is freed)
  int offscreen_penalty = 3;       // extra age per frame for points that project outside the image
  float depth_cull_offset = 0.1f;  // cull a point deeper than (1 + offset) x the 3x3 mean depth
  float change_threshold = 0.1f;   // relative colour change that counts as "shading changed"
  int change_penalty = 48;         // age added around a pixel whose shading changed
  int change_radius = 2;           // ... over a (2r+1)^2 window
};

struct CachePoint {
  glm::vec3 local{0.0f};  // object space; for background (object == kNone) a world direction
  glm::vec3 color{0.0f};  // linear RGB
  uint32_t srgb = 0;      // the colour as the EPI stores it (8-bit sRGB r, g, b), encoded once
  uint32_t object = kNone;
  int32_t image_id = -1;  // pixel index of the last projection, -1: none
  uint16_t age = 0;
  bool valid = false;
};

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
  size_t expired = 0;    // points freed for exceeding the maximum age
};

class PointCache {
 public:
  PointCache(int width, int height, const PointCacheSettings& settings = {});

  // Ages every point, projects the cloud into `frame` with a z-buffer (points of object o placed
  // by object_to_world[o]), then runs the depth cull. Fills image().
  ProjectionCounts project(const ViewFrame& frame, std::span<const glm::mat4> object_to_world);

  // Integrates shading results made for `shot` (its camera gives misses their direction) and traced
  // with objects placed by object_to_world (the hit positions are converted to object space with
  // it, so they then move with their object). A result
  // replaces the point drawn at its pixel in the last projection when that point is the same
  // surface; otherwise it takes a free slot, or the next slot in round-robin order. When the
  // replaced point's colour differs noticeably, the points around it are aged (shading changed).
  // Returns the number of results integrated.
  size_t insert(const ViewFrame& shot, const ShadeBatch& batch, std::span<const glm::mat4> object_to_world);

  // Writes the drawn points into the EPI as samples (colour, sub-pixel region, age); clears the rest.
  void fill_epi(EpiImage& epi) const;

  // Where a point is in the world under the given object transforms (background points sit at
  // background_depth() along their direction from the frame's eye).
  glm::vec3 world_position(const CachePoint& p, const ViewFrame& frame, std::span<const glm::mat4> object_to_world) const;

  const PointImage& image() const { return image_; }
  const std::vector<CachePoint>& points() const { return points_; }
  size_t capacity() const { return points_.size(); }
  size_t valid_points() const;
  size_t hidden_removed() const { return hidden_removed_; }  // points whose slot a ray showed hidden
  const PointCacheSettings& settings() const { return settings_; }
  float background_depth() const { return background_depth_; }

 private:
  size_t take_slot();
  void choose_evict_age(size_t needed);
  int32_t find_hidden(const ViewFrame& shot, const ShadeResult& r, const glm::vec3& last_world,
                      std::span<const glm::mat4> object_to_world) const;

  PointCacheSettings settings_;
  std::vector<CachePoint> points_;
  std::vector<uint32_t> free_slots_;
  size_t cursor_ = 0;
  int evict_age_ = 1;                   // take_slot's sweep takes points at least this old
  std::vector<uint32_t> age_histogram_;  // of the last projection less the points evicted since (off-screen last)
  size_t hidden_removed_ = 0;
  PointImage image_;
  std::vector<uint64_t> zbuffer_;  // (depth bits << 32) | point index, min wins
  std::vector<int32_t> winners_;   // z-buffer result before the depth cull
  float background_depth_ = 1e6f;  // where background points are placed along their direction
  std::optional<ViewFrame> last_frame_;
  std::vector<glm::mat4> last_transforms_;  // the placement of the last projection
};

}  // namespace epi::render

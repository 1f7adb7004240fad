#include "render/point_cache.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace epi::render {

namespace {

constexpr size_t kAgeBins = 258;  // ages 0..255 (capped), then off screen
constexpr uint64_t kEmptyKey = ~uint64_t(0);
constexpr uint32_t kIndexMask = 0x0fffffffu;  // point index; bits 28-31 hold the sub-pixel region

// Z-buffer key: depth first (positive floats order like their bits), then region and index.
uint64_t zkey(float depth, int region, uint32_t index) {
  return uint64_t(std::bit_cast<uint32_t>(depth)) << 32 | uint64_t(region) << 28 | index;
}

void atomic_min(uint64_t& slot, uint64_t value) {
  std::atomic_ref<uint64_t> ref(slot);
  uint64_t current = ref.load(std::memory_order_relaxed);
  while (value < current && !ref.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
  }
}

uint32_t pack_srgb(const glm::vec3& c) {
  return uint32_t(encode_srgb8(c.r)) | uint32_t(encode_srgb8(c.g)) << 8 | uint32_t(encode_srgb8(c.b)) << 16;
}

bool shading_changed(const glm::vec3& before, const glm::vec3& after, float threshold) {
  const glm::vec3 d = glm::abs(after - before);
  const float scale = 0.5f * (before.r + before.g + before.b + after.r + after.g + after.b) + 0.03f;
  return (d.r + d.g + d.b) > threshold * scale;
}

}  // namespace

PointCache::PointCache(int width, int height, const PointCacheSettings& settings) : settings_(settings) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("point cache: image size is not positive");
  const double capacity = std::ceil(double(width) * double(height) * std::max(1.0, settings.capacity_factor));
  if (capacity > double(kIndexMask)) throw std::invalid_argument("point cache: image too large");
  points_.resize(size_t(capacity));
  free_slots_.reserve(points_.size());
  for (size_t i = points_.size(); i-- > 0;) free_slots_.push_back(uint32_t(i));
  const size_t pixels = size_t(width) * size_t(height);
  image_.width = width, image_.height = height;
  image_.point.assign(pixels, -1);
  image_.depth.assign(pixels, std::numeric_limits<float>::infinity());
  image_.region.assign(pixels, 0);
  zbuffer_.assign(pixels, kEmptyKey);
  winners_.assign(pixels, -1);
}

size_t PointCache::valid_points() const {
  return size_t(std::count_if(points_.begin(), points_.end(), [](const CachePoint& p) { return p.valid; }));
}

glm::vec3 PointCache::world_position(const CachePoint& p, const ViewFrame& frame,
                                     std::span<const glm::mat4> object_to_world) const {
  if (p.object == kNone || p.object >= object_to_world.size()) return frame.eye() + p.local * background_depth_;
  return glm::vec3(object_to_world[p.object] * glm::vec4(p.local, 1.0f));
}

ProjectionCounts PointCache::project(const ViewFrame& frame, std::span<const glm::mat4> object_to_world) {
  const int w = image_.width, h = image_.height;
  if (frame.view().width != w || frame.view().height != h)
    throw std::invalid_argument("point cache: view size differs from the cache's image size");
  std::fill(zbuffer_.begin(), zbuffer_.end(), kEmptyKey);
  const float znear = std::max(frame.view().camera.znear, 0.0f);
  const int max_age = settings_.max_age;

  // Aging and projection with a z-buffer (points in parallel; the minimum key wins).
  struct Counts {
    size_t projected = 0, expired = 0;
    std::array<uint32_t, kAgeBins> ages{};  // eviction order: age, off-screen points in the top bin
  };
  const Counts counts = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, points_.size(), 4096), Counts{},
      [&](const tbb::blocked_range<size_t>& range, Counts c) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          CachePoint& p = points_[i];
          if (!p.valid) continue;
          p.age = uint16_t(std::min(p.age + 1, 0xffff));
          const Projection proj = frame.project(world_position(p, frame, object_to_world));
          const bool inside = proj.depth > znear && proj.pixel.x >= 0.0f && proj.pixel.y >= 0.0f &&
                              proj.pixel.x < float(w) && proj.pixel.y < float(h);
          if (!inside) {
            p.age = uint16_t(std::min(p.age + settings_.offscreen_penalty, 0xffff));
            p.image_id = -1;
          }
          if (p.age > max_age) {
            p.valid = false, p.image_id = -1;
            ++c.expired;
            continue;
          }
          ++c.ages[inside ? std::min<size_t>(p.age, kAgeBins - 2) : kAgeBins - 1];
          if (!inside) continue;
          const int px = std::min(w - 1, int(proj.pixel.x)), py = std::min(h - 1, int(proj.pixel.y));
          const int rx = std::min(3, int((proj.pixel.x - float(px)) * 4.0f));
          const int ry = std::min(3, int((proj.pixel.y - float(py)) * 4.0f));
          const size_t pixel = size_t(py) * size_t(w) + size_t(px);
          p.image_id = int32_t(pixel);
          atomic_min(zbuffer_[pixel], zkey(proj.depth, rx + 4 * ry, uint32_t(i)));
          ++c.projected;
        }
        return c;
      },
      [](Counts a, const Counts& b) {
        a.projected += b.projected, a.expired += b.expired;
        for (size_t k = 0; k < kAgeBins; ++k) a.ages[k] += b.ages[k];
        return a;
      });

  // Unpack the z-buffer.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, zbuffer_.size(), 16384), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const uint64_t key = zbuffer_[i];
      if (key == kEmptyKey) {
        winners_[i] = -1;
        image_.depth[i] = std::numeric_limits<float>::infinity();
        continue;
      }
      winners_[i] = int32_t(uint32_t(key) & kIndexMask);
      image_.depth[i] = std::bit_cast<float>(uint32_t(key >> 32));
      image_.region[i] = uint8_t((uint32_t(key) >> 28) & 15);
    }
  });

  // Depth cull: remove a point deeper than (1 + offset) x the mean depth of the points in its 3x3.
  const float cull_scale = 1.0f + settings_.depth_cull_offset;
  const auto cull_counts = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, h, 8), std::pair<size_t, size_t>{0, 0},
      [&](const tbb::blocked_range<int>& rows, std::pair<size_t, size_t> c) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < w; ++x) {
            const size_t i = image_.index(x, y);
            image_.point[i] = winners_[i];
            if (winners_[i] < 0) continue;
            double sum = 0.0;
            int n = 0;
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int qx = x + dx, qy = y + dy;
                if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                const size_t q = image_.index(qx, qy);
                if (winners_[q] < 0) continue;
                sum += image_.depth[q];
                ++n;
              }
            if (image_.depth[i] > float(sum / n) * cull_scale) {
              image_.point[i] = -1;
              ++c.second;
            } else {
              ++c.first;
            }
          }
        return c;
      },
      [](std::pair<size_t, size_t> a, const std::pair<size_t, size_t>& b) {
        return std::pair<size_t, size_t>{a.first + b.first, a.second + b.second};
      });
  // The culled pixels' depth stays +inf for later stages.
  for (size_t i = 0; i < winners_.size(); ++i)
    if (winners_[i] >= 0 && image_.point[i] < 0) image_.depth[i] = std::numeric_limits<float>::infinity();

  // Free the slots of expired points.
  if (counts.expired > 0) {
    free_slots_.clear();
    for (size_t i = points_.size(); i-- > 0;)
      if (!points_[i].valid) free_slots_.push_back(uint32_t(i));
  }
  age_histogram_.assign(counts.ages.begin(), counts.ages.end());
  last_frame_.emplace(frame);
  last_transforms_.assign(object_to_world.begin(), object_to_world.end());
  return {counts.projected, cull_counts.first, cull_counts.second, counts.expired};
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
    const size_t bin = p.image_id < 0 ? age_histogram_.size() - 1 : std::min<size_t>(p.age, age_histogram_.size() - 2);
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
    if (p.image_id < 0 || p.age >= evict_age_) return evict(slot);
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
                                std::span<const glm::mat4> object_to_world) const {
  // Candidates: the z-buffer winners of the last projection near where the shot's ray runs in it,
  // from the hit (3x3 around it) along the ray's image towards its vanishing point (parallax when
  // the eye moved), at most kMaxWalk pixels.
  constexpr float kRadius = 0.35f;   // the ray's evidence covers this far around it, pixels
  constexpr float kMargin = 0.05f;    // relative depth behind the hit
  constexpr float kMaxWalk = 8.0f;
  const int w = image_.width, h = image_.height;
  const Projection hit_shot = shot.project(r.position);
  const glm::vec2 sample(r.x, r.y);
  auto hidden = [&](int32_t q) {
    if (q < 0) return false;
    const CachePoint& p = points_[size_t(q)];
    if (!p.valid || p.age == 0) return false;
    const Projection pq = shot.project(world_position(p, shot, object_to_world));
    return pq.depth > hit_shot.depth * (1.0f + kMargin) && glm::distance(pq.pixel, sample) <= kRadius;
  };
  auto check = [&](int x, int y) -> int32_t {
    if (x < 0 || y < 0 || x >= w || y >= h) return -1;
    const int32_t q = winners_[image_.index(x, y)];
    return hidden(q) ? q : -1;
  };
  const Projection p0 = last_frame_->project(last_world);
  // In front, and near the image (a hit close to the last eye's plane projects far away, or to
  // non-finite pixels: converting those to int would be undefined).
  if (!p0.in_front() || !(p0.pixel.x > -2.0f && p0.pixel.y > -2.0f && p0.pixel.x < float(w) + 2.0f &&
                          p0.pixel.y < float(h) + 2.0f))
    return -1;
  const int x0 = int(std::floor(p0.pixel.x)), y0 = int(std::floor(p0.pixel.y));
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (const int32_t q = check(x0 + dx, y0 + dy); q >= 0) return q;
  const glm::vec3 dir = shot.ray(r.x, r.y).direction;
  const Projection p1 = last_frame_->project(last_frame_->eye() + dir * background_depth_);
  if (!p1.in_front()) return -1;
  glm::vec2 d = p1.pixel - p0.pixel;
  if (!std::isfinite(d.x) || !std::isfinite(d.y)) return -1;
  const float length = std::min(glm::length(d), kMaxWalk);
  if (!(length >= 1.0f)) return -1;
  d = glm::normalize(d);
  int last_x = x0, last_y = y0;
  for (float t = 0.5f; t <= length; t += 0.5f) {
    const glm::vec2 c = p0.pixel + d * t;
    const int x = int(std::floor(c.x)), y = int(std::floor(c.y));
    if (x == last_x && y == last_y) continue;
    last_x = x, last_y = y;
    if (std::abs(x - x0) <= 1 && std::abs(y - y0) <= 1) continue;
    if (const int32_t q = check(x, y); q >= 0) return q;
  }
  return -1;
}

size_t PointCache::insert(const ViewFrame& shot, const ShadeBatch& batch, std::span<const glm::mat4> object_to_world) {
  std::vector<glm::mat4> to_object(object_to_world.size());
  std::vector<uint8_t> inverted(object_to_world.size(), 0);
  const int w = image_.width, h = image_.height;
  if (free_slots_.size() < batch.results.size()) choose_evict_age(batch.results.size() - free_slots_.size());
  size_t inserted = 0;
  for (const ShadeResult& r : batch.results) {
    CachePoint point;
    point.color = glm::max(r.color, glm::vec3(0.0f));
    point.srgb = pack_srgb(point.color);
    point.valid = true;
    glm::vec3 world;
    if (r.hit && r.object < object_to_world.size()) {
      if (!inverted[r.object]) to_object[r.object] = glm::inverse(object_to_world[r.object]), inverted[r.object] = 1;
      point.object = r.object;
      point.local = glm::vec3(to_object[r.object] * glm::vec4(r.position, 1.0f));
      // Where the point was at the last projection (its object may have moved since the shot).
      world = r.object < last_transforms_.size() ? glm::vec3(last_transforms_[r.object] * glm::vec4(point.local, 1.0f))
                                                 : r.position;
    } else {
      point.object = kNone;
      point.local = shot.ray(r.x, r.y).direction;
      world = shot.eye() + point.local * background_depth_;
    }

    // The point drawn where this result lands in the last projection: replaced if it is the same surface.
    int32_t replace = -1;
    if (last_frame_) {
      const Projection proj = last_frame_->project(world);
      if (proj.in_front() && proj.pixel.x >= 0.0f && proj.pixel.y >= 0.0f && proj.pixel.x < float(w) &&
          proj.pixel.y < float(h)) {
        const int px = std::min(w - 1, int(proj.pixel.x)), py = std::min(h - 1, int(proj.pixel.y));
        const int32_t old = image_.point[image_.index(px, py)];
        // (age 0: the slot was given to a result since the projection: not the point drawn there)
        if (old >= 0 && points_[size_t(old)].valid && points_[size_t(old)].age != 0 &&
            points_[size_t(old)].object == point.object &&
            (point.object == kNone || std::abs(image_.depth[image_.index(px, py)] - proj.depth) <= 0.05f * proj.depth)) {
          replace = old;
          if (shading_changed(points_[size_t(old)].color, point.color, settings_.change_threshold)) {
            const int r0 = settings_.change_radius;
            for (int qy = std::max(0, py - r0); qy <= std::min(h - 1, py + r0); ++qy)
              for (int qx = std::max(0, px - r0); qx <= std::min(w - 1, px + r0); ++qx) {
                const int32_t q = image_.point[image_.index(qx, qy)];
                if (q >= 0) points_[size_t(q)].age = uint16_t(std::min(points_[size_t(q)].age + settings_.change_penalty, 0xffff));
              }
          }
        }
      }
      // The ray is evidence that what lies behind its hit along it is hidden from the shot's eye:
      // a point of the last projection there (within kRadius of the ray, farther by a margin)
      // gives its slot to this result (or is freed when the result already has one).
      if (r.hit && point.object != kNone) {
        const int32_t hidden = find_hidden(shot, r, world, object_to_world);
        if (hidden >= 0) {
          CachePoint& q = points_[size_t(hidden)];
          if (q.image_id >= 0 && winners_[size_t(q.image_id)] == hidden) {
            winners_[size_t(q.image_id)] = -1;
            image_.point[size_t(q.image_id)] = -1;
          }
          ++hidden_removed_;
          if (replace < 0) {
            replace = hidden;
          } else {
            q.valid = false, q.image_id = -1;
            free_slots_.push_back(uint32_t(hidden));
          }
        }
      }
    }
    points_[replace >= 0 ? size_t(replace) : take_slot()] = point;
    ++inserted;
  }
  return inserted;
}

void PointCache::fill_epi(EpiImage& epi) const {
  if (epi.width != image_.width || epi.height != image_.height)
    throw std::invalid_argument("point cache: EPI size differs from the cache's image size");
  tbb::parallel_for(tbb::blocked_range<size_t>(0, image_.point.size(), 16384), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const int32_t p = image_.point[i];
      if (p < 0) {
        epi.edge[i] = 0;
        epi.color[i] = 0;
        continue;
      }
      const CachePoint& point = points_[size_t(p)];
      epi.edge[i] = uint16_t(uint16_t(image_.region[i]) << bits::kRegionShift | bits::kHasSample);
      epi.color[i] = point.srgb | uint32_t(std::min<int>(point.age, 255)) << bits::kAgeShift;
    }
  });
}

}  // namespace epi::render

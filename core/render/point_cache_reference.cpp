// The reference path of the point cache (PointCacheSettings::reference_path): the straightforward
// implementation the fast path in point_cache.cpp must match bit for bit (docs/performance.md,
// "Point processing"). Tests and bench/render/points_bench.cpp run both.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "render/point_cache.h"
#include "render/point_cache_detail.h"

namespace epi::render {

using namespace detail;

ProjectionCounts PointCache::project_reference(const ViewFrame& frame, std::span<const glm::mat4> object_to_world, bool depth_cull) {
  const int w = image_.width, h = image_.height;
  if (frame.view().width != w || frame.view().height != h)
    throw std::invalid_argument("point cache: view size differs from the cache's image size");
  zbuffer_.assign(image_.point.size(), kEmptyKey);  // sized on first use (the fast path has none)
  const float znear = std::max(frame.view().camera.znear, 0.0f);
  const int max_age = settings_.max_age;
  // The eye in each object's space: a point's stored normal faces the eye it was shaded from, and
  // a point whose surface now faces away from the eye is not drawn (back_facing).
  eye_local_.resize(object_to_world.size());
  for (size_t o = 0; o < object_to_world.size(); ++o) eye_local_[o] = glm::vec3(glm::inverse(object_to_world[o]) * glm::vec4(frame.eye(), 1.0f));

  // Aging and projection with a z-buffer (points in parallel; the minimum key wins).
  struct Counts {
    size_t projected = 0, expired = 0, back_facing = 0;
    std::array<uint32_t, kAgeBins> ages{};  // eviction order: age, off-screen points in the top bin
  };
  const Counts counts = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, points_.size(), 4096), Counts{},
      [&](const tbb::blocked_range<size_t>& range, Counts c) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          CachePoint& p = points_[i];
          if (!p.valid) continue;
          p.age = uint16_t(std::min(p.age + 1, 0xffff));
          const glm::vec3 world = world_position(p, frame, object_to_world);
          p.staleness = view_staleness(p, colour_terms(colours_[i]).view_share, frame.eye() - world);
          const Projection proj = frame.project(world);
          const bool inside = in_view_or_penalised(p, proj, znear);
          if (p.age > max_age) {
            p.valid = false, p.image_id = -1;
            ++c.expired;
            continue;
          }
          ++c.ages[kAgeBins - 1];  // as not drawn; the drawn ones move to their age's bin after the cull
          if (!inside) continue;
          if (back_facing(p)) {
            p.image_id = -1;
            ++c.back_facing;
            continue;
          }
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
        a.projected += b.projected, a.expired += b.expired, a.back_facing += b.back_facing;
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

  std::copy(winners_.begin(), winners_.end(), image_.point.begin());
  const size_t culled = depth_cull ? depth_cull_reference({}) : 0;

  // Free the slots of expired points.
  valid_points_ -= counts.expired;
  if (counts.expired > 0) {
    free_slots_.clear();
    for (size_t i = points_.size(); i-- > 0;)
      if (!points_[i].valid) free_slots_.push_back(uint32_t(i));
  }
  age_histogram_.assign(counts.ages.begin(), counts.ages.end());
  for (const int32_t q : image_.point)
    if (q >= 0) --age_histogram_[kAgeBins - 1], ++age_histogram_[std::min<size_t>(points_[size_t(q)].age, kAgeBins - 2)];
  last_frame_.emplace(frame);
  last_transforms_.assign(object_to_world.begin(), object_to_world.end());
  const size_t drawn = size_t(std::count_if(image_.point.begin(), image_.point.end(), [](int32_t q) { return q >= 0; }));
  return {counts.projected, drawn, culled, 0, counts.expired, counts.back_facing};
}

size_t PointCache::depth_cull_reference(std::span<const uint8_t> edge_pixels) {
  const int w = image_.width, h = image_.height;
  const float cull_scale = 1.0f + settings_.depth_cull_offset;
  std::vector<uint8_t> cull(image_.point.size(), 0);
  const size_t culled = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, h, 8), size_t(0),
      [&](const tbb::blocked_range<int>& rows, size_t count) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < w; ++x) {
            const size_t i = image_.index(x, y);
            if (image_.point[i] < 0 || near_depth_edge(edge_pixels, x, y)) continue;
            double sum = 0.0;
            int n = 0;
            for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
              for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) {
                const size_t q = image_.index(qx, qy);
                if (image_.point[q] < 0) continue;
                sum += image_.depth[q];
                ++n;
              }
            if (image_.depth[i] > float(sum / n) * cull_scale) cull[i] = 1, ++count;
          }
        return count;
      },
      std::plus<size_t>());
  // Removed after the pass (the means see the z-buffer's winners); the depth of a culled pixel is +inf.
  for (size_t i = 0; i < cull.size(); ++i)
    if (cull[i]) image_.point[i] = -1, image_.depth[i] = std::numeric_limits<float>::infinity();
  return culled;
}

size_t PointCache::cull_behind_surfaces_reference(const ViewFrame& frame, std::span<const glm::mat4> object_to_world,
                                        const EdgeCrossings& crossings) {
  const int w = image_.width, h = image_.height;
  hidden_.assign(image_.point.size(), 0);
  mark_alone();
  const size_t removed = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, h, 8), size_t(0),
      [&](const tbb::blocked_range<int>& rows, size_t count) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < w; ++x) {
            const size_t i = image_.index(x, y);
            if (image_.point[i] < 0) continue;
            if (hidden_behind_a_neighbour(frame, object_to_world, crossings, x, y)) hidden_[i] = 1, ++count;
          }
        return count;
      },
      std::plus<size_t>());
  for (size_t i = 0; i < hidden_.size(); ++i)
    if (hidden_[i]) image_.point[i] = -1, image_.depth[i] = std::numeric_limits<float>::infinity();
  return removed;
}

void PointCache::fill_epi_reference(EpiImage& epi) const {
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
      // The colour terms from the colour statistics (the fast path reads the stored ones).
      const CachePoint& point = points_[size_t(p)];
      const PointColour& colour = colours_[size_t(p)];
      const ColourTerms terms = colour_terms(colour);
      if (shows_nothing(point, terms.view_share)) {
        epi.edge[i] = 0;
        epi.color[i] = 0;
        continue;
      }
      epi.edge[i] = uint16_t(uint16_t(image_.region[i]) << bits::kRegionShift | bits::kHasSample);
      epi.color[i] = display_srgb(point, colour, transmission_now(point), false, highlight_now(size_t(p))) |
                     uint32_t(std::min<int>(priority_age(point, terms), 255)) << bits::kAgeShift;
    }
  });
}

}  // namespace epi::render

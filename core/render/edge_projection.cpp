#include "render/edge_projection.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "target_clones.h"

namespace epi::render {

namespace {

// The row loops of filter_depth, with restrict pointers so that the compiler vectorizes them (for
// each target: target_clones.h).
// A drawn pixel's depth, -inf where empty (or NaN), and 1 / 0 for drawn / empty.
EPI_TARGET_CLONES void masked_row(const int32_t* __restrict point, const float* __restrict depth, float* __restrict masked,
                uint8_t* __restrict drawn_flags, int w) {
  const float empty = -std::numeric_limits<float>::infinity();
  for (int x = 0; x < w; ++x) {
    const bool drawn = point[x] >= 0;
    masked[x] = (drawn & (depth[x] == depth[x])) ? depth[x] : empty;
    drawn_flags[x] = uint8_t(drawn);
  }
}
// Maximum and sum over x-1..x+2 of rows padded by one element before and two after.
EPI_TARGET_CLONES void window4_row(const float* __restrict masked, const uint8_t* __restrict drawn_flags, float* __restrict m,
                 uint8_t* __restrict n, int w) {
  for (int x = 0; x < w; ++x) {
    m[x] = std::max(std::max(masked[x - 1], masked[x]), std::max(masked[x + 1], masked[x + 2]));
    n[x] = uint8_t(drawn_flags[x - 1] + drawn_flags[x] + drawn_flags[x + 1] + drawn_flags[x + 2]);
  }
}
// Rows y-1..y+2 of the window maxima and counts to the filtered depth.
EPI_TARGET_CLONES void filtered_row(const float* __restrict m0, const float* __restrict m1, const float* __restrict m2,
                  const float* __restrict m3, const uint8_t* __restrict n0, const uint8_t* __restrict n1,
                  const uint8_t* __restrict n2, const uint8_t* __restrict n3, float base, float sparse,
                  float* __restrict out, int w) {
  const float inf = std::numeric_limits<float>::infinity();
  for (int x = 0; x < w; ++x) {
    const float m = std::max(std::max(m0[x], m1[x]), std::max(m2[x], m3[x]));
    const int n = n0[x] + n1[x] + n2[x] + n3[x];
    out[x] = n == 0 ? inf : m * (base + sparse * (float(16 - n) / 16.0f));
  }
}

}  // namespace

void filter_depth(const PointImage& points, const DepthFilterSettings& settings, std::vector<float>& out) {
  const int w = points.width, h = points.height;
  const float inf = std::numeric_limits<float>::infinity();
  out.resize(size_t(w) * size_t(h));
  // Bands of rows: the max depth and point count over x-1..x+2 of the rows y0-1..y1+1, kept in
  // the band's own rows (ring of 4), then columns over y-1..y+2. Same arithmetic as row-then-column
  // over the whole image: max and integer counts do not depend on the grouping. No branch per
  // pixel (empty and drawn pixels alternate at random, so a branch on "drawn" mispredicts): each
  // row is first made into padded planes, -inf and 0 where empty and beyond the border, whose
  // window maxima and sums the compiler vectorizes. A NaN depth counts as a point but, as in
  // std::max folded from -inf, never becomes the maximum.
  constexpr int kBand = 16;
  tbb::parallel_for(tbb::blocked_range<int>(0, (h + kBand - 1) / kBand, 1), [&](const tbb::blocked_range<int>& r) {
    thread_local std::vector<float> ring_max, padded_depth;
    thread_local std::vector<uint8_t> ring_count, padded_count;
    ring_max.resize(5 * size_t(w)), ring_count.resize(5 * size_t(w));
    padded_depth.assign(size_t(w) + 3, -inf), padded_count.assign(size_t(w) + 3, 0);
    // Slot 4 of the ring: the rows outside the image.
    std::fill_n(ring_max.data() + 4 * size_t(w), w, -inf);
    std::fill_n(ring_count.data() + 4 * size_t(w), w, uint8_t(0));
    auto row_of = [&](int y) {  // fills the ring's slot of row y (y in [0, h))
      // Element x + 1 of the padded rows is pixel x; elements 0, w + 1 and w + 2 stay empty.
      masked_row(points.point.data() + points.index(0, y), points.depth.data() + points.index(0, y),
                 padded_depth.data() + 1, padded_count.data() + 1, w);
      window4_row(padded_depth.data() + 1, padded_count.data() + 1, ring_max.data() + size_t(y & 3) * size_t(w),
                  ring_count.data() + size_t(y & 3) * size_t(w), w);
    };
    auto slot = [&](int y) { return size_t(y >= 0 && y < h ? (y & 3) : 4) * size_t(w); };
    for (int band = r.begin(); band != r.end(); ++band) {
      const int y0 = band * kBand, y1 = std::min(h, y0 + kBand);
      for (int y = std::max(0, y0 - 1); y < std::min(h, y0 + 2); ++y) row_of(y);
      for (int y = y0; y < y1; ++y) {
        if (y + 2 < h) row_of(y + 2);  // rows y-1..y+2 are in the ring
        const float* m = ring_max.data();
        const uint8_t* n = ring_count.data();
        filtered_row(m + slot(y - 1), m + slot(y), m + slot(y + 1), m + slot(y + 2), n + slot(y - 1), n + slot(y),
                     n + slot(y + 1), n + slot(y + 2), 1.0f + settings.base_offset, settings.sparse_offset,
                     out.data() + size_t(y) * size_t(w), w);
      }
    }
  });
}

EdgeFate project_edge(const ViewFrame& frame, const glm::dvec3& a, const glm::dvec3& b,
                      std::span<const float> filtered_depth, std::vector<Segment>& out,
                      std::vector<glm::dvec2>* inv_depths) {
  const View& view = frame.view();
  const glm::dvec3 eye(frame.eye()), forward(frame.forward());
  const double znear = std::max(double(view.camera.znear), 1e-6);

  // Near plane.
  glm::dvec3 p0 = a, p1 = b;
  const double d0 = glm::dot(p0 - eye, forward), d1 = glm::dot(p1 - eye, forward);
  if (d0 < znear && d1 < znear) return EdgeFate::outside;
  if (d0 < znear) p0 = p0 + (p1 - p0) * ((znear - d0) / (d1 - d0));
  if (d1 < znear) p1 = p1 + (p0 - p1) * ((znear - d1) / (d0 - d1));

  const Projection q0 = frame.project(glm::vec3(p0)), q1 = frame.project(glm::vec3(p1));
  const double x0 = q0.pixel.x, y0 = q0.pixel.y, x1 = q1.pixel.x, y1 = q1.pixel.y;
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return EdgeFate::outside;

  // Liang-Barsky against the image grown by one pixel.
  const double lo_x = -1.0, lo_y = -1.0, hi_x = view.width + 1.0, hi_y = view.height + 1.0;
  double t0 = 0.0, t1 = 1.0;
  const double dx = x1 - x0, dy = y1 - y0;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {x0 - lo_x, hi_x - x0, y0 - lo_y, hi_y - y0};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return EdgeFate::outside;
      continue;
    }
    const double r = q[k] / p[k];
    if (p[k] < 0.0) t0 = std::max(t0, r);
    else t1 = std::min(t1, r);
    if (t0 > t1) return EdgeFate::outside;
  }
  auto point_at = [&](double t) { return glm::dvec2(x0 + t * dx, y0 + t * dy); };
  // 1/depth is linear in screen space along the projected segment.
  const double inv0 = 1.0 / double(q0.depth), inv1 = 1.0 / double(q1.depth);
  auto emit = [&](double ts, double te) {
    const glm::dvec2 s = point_at(ts), e = point_at(te);
    out.push_back({s.x, s.y, e.x, e.y});
    if (inv_depths) inv_depths->emplace_back(inv0 + ts * (inv1 - inv0), inv0 + te * (inv1 - inv0));
  };
  if (filtered_depth.empty()) {
    emit(t0, t1);
    return EdgeFate::visible;
  }

  // Occlusion culling.
  const double length = std::hypot(dx, dy) * (t1 - t0);
  const int steps = std::max(1, int(std::ceil(length)));
  auto visible_at = [&](double t) {
    const glm::dvec2 s = point_at(t);
    const int px = int(std::floor(s.x)), py = int(std::floor(s.y));
    if (px < 0 || py < 0 || px >= view.width || py >= view.height) return true;  // margin: keep
    const double depth = 1.0 / (inv0 + t * (inv1 - inv0));
    return depth <= double(filtered_depth[size_t(py) * size_t(view.width) + size_t(px)]);
  };
  // Pieces between samples a pixel or less apart; a piece is visible when either end or its
  // middle is (conservative); consecutive visible pieces make one output segment.
  auto t_at = [&](int k) { return t0 + (t1 - t0) * double(k) / double(steps); };
  bool any = false, previous = visible_at(t0);
  int run_start = -1;
  for (int k = 0; k < steps; ++k) {
    const bool next = visible_at(t_at(k + 1));
    const bool piece = previous || next || visible_at(0.5 * (t_at(k) + t_at(k + 1)));
    if (piece && run_start < 0) run_start = k;
    if (run_start >= 0 && (!piece || k == steps - 1)) {
      const int end = piece ? k + 1 : k;
      emit(t_at(run_start), t_at(end));
      any = true;
      run_start = -1;
    }
    previous = next;
  }
  return any ? EdgeFate::visible : EdgeFate::culled;
}

void mark_edge_pixels(std::span<const Segment> segments, std::span<const edges::EdgeKind> kinds, int w, int h,
                      std::vector<uint8_t>& mask) {
  mask.resize(size_t(w) * size_t(h));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mask.size(), 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
    std::fill(mask.begin() + ptrdiff_t(r.begin()), mask.begin() + ptrdiff_t(r.end()), uint8_t(0));
  });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, segments.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
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
        std::atomic_ref<uint8_t> m(mask[size_t(y) * size_t(w) + size_t(x)]);
        if ((m.load(std::memory_order_relaxed) & bit) == 0) m.fetch_or(bit, std::memory_order_relaxed);
      }
    }
  });
}


void project_edges(const ViewFrame& frame, std::span<const edges::SceneEdge> edges, std::span<const float> filtered_depth,
                   std::vector<Segment>& out, std::vector<uint32_t>& piece_edge, std::vector<glm::dvec2>& piece_inv_depth,
                   std::vector<EdgeFate>& fates, EdgeProjectionScratch& scratch) {
  // Fixed chunks (not the scheduler's split), each appending to its own buffers; concatenated in
  // chunk order, so the pieces come out in edge order whatever thread ran which chunk.
  constexpr size_t kChunk = 64;
  const size_t chunks = (edges.size() + kChunk - 1) / kChunk;
  if (scratch.pieces.size() < chunks)
    scratch.pieces.resize(chunks), scratch.piece_edge.resize(chunks), scratch.piece_inv_depth.resize(chunks);
  fates.resize(edges.size());
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    std::vector<Segment>& pieces = scratch.pieces[c];
    std::vector<uint32_t>& owner = scratch.piece_edge[c];
    std::vector<glm::dvec2>& inv_depth = scratch.piece_inv_depth[c];
    pieces.clear(), owner.clear(), inv_depth.clear();
    for (size_t k = c * kChunk; k < std::min(edges.size(), (c + 1) * kChunk); ++k) {
      fates[k] = project_edge(frame, edges[k].a, edges[k].b, filtered_depth, pieces, &inv_depth);
      owner.resize(pieces.size(), uint32_t(k));
    }
  });
  for (size_t c = 0; c < chunks; ++c) {
    out.insert(out.end(), scratch.pieces[c].begin(), scratch.pieces[c].end());
    piece_edge.insert(piece_edge.end(), scratch.piece_edge[c].begin(), scratch.piece_edge[c].end());
    piece_inv_depth.insert(piece_inv_depth.end(), scratch.piece_inv_depth[c].begin(), scratch.piece_inv_depth[c].end());
  }
}

}  // namespace epi::render

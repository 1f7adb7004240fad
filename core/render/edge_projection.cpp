#include "render/edge_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace epi::render {

void filter_depth(const PointImage& points, const DepthFilterSettings& settings, std::vector<float>& out) {
  const int w = points.width, h = points.height;
  const float inf = std::numeric_limits<float>::infinity();
  // Rows first: max depth and point count over x-1..x+2; then columns over y-1..y+2.
  std::vector<float> row_max(size_t(w) * size_t(h));
  std::vector<uint8_t> row_count(size_t(w) * size_t(h));
  auto rows = [h](auto&& body) {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y != r.end(); ++y) body(y);
    });
  };
  rows([&](int y) {
    for (int x = 0; x < w; ++x) {
      float m = -inf;
      int n = 0;
      for (int dx = -1; dx <= 2; ++dx) {
        const int qx = x + dx;
        if (qx < 0 || qx >= w) continue;
        const size_t q = points.index(qx, y);
        if (points.point[q] < 0) continue;
        m = std::max(m, points.depth[q]), ++n;
      }
      row_max[points.index(x, y)] = m, row_count[points.index(x, y)] = uint8_t(n);
    }
  });
  out.assign(size_t(w) * size_t(h), inf);
  rows([&](int y) {
    for (int x = 0; x < w; ++x) {
      float m = -inf;
      int n = 0;
      for (int dy = -1; dy <= 2; ++dy) {
        const int qy = y + dy;
        if (qy < 0 || qy >= h) continue;
        m = std::max(m, row_max[points.index(x, qy)]), n += row_count[points.index(x, qy)];
      }
      if (n == 0) continue;
      const float empty = float(16 - n) / 16.0f;
      out[points.index(x, y)] = m * (1.0f + settings.base_offset + settings.sparse_offset * empty);
    }
  });
}

EdgeFate project_edge(const ViewFrame& frame, const glm::dvec3& a, const glm::dvec3& b,
                      std::span<const float> filtered_depth, std::vector<Segment>& out) {
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
  if (filtered_depth.empty()) {
    const glm::dvec2 s = point_at(t0), e = point_at(t1);
    out.push_back({s.x, s.y, e.x, e.y});
    return EdgeFate::visible;
  }

  // Occlusion culling: 1/depth is linear in screen space along the projected segment.
  const double inv0 = 1.0 / double(q0.depth), inv1 = 1.0 / double(q1.depth);
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
      const glm::dvec2 s = point_at(t_at(run_start)), e = point_at(t_at(end));
      out.push_back({s.x, s.y, e.x, e.y});
      any = true;
      run_start = -1;
    }
    previous = next;
  }
  return any ? EdgeFate::visible : EdgeFate::culled;
}

}  // namespace epi::render

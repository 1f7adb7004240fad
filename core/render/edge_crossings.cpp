#include "render/edge_crossings.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace epi::render {

namespace {

bool is_barrier(edges::EdgeKind kind) {
  return kind == edges::EdgeKind::silhouette || kind == edges::EdgeKind::border || kind == edges::EdgeKind::sharp;
}

double cross(glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

bool on_segment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}

// Whether closed segments ab and cd share a point (collinear overlaps included), and where along
// cd: `u` in [0, 1] at a proper crossing; -1 where they touch along a stretch or at an end.
bool touches(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d, double& u) {
  const double d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    u = d3 / (d3 - d4);
    return true;
  }
  u = -1.0;
  return (d1 == 0 && on_segment(a, c, d)) || (d2 == 0 && on_segment(b, c, d)) || (d3 == 0 && on_segment(c, a, b)) ||
         (d4 == 0 && on_segment(d, a, b));
}

// Clips s to the image grown by one cell (Liang-Barsky), and its ends' 1/depth with it; false
// when nothing is left.
bool clip(Segment& s, glm::dvec2& inv_depth, int w, int h) {
  if (!(std::isfinite(s.x0) && std::isfinite(s.y0) && std::isfinite(s.x1) && std::isfinite(s.y1))) return false;
  const double m = EdgeCrossings::kCell, dx = s.x1 - s.x0, dy = s.y1 - s.y0;
  double t0 = 0.0, t1 = 1.0;
  const double p[4] = {-dx, dx, -dy, dy}, q[4] = {s.x0 + m, w + m - s.x0, s.y0 + m, h + m - s.y0};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0.0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
  }
  if (t0 > t1) return false;
  s = {s.x0 + t0 * dx, s.y0 + t0 * dy, s.x0 + t1 * dx, s.y0 + t1 * dy};
  const double di = inv_depth.y - inv_depth.x;
  inv_depth = {inv_depth.x + t0 * di, inv_depth.x + t1 * di};
  return true;
}

}  // namespace

void EdgeCrossings::build(std::span<const Segment> segments, std::span<const edges::EdgeKind> kinds, int w, int h,
                          std::span<const glm::dvec2> inv_depths) {
  cells_x_ = std::max(1, (w + kCell - 1) / kCell), cells_y_ = std::max(1, (h + kCell - 1) / kCell);
  const bool with_depths = !inv_depths.empty();
  if (with_depths && inv_depths.size() != segments.size())
    throw std::invalid_argument("EdgeCrossings::build: one pair of inverse depths per segment");
  pieces_.clear();
  inv_depths_.clear();
  pairs_.clear();
  auto cell_x = [&](double x) { return std::clamp(int(std::floor(x / kCell)), 0, cells_x_ - 1); };
  auto cell_y = [&](double y) { return std::clamp(int(std::floor(y / kCell)), 0, cells_y_ - 1); };
  for (size_t k = 0; k < segments.size() && k < kinds.size(); ++k) {
    if (!is_barrier(kinds[k])) continue;
    Segment s = segments[k];
    glm::dvec2 inv_depth = with_depths ? inv_depths[k] : glm::dvec2(0.0);
    if (!clip(s, inv_depth, w, h)) continue;
    const uint32_t piece = uint32_t(pieces_.size());
    pieces_.push_back(s);
    if (with_depths) inv_depths_.push_back(inv_depth);
    // Walk the segment in steps of at most one cell; each step's bounding box (at most 2x2
    // cells) lists the piece, so every cell the segment touches lists it.
    const double length = std::hypot(s.x1 - s.x0, s.y1 - s.y0);
    const int steps = std::max(1, int(std::ceil(length / kCell)));
    for (int j = 0; j < steps; ++j) {
      const double t0 = double(j) / steps, t1 = double(j + 1) / steps;
      const double ax = s.x0 + t0 * (s.x1 - s.x0), ay = s.y0 + t0 * (s.y1 - s.y0);
      const double bx = s.x0 + t1 * (s.x1 - s.x0), by = s.y0 + t1 * (s.y1 - s.y0);
      for (int cy = cell_y(std::min(ay, by)); cy <= cell_y(std::max(ay, by)); ++cy)
        for (int cx = cell_x(std::min(ax, bx)); cx <= cell_x(std::max(ax, bx)); ++cx)
          pairs_.emplace_back(uint32_t(cy * cells_x_ + cx), piece);
    }
  }
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  cell_start_.assign(size_t(cells_x_) * size_t(cells_y_) + 1, 0);
  for (const auto& p : pairs_) ++cell_start_[p.first + 1];
  for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cell_pieces_.resize(pairs_.size());
  for (size_t k = 0; k < pairs_.size(); ++k) cell_pieces_[k] = pairs_[k].second;  // sorted by cell
}

bool EdgeCrossings::any_piece_near(int x0, int y0, int x1, int y1) const {
  if (pieces_.empty()) return false;
  const int cx0 = std::clamp(x0 / kCell, 0, cells_x_ - 1), cx1 = std::clamp(x1 / kCell, 0, cells_x_ - 1);
  const int cy0 = std::clamp(y0 / kCell, 0, cells_y_ - 1), cy1 = std::clamp(y1 / kCell, 0, cells_y_ - 1);
  for (int cy = cy0; cy <= cy1; ++cy) {
    const size_t row = size_t(cy) * size_t(cells_x_);
    if (cell_start_[row + size_t(cx1) + 1] != cell_start_[row + size_t(cx0)]) return true;  // CSR: the row's cells in one span
  }
  return false;
}

bool EdgeCrossings::separated(glm::dvec2 a, glm::dvec2 b, double nearer_than) const {
  if (pieces_.empty()) return false;
  // A piece counts where 1/depth there exceeds this (every piece when depths are unknown).
  const bool any_depth = inv_depths_.empty() || !(nearer_than < std::numeric_limits<double>::infinity());
  const double least_inv = 1.0 / nearer_than;
  const int x0 = std::clamp(int(std::floor(std::min(a.x, b.x) / kCell)), 0, cells_x_ - 1);
  const int x1 = std::clamp(int(std::floor(std::max(a.x, b.x) / kCell)), 0, cells_x_ - 1);
  const int y0 = std::clamp(int(std::floor(std::min(a.y, b.y) / kCell)), 0, cells_y_ - 1);
  const int y1 = std::clamp(int(std::floor(std::max(a.y, b.y) / kCell)), 0, cells_y_ - 1);
  for (int cy = y0; cy <= y1; ++cy)
    for (int cx = x0; cx <= x1; ++cx) {
      const size_t c = size_t(cy) * size_t(cells_x_) + size_t(cx);
      for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const uint32_t piece = cell_pieces_[k];
        const Segment& s = pieces_[piece];
        double u;
        if (!touches(a, b, {s.x0, s.y0}, {s.x1, s.y1}, u)) continue;
        if (any_depth) return true;
        const glm::dvec2 inv = inv_depths_[piece];
        if ((u >= 0.0 ? inv.x + u * (inv.y - inv.x) : std::max(inv.x, inv.y)) > least_inv) return true;
      }
    }
  return false;
}

}  // namespace epi::render

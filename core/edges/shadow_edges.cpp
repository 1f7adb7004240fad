#include "edges/shadow_edges.h"

#include <algorithm>
#include <cmath>

namespace epi::edges {
namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

// The event plane with a 2D frame, and the wedge as three half-planes.
struct EventFrame {
  const ShadowEvent& event;
  glm::dvec3 origin, axis_u, axis_v, normal;
  double scale = 0.0;
  glm::dvec2 b0, b1, s0, s1, dir;  // 2D images of the event's points (dir: parallel events)
  struct HalfPlane {
    glm::dvec2 point, inward;  // keep inward . (x - point) >= offset
    double offset;
  };
  HalfPlane bounds[3];  // the wedge beyond the blocker
  HalfPlane before[4];  // between the light and the blocker: occluders there void the event
  int before_count = 3;

  explicit EventFrame(const ShadowEvent& e) : event(e) {
    normal = e.normal();
    origin = e.blocker0;
    glm::dvec3 along = e.shape == EventShape::edge_vertex ? e.source1 - e.source0 : e.blocker1 - e.blocker0;
    axis_u = glm::normalize(along);
    normal = glm::normalize(normal);
    axis_v = glm::cross(normal, axis_u);
    scale = glm::length(e.blocker1 - e.blocker0) + glm::length(e.source1 - e.source0) +
            (e.shape == EventShape::parallel ? 0.0 : glm::length(e.blocker0 - e.source0));
    b0 = to2(e.blocker0), b1 = to2(e.blocker1);
    s0 = to2(e.source0), s1 = to2(e.source1);
    dir = glm::dvec2(glm::dot(e.source0, axis_u), glm::dot(e.source0, axis_v));
    const glm::dvec2 inside = to2(e.base(0.5) + e.direction(0.5));
    const double t_min = 1e-7 * scale;  // just beyond the blocker: its own edge is no shadow edge
    switch (e.shape) {
      case EventShape::vertex_edge:
        bounds[0] = half_plane(s0, b0, inside, 0.0), bounds[1] = half_plane(s0, b1, inside, 0.0);
        bounds[2] = half_plane(b0, b1, inside, t_min);
        before[3] = half_plane(s0, s0 + (b1 - b0), 0.5 * (b0 + b1), 0.0), before_count = 4;
        break;
      case EventShape::edge_vertex:
        bounds[0] = half_plane(s0, b0, inside, 0.0), bounds[1] = half_plane(s1, b0, inside, 0.0);
        bounds[2] = half_plane(b0, b0 + (s1 - s0), inside, t_min);
        before[0] = half_plane(s0, b0, 0.5 * (s0 + s1), 0.0), before[1] = half_plane(s1, b0, 0.5 * (s0 + s1), 0.0);
        before[3] = half_plane(s0, s1, b0, 0.0), before_count = 4;
        break;
      case EventShape::parallel:
        bounds[0] = half_plane(b0, b0 + dir, inside, 0.0), bounds[1] = half_plane(b1, b1 + dir, inside, 0.0);
        bounds[2] = half_plane(b0, b1, inside, t_min);
        break;
    }
    if (e.shape != EventShape::edge_vertex) before[0] = bounds[0], before[1] = bounds[1];
    before[2] = {bounds[2].point, -bounds[2].inward, 2.0 * t_min};  // the near side, short of the blocker
  }

  glm::dvec2 to2(const glm::dvec3& p) const { return {glm::dot(p - origin, axis_u), glm::dot(p - origin, axis_v)}; }
  glm::dvec3 to3(const glm::dvec2& p) const { return origin + p.x * axis_u + p.y * axis_v; }

  static HalfPlane half_plane(const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& inside, double offset) {
    const glm::dvec2 d = glm::normalize(q - p);
    glm::dvec2 inward(-d.y, d.x);
    if (glm::dot(inward, inside - p) < 0.0) inward = -inward;
    return {p, inward, offset};
  }

  // Ray u: origin B(u) and direction D(u), in 2D.
  glm::dvec2 ray_origin(double u) const { return event.shape == EventShape::edge_vertex ? b0 : b0 + u * (b1 - b0); }
  glm::dvec2 ray_direction(double u) const {
    switch (event.shape) {
      case EventShape::vertex_edge: return ray_origin(u) - s0;
      case EventShape::edge_vertex: return b0 - (s0 + u * (s1 - s0));
      default: return dir;
    }
  }

  // u of a 2D point: where the line through the point and the pencil's centre crosses B or S.
  double u_of(const glm::dvec2& x) const {
    switch (event.shape) {
      case EventShape::vertex_edge: return -cross2(x - s0, b0 - s0) / cross2(x - s0, b1 - b0);
      case EventShape::edge_vertex: return -cross2(x - b0, s0 - b0) / cross2(x - b0, s1 - s0);
      default: return cross2(x - b0, dir) / cross2(b1 - b0, dir);
    }
  }

  // Distance parameter t where ray u meets the line through p, q (infinite if parallel).
  double t_at(double u, const glm::dvec2& p, const glm::dvec2& q) const {
    const glm::dvec2 o = ray_origin(u), d = ray_direction(u);
    const double denominator = cross2(d, q - p);
    if (denominator == 0.0) return INFINITY;
    return cross2(p - o, q - p) / denominator;
  }
  glm::dvec2 point_at(double u, const glm::dvec2& p, const glm::dvec2& q) const {
    const double t = t_at(u, p, q);
    return std::isfinite(t) ? ray_origin(u) + t * ray_direction(u) : p;
  }
};

struct Candidate {
  glm::dvec2 p, q;  // clipped to the wedge, 2D
  double u0, u1;    // u range, u0 <= u1
  uint32_t receiver, face;
  bool occluder_only;  // a face of the blocker turned away from the light: blocks, shows no edge
};

bool clip(const EventFrame::HalfPlane& h, glm::dvec2& p, glm::dvec2& q) {
  const double dp = glm::dot(h.inward, p - h.point) - h.offset, dq = glm::dot(h.inward, q - h.point) - h.offset;
  if (dp < 0 && dq < 0) return false;
  if (dp < 0) p = p + (q - p) * (dp / (dp - dq));
  if (dq < 0) q = q + (p - q) * (dq / (dq - dp));
  return true;
}

glm::dvec3 transform_point(const glm::dmat4& m, const glm::dvec3& p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); }

}  // namespace

glm::dvec2 event_coordinates(const ShadowEvent& event, const glm::dvec3& point) {
  const EventFrame frame(event);
  const glm::dvec2 x = frame.to2(point);
  const double u = frame.u_of(x);
  const glm::dvec2 d = frame.ray_direction(u);
  return {u, glm::dot(x - frame.ray_origin(u), d) / glm::dot(d, d)};
}

size_t shadow_edges_of_event(const ShadowEvent& event, uint32_t event_index, std::span<const ReceiverView> receivers,
                             std::vector<ShadowEdge>& out) {
  if (glm::length(event.normal()) == 0.0) return 0;
  const EventFrame frame(event);
  if (!std::isfinite(frame.normal.x)) return 0;
  std::vector<Candidate> candidates;
  size_t searched = 0;

  for (const ReceiverView& r : receivers) {
    // The event lies in its plane: a receiver whose sphere misses the plane has no face there.
    if (std::abs(glm::dot(frame.normal, r.bound_centre - event.blocker0)) > r.bound_radius) continue;
    ++searched;
    const EdgeMesh& m = *r.mesh;
    // The event plane and the light in the receiver's object space.
    const glm::dvec3 p0 = transform_point(r.world_to_object, event.blocker0);
    const glm::dvec3 p1 = transform_point(r.world_to_object, event.base(1.0) + event.direction(1.0));
    const glm::dvec3 p2 = transform_point(r.world_to_object, event.base(0.0) + event.direction(0.0));
    glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
    if (glm::length(n) == 0.0) continue;
    n = glm::normalize(n);
    const double c = glm::dot(n, p0);
    ViewBox light;
    std::vector<Viewpoint> sources;
    if (event.shape == EventShape::parallel) {
      const glm::dvec3 towards = -glm::dvec3(r.world_to_object * glm::dvec4(event.source0, 0.0));
      sources.push_back(EdgeMesh::local_direction(towards));
    } else {
      sources.push_back(m.local_point(transform_point(r.world_to_object, event.source0)));
      if (event.shape == EventShape::edge_vertex)
        sources.push_back(m.local_point(transform_point(r.world_to_object, event.source1)));
    }
    light = ViewBox::point(sources[0]);
    for (const Viewpoint& s : sources) {
      light.x = {std::min(light.x.lo, double(s.x)), std::max(light.x.hi, double(s.x))};
      light.y = {std::min(light.y.lo, double(s.y)), std::max(light.y.hi, double(s.y))};
      light.z = {std::min(light.z.lo, double(s.z)), std::max(light.z.hi, double(s.z))};
    }
    const double tolerance = 1e-9 * (std::fabs(c) + 1.0);

    // Rays leaving a blocker's silhouette at a saddle run inside it and leave through a face turned
    // away from the light: for the blocker itself every face occludes.
    const bool self = r.object == event.blocker;
    // The wedge's sides (rays from the light through the blocker edge's ends, both ways from the
    // blocker), as half-spaces across the event plane; EV wedges (a bow tie) use the plane only.
    ReceiverTree::HalfSpace sides[2];
    int side_count = 0;
    if (event.shape != EventShape::edge_vertex) {
      const glm::dvec3 b0 = transform_point(r.world_to_object, event.blocker0);
      const glm::dvec3 b1 = transform_point(r.world_to_object, event.blocker1);
      const glm::dvec3 d0 = transform_point(r.world_to_object, event.blocker0 + event.direction(0.0)) - b0;
      const glm::dvec3 d1 = transform_point(r.world_to_object, event.blocker1 + event.direction(1.0)) - b1;
      glm::dvec3 m0 = glm::cross(d0, n), m1 = glm::cross(d1, n);
      if (glm::dot(m0, b1 - b0) < 0.0) m0 = -m0;
      if (glm::dot(m1, b0 - b1) < 0.0) m1 = -m1;
      const double l0 = glm::length(m0), l1 = glm::length(m1);
      if (l0 > 0.0 && l1 > 0.0) {
        m0 /= l0, m1 /= l1;
        sides[0] = {m0, glm::dot(m0, b0)}, sides[1] = {m1, glm::dot(m1, b1)};
        side_count = 2;
      }
    }
    r.tree->faces_near_plane(n, c, tolerance, self ? nullptr : &light, std::span(sides, side_count), [&](uint32_t f) {
      const glm::uvec3& tri = m.faces[f];
      bool lit = false;
      for (const Viewpoint& s : sources) lit |= front_facing(m, f, s);
      if (!lit && !self) return;
      if (self)  // faces touching the blocker's own edge or vertex only occlude
        for (int k = 0; k < 3; ++k)
          if (tri[k] == event.blocker_v0 || tri[k] == event.blocker_v1) lit = false;
      // Triangle against the plane.
      glm::dvec3 corner[3];
      double distance[3];
      for (int k = 0; k < 3; ++k) corner[k] = m.positions[tri[k]], distance[k] = glm::dot(n, corner[k]) - c;
      glm::dvec3 hit[3];
      int hits = 0;
      for (int k = 0; k < 3 && hits < 2; ++k) {
        const int j = (k + 1) % 3;
        if (distance[k] == 0.0) hit[hits++] = corner[k];
        else if ((distance[k] > 0.0) != (distance[j] > 0.0) && distance[j] != 0.0)
          hit[hits++] = corner[k] + (corner[j] - corner[k]) * (distance[k] / (distance[k] - distance[j]));
      }
      if (hits < 2) return;
      const glm::dvec2 hit_p = frame.to2(transform_point(r.object_to_world, hit[0]));
      const glm::dvec2 hit_q = frame.to2(transform_point(r.object_to_world, hit[1]));
      auto add = [&](std::span<const EventFrame::HalfPlane> region, bool occluder_only) {
        glm::dvec2 p = hit_p, q = hit_q;
        for (const auto& h : region)
          if (!clip(h, p, q)) return;
        if (glm::length(q - p) <= 1e-12 * frame.scale) return;
        double u0 = frame.u_of(p), u1 = frame.u_of(q);
        if (!std::isfinite(u0) || !std::isfinite(u1)) return;
        if (u0 > u1) std::swap(u0, u1), std::swap(p, q);
        candidates.push_back({p, q, std::clamp(u0, 0.0, 1.0), std::clamp(u1, 0.0, 1.0), r.object, f, occluder_only});
      };
      add(frame.bounds, !lit);
      add(std::span(frame.before, frame.before_count), true);
    });
  }
  if (candidates.empty()) return searched;

  // 1D visibility along u: cut at every candidate end and wherever two candidates that overlap in
  // u cross (interpenetrating receivers); on each interval between cuts the nearest candidate
  // along the ray wins.
  std::vector<double> cuts;
  for (const Candidate& c : candidates) cuts.push_back(c.u0), cuts.push_back(c.u1);
  std::vector<size_t> by_start(candidates.size());
  for (size_t k = 0; k < by_start.size(); ++k) by_start[k] = k;
  std::sort(by_start.begin(), by_start.end(), [&](size_t a, size_t b) { return candidates[a].u0 < candidates[b].u0; });
  for (size_t i = 0; i < by_start.size(); ++i) {
    const Candidate& a = candidates[by_start[i]];
    for (size_t j = i + 1; j < by_start.size() && candidates[by_start[j]].u0 < a.u1; ++j) {
      const Candidate& b = candidates[by_start[j]];
      // Segments p + s (q - p) and p' + r (q' - p') in the event plane's 2D frame.
      const glm::dvec2 da = a.q - a.p, db = b.q - b.p;
      const double denominator = cross2(da, db);
      if (denominator == 0.0) continue;
      const double sa = cross2(b.p - a.p, db) / denominator, sb = cross2(b.p - a.p, da) / denominator;
      if (sa <= 0.0 || sa >= 1.0 || sb <= 0.0 || sb >= 1.0) continue;
      const double u = frame.u_of(a.p + sa * da);
      if (std::isfinite(u) && u > std::max(a.u0, b.u0) && u < std::min(a.u1, b.u1)) cuts.push_back(u);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  int previous = -1;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double ua = cuts[i], ub = cuts[i + 1], um = 0.5 * (ua + ub);
    if (ub - ua <= 1e-12) continue;
    int best = -1;
    double best_t = INFINITY;
    for (size_t k = 0; k < candidates.size(); ++k) {
      const Candidate& c = candidates[k];
      if (c.u0 > um || c.u1 < um) continue;
      const double t = frame.t_at(um, c.p, c.q);
      if ((t > -1.0 || event.shape == EventShape::parallel) && t < best_t) best_t = t, best = int(k);
    }
    if (best < 0 || candidates[best].occluder_only) {
      previous = -1;
      continue;
    }
    const Candidate& c = candidates[best];
    const glm::dvec3 a = frame.to3(frame.point_at(ua, c.p, c.q)), b = frame.to3(frame.point_at(ub, c.p, c.q));
    if (best == previous && !out.empty()) {
      out.back().b = b;  // continue the same piece
      continue;
    }
    out.push_back({a, b, c.receiver, c.face, event.blocker, event.light, event.kind, event_index});
    previous = best;
  }
  return searched;
}

}  // namespace epi::edges

#include "edges/shadow_events.h"

#include <algorithm>
#include <cmath>

namespace epi::edges {

glm::dvec3 ShadowEvent::base(double u) const {
  return shape == EventShape::edge_vertex ? blocker0 : blocker0 + u * (blocker1 - blocker0);
}

glm::dvec3 ShadowEvent::direction(double u) const {
  switch (shape) {
    case EventShape::vertex_edge: return base(u) - source0;
    case EventShape::edge_vertex: return blocker0 - (source0 + u * (source1 - source0));
    default: return source0;
  }
}

glm::dvec3 ShadowEvent::normal() const {
  switch (shape) {
    case EventShape::vertex_edge: return glm::cross(blocker1 - blocker0, blocker0 - source0);
    case EventShape::edge_vertex: return glm::cross(source1 - source0, blocker0 - source0);
    default: return glm::cross(blocker1 - blocker0, source0);
  }
}

namespace {

glm::dvec3 transform_point(const glm::dmat4& m, const glm::dvec3& p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); }
glm::dvec3 transform_vector(const glm::dmat4& m, const glm::dvec3& v) { return glm::dvec3(m * glm::dvec4(v, 0.0)); }

int side(const glm::dvec3& normal, const glm::dvec3& origin, const glm::dvec3& p, double tolerance) {
  const double s = glm::dot(normal, p - origin);
  return s > tolerance ? 1 : s < -tolerance ? -1 : 0;
}

// Silhouette edges of the blocker from one viewpoint (tree or brute force).
void silhouettes(const BlockerView& b, const Viewpoint& v, std::vector<uint32_t>& out) {
  if (b.tree) {
    b.tree->silhouettes(*b.mesh, v, out);
  } else {
    std::vector<uint8_t> facing;
    brute_force_silhouettes(*b.mesh, v, facing, out);
  }
}

ShadowEvent hard_event(const BlockerView& b, uint32_t e, uint32_t light_index) {
  const EdgeMesh& m = *b.mesh;
  ShadowEvent event;
  event.blocker0 = transform_point(b.object_to_world, m.positions[m.v0[e]]);
  event.blocker1 = transform_point(b.object_to_world, m.positions[m.v1[e]]);
  event.blocker_v0 = m.v0[e], event.blocker_v1 = m.v1[e];
  event.light = light_index, event.blocker = b.object;
  return event;
}

// The third vertex of a face, opposite the edge (a, b).
uint32_t opposite(const glm::uvec3& f, uint32_t a, uint32_t b) {
  for (int k = 0; k < 3; ++k)
    if (f[k] != a && f[k] != b) return f[k];
  return f[0];
}

// Whether every face of edge e lies on one side of the plane through e and a viewpoint (the
// edge bounds the blocker's image seen from there). For a manifold edge that is Equation 1; a
// border edge's single face always does unless the viewpoint is in its plane; a non-manifold edge
// needs all its faces on one side. Returns the side (+1 or -1) or 0. World space.
int blocker_side_of_edge(const EdgeMesh& m, const std::vector<glm::dvec3>& world, uint32_t e,
                         const glm::dvec3& normal, const glm::dvec3& origin, double tolerance) {
  uint32_t scratch[2];
  int common = 0;
  for (uint32_t f : m.edge_faces(e, scratch)) {
    const int s = side(normal, origin, world[opposite(m.faces[f], m.v0[e], m.v1[e])], tolerance);
    if (s == 0 || (common != 0 && s != common)) return 0;
    common = s;
  }
  return common;
}

// The 1-ring of a blocker vertex w as its other corners (p, q), in the winding of each face.
struct Corner {
  glm::dvec3 p, q;
};

// A part [u0, u1] of a light edge whose EV event with a vertex exists, and its kind.
struct EvPiece {
  double u0, u1;
  EventKind kind;
};

struct EvScratch {
  std::vector<double> cuts;
  std::vector<std::pair<double, double>> arcs;
};

// Whether the faces around w bound a convex cone (no reflex edge at w): every corner of the ring on
// or below every ring face's plane, up to the rounding of float vertex positions (coplanar
// neighbours, such as the two halves of a planar quad, come out a few ulps either way). The image
// of a convex cone is a sector narrower than a half-plane, or the whole plane: never an umbral EV
// event.
bool convex_cone(const glm::dvec3& w, const std::vector<Corner>& ring) {
  double magnitude = glm::length(w);
  for (const Corner& c : ring) magnitude = std::max({magnitude, glm::length(c.p), glm::length(c.q)});
  const double tolerance = 2e-6 * magnitude;
  for (const Corner& f : ring) {
    glm::dvec3 normal = glm::cross(f.p - w, f.q - w);
    const double length = glm::length(normal);
    if (!(length > 0.0)) continue;
    normal /= length;
    for (const Corner& g : ring)
      if (glm::dot(normal, g.p - w) > tolerance || glm::dot(normal, g.q - w) > tolerance) return false;
  }
  return true;
}

// The EV test for one light edge [s0, s1] and one blocker vertex w (docs/edges.md, "EV events").
// `n` is the unit normal of the plane through the light edge and w, oriented so that the light
// lies on its positive side. Seen along a ray from a light-edge point through w, each face around
// w covers a sector around the image of w; the event plane's trace is the line through it along
// the light edge. The plane is an event of the shadow-volume boundary where the image of w, moving
// across that line, changes whether the light is touched or covered:
//   penumbral: every face lies strictly on the far side (the blocker just touches the light's edge
//              from outside);
//   umbral:    the faces cover the whole light side of the line and leave a gap on the far side
//              (a saddle or concave vertex: the light is just covered, a hole is about to open).
// The first depends on the plane only; the second on the ray direction too, so the light edge is
// cut where a face plane at w crosses it and each piece is tested. Appends [u0, u1] pieces.
// `convex`: the vertex's convex_cone(), computed on first use (-1: not yet).
void ev_pieces(const glm::dvec3& s0, const glm::dvec3& s1, const glm::dvec3& w, const glm::dvec3& n,
               const std::vector<Corner>& ring, int& convex, EvScratch& scratch, std::vector<EvPiece>& out) {
  constexpr double kRelative = 1e-9;
  auto height = [&](const glm::dvec3& p) {
    const double h = glm::dot(n, p - w);
    return h * h <= kRelative * kRelative * glm::dot(p - w, p - w) ? 0.0 : h;
  };
  bool above = false, below = false;
  for (const Corner& c : ring)
    for (const glm::dvec3* p : {&c.p, &c.q}) {
      const double h = height(*p);
      above |= h > 0.0, below |= h < 0.0;
    }
  if (!below) return;
  if (!above) {
    out.push_back({0.0, 1.0, EventKind::penumbral});
    return;
  }
  if (convex < 0) convex = convex_cone(w, ring);
  if (convex) return;

  // The light-edge point S(u) seen through w along the line from a point c of the event plane.
  auto u_through = [&](const glm::dvec3& c) {
    const double denominator = glm::dot(n, glm::cross(c - w, s1 - s0));
    return denominator == 0.0 ? -1.0 : -glm::dot(n, glm::cross(c - w, s0 - w)) / denominator;
  };
  std::vector<double>& cuts = scratch.cuts;
  cuts.assign({0.0, 1.0});
  for (const Corner& c : ring) {
    const double hp = height(c.p), hq = height(c.q);
    if (hp == 0.0) cuts.push_back(u_through(c.p));
    if (hq == 0.0) cuts.push_back(u_through(c.q));
    if ((hp > 0.0 && hq < 0.0) || (hp < 0.0 && hq > 0.0)) cuts.push_back(u_through(c.p + (c.q - c.p) * (hp / (hp - hq))));
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::remove_if(cuts.begin(), cuts.end(), [](double u) { return !(u >= 0.0 && u <= 1.0); }), cuts.end());

  std::vector<std::pair<double, double>>& arcs = scratch.arcs;
  auto light_side_covered = [&](const glm::dvec3& s) {
    // Image frame at w: e1 along the event line, n across it (light side positive).
    const glm::dvec3 e1 = glm::cross(n, glm::normalize(w - s));
    arcs.clear();
    auto angle = [&](const glm::dvec3& p, bool& ok) {
      const double h = height(p), x = glm::dot(e1, p - w);
      ok = std::fabs(x) > kRelative * glm::length(p - w) || h != 0.0;
      const double a = std::atan2(h, x);
      return a < 0.0 ? a + 2.0 * M_PI : a;
    };
    for (const Corner& c : ring) {
      bool ok_p, ok_q;
      double a = angle(c.p, ok_p), b = angle(c.q, ok_q);
      if (!ok_p || !ok_q) continue;
      double span = b - a;
      if (span > M_PI) span -= 2.0 * M_PI;
      if (span < -M_PI) span += 2.0 * M_PI;
      if (std::fabs(span) >= M_PI - 1e-9) continue;  // the face is seen edge-on
      if (span < 0.0) a = b, span = -span;
      if (a + span > 2.0 * M_PI) {
        arcs.push_back({a, 2.0 * M_PI}), arcs.push_back({0.0, a + span - 2.0 * M_PI});
      } else {
        arcs.push_back({a, a + span});
      }
    }
    std::sort(arcs.begin(), arcs.end());
    // Union of the arcs: must hold [0, pi] and leave a gap.
    constexpr double kGap = 1e-12;
    double reach = 0.0;
    bool started = false, gap = false;
    for (const auto& [a, b] : arcs) {
      if (!started) {
        if (a > kGap) gap = true;
        if (a > kGap) return false;  // 0 not covered
        started = true, reach = b;
        continue;
      }
      if (a > reach + kGap) {
        if (reach < M_PI) return false;
        gap = true;
      }
      reach = std::max(reach, b);
    }
    if (!started || reach < M_PI) return false;
    return gap || reach < 2.0 * M_PI - kGap;
  };
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double ua = cuts[i], ub = cuts[i + 1];
    if (ub - ua <= 1e-9) continue;
    if (!light_side_covered(s0 + 0.5 * (ua + ub) * (s1 - s0))) continue;
    if (!out.empty() && out.back().kind == EventKind::umbral && out.back().u1 == ua) out.back().u1 = ub;
    else out.push_back({ua, ub, EventKind::umbral});
  }
}

// Whether edge e (two faces) is a silhouette from some point of the light segment [a, b] (local
// frame, double): the product of the two faces' Equation 1 values, a quadratic along the segment,
// is negative or zero somewhere. An edge that is a silhouette from a point of the light polygon is
// one from a point of its outline (the region where the two faces differ is a wedge, unbounded).
bool silhouette_along(const EdgeMesh& m, uint32_t e, const glm::dvec3& a, const glm::dvec3& b) {
  auto value = [&](uint32_t f, const glm::dvec3& p) {
    return double(m.nx[f]) * p.x + double(m.ny[f]) * p.y + double(m.nz[f]) * p.z - double(m.d[f]);
  };
  const double a0 = value(m.face0[e], a), b0 = value(m.face0[e], b) - a0;
  const double a1 = value(m.face1[e], a), b1 = value(m.face1[e], b) - a1;
  auto product = [&](double t) { return (a0 + b0 * t) * (a1 + b1 * t); };
  if (product(0.0) <= 0.0 || product(1.0) <= 0.0) return true;
  if (b0 * b1 == 0.0) return false;
  const double t = -(a0 * b1 + a1 * b0) / (2.0 * b0 * b1);
  return t > 0.0 && t < 1.0 && product(t) <= 0.0;
}

void area_light_events(const BlockerView& b, const EdgeLight& light, uint32_t light_index, std::vector<ShadowEvent>& out) {
  const EdgeMesh& m = *b.mesh;
  const glm::dmat4 world_to_object = glm::inverse(b.object_to_world);
  std::vector<glm::dvec3> world_blocker(m.positions.size());
  for (size_t v = 0; v < m.positions.size(); ++v) world_blocker[v] = transform_point(b.object_to_world, m.positions[v]);
  double scale = 0.0;
  for (const auto& loop : light.outlines)
    for (const glm::dvec3& p : loop) scale = std::max(scale, glm::length(p));
  for (const glm::dvec3& p : world_blocker) scale = std::max(scale, glm::length(p));
  const double tolerance = 1e-12 * scale * scale;

  // The light's normal (Newell, over all loops: holes wind the other way), so that the light's
  // inside is to the left of each outline edge seen from that normal.
  glm::dvec3 light_normal(0.0);
  for (const auto& loop : light.outlines)
    for (size_t i = 0; i < loop.size(); ++i)
      light_normal += glm::cross(loop[i] - loop[0], loop[(i + 1) % loop.size()] - loop[0]);
  if (glm::length(light_normal) == 0.0) return;
  light_normal = glm::normalize(light_normal);

  // Light vertices in the blocker's local frame, and their bounding box for the tree traversal.
  ViewBox box{{INFINITY, -INFINITY}, {INFINITY, -INFINITY}, {INFINITY, -INFINITY}, 1.0};
  std::vector<std::vector<Viewpoint>> local(light.outlines.size());
  std::vector<std::vector<glm::dvec3>> local_double(light.outlines.size());
  for (size_t l = 0; l < light.outlines.size(); ++l)
    for (const glm::dvec3& p : light.outlines[l]) {
      const glm::dvec3 q = transform_point(world_to_object, p);
      const Viewpoint v = m.local_point(q);
      local[l].push_back(v);
      local_double[l].push_back(q - m.origin);
      box.x = {std::min(box.x.lo, double(v.x)), std::max(box.x.hi, double(v.x))};
      box.y = {std::min(box.y.lo, double(v.y)), std::max(box.y.hi, double(v.y))};
      box.z = {std::min(box.z.lo, double(v.z)), std::max(box.z.hi, double(v.z))};
    }
  std::vector<uint32_t> candidates;
  if (b.tree) {
    b.tree->candidates(m, box, [&](uint32_t e) { candidates.push_back(e); });
    std::sort(candidates.begin(), candidates.end());
  } else {
    for (uint32_t e = 0; e < m.edge_count(); ++e)
      if (m.face0[e] != m.face1[e]) candidates.push_back(e);
  }

  // VE events: a convex light vertex v and a blocker edge that bounds the blocker's image from v.
  for (size_t l = 0; l < light.outlines.size(); ++l) {
    const auto& loop = light.outlines[l];
    const size_t n = loop.size();
    if (n < 3) continue;
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec3& v = loop[i];
      const glm::dvec3& prev = loop[(i + n - 1) % n];
      const glm::dvec3& next = loop[(i + 1) % n];
      // At a reflex (or straight) light vertex the light covers both sides of any line through
      // it: no umbra or penumbra boundary starts there.
      if (glm::dot(light_normal, glm::cross(v - prev, next - v)) <= 0.0) continue;
      auto try_edge = [&](uint32_t e) {
        // The plane through v and e must leave both light neighbours of v on one side.
        const uint32_t a = m.v0[e], bv = m.v1[e];
        const glm::dvec3 normal = glm::cross(world_blocker[a] - v, world_blocker[bv] - v);
        const int s_prev = side(normal, v, prev, tolerance), s_next = side(normal, v, next, tolerance);
        if (s_prev * s_next < 0 || (s_prev == 0 && s_next == 0)) return;
        const int light_side = s_prev != 0 ? s_prev : s_next;
        const int blocker_side = blocker_side_of_edge(m, world_blocker, e, normal, v, tolerance);
        if (blocker_side == 0) return;
        ShadowEvent event = hard_event(b, e, light_index);
        event.shape = EventShape::vertex_edge;
        event.source0 = event.source1 = v;
        event.kind = light_side == blocker_side ? EventKind::umbral : EventKind::penumbral;
        out.push_back(event);
      };
      for (uint32_t e : candidates)
        if (is_silhouette(m, e, local[l][i])) try_edge(e);
      for (uint32_t e : m.border_edges) try_edge(e);  // an open surface's outline always bounds its shadow
    }
  }

  // EV events: every blocker vertex on the outline of the blocker's image from some point of a
  // light edge (an end of an edge that is a silhouette from there, or of a border edge) against
  // that light edge; each (light edge, vertex) pair is tested once, in a fixed order (the same for
  // the tree and brute force). `touched` holds one bit per light edge (all bits past 64 edges).
  size_t light_edges = 0;
  for (const auto& loop : light.outlines) light_edges += loop.size() >= 3 ? loop.size() : 0;
  const bool per_edge_bits = light_edges <= 64;
  std::vector<uint64_t> touched(m.positions.size(), 0);
  for (uint32_t e : candidates) {
    uint64_t bits = 0;
    size_t k = 0;
    for (size_t l = 0; l < local_double.size(); ++l) {
      const size_t n = local_double[l].size();
      if (n < 3) continue;
      for (size_t i = 0; i < n; ++i, ++k)
        if (silhouette_along(m, e, local_double[l][i], local_double[l][(i + 1) % n])) bits |= per_edge_bits ? uint64_t(1) << k : ~uint64_t(0);
    }
    touched[m.v0[e]] |= bits, touched[m.v1[e]] |= bits;
  }
  // An open fan (a vertex on a border) may be part of a convex cone seen from inside it, whose
  // image covers more than a half-plane: the convex shortcut does not apply there.
  std::vector<uint8_t> on_border(m.positions.size(), 0);
  for (uint32_t e : m.border_edges) {
    touched[m.v0[e]] = touched[m.v1[e]] = ~uint64_t(0);
    on_border[m.v0[e]] = on_border[m.v1[e]] = 1;
  }

  std::vector<Corner> ring;
  std::vector<EvPiece> pieces;
  EvScratch scratch;
  for (uint32_t w = 0; w < touched.size(); ++w) {
    if (!touched[w]) continue;
    const glm::dvec3& wp = world_blocker[w];
    ring.clear();
    for (uint32_t r = m.ring_start[w]; r < m.ring_start[w + 1]; ++r) {
      const glm::uvec3& f = m.faces[m.ring_faces[r]];
      const int k = f.x == w ? 0 : f.y == w ? 1 : 2;
      ring.push_back({world_blocker[f[(k + 1) % 3]], world_blocker[f[(k + 2) % 3]]});
    }
    int convex = on_border[w] ? 0 : -1;
    size_t k = 0;
    for (size_t l = 0; l < light.outlines.size(); ++l) {
      const auto& loop = light.outlines[l];
      const size_t n = loop.size();
      if (n < 3) continue;
      for (size_t j = 0; j < n; ++j, ++k) {
        if (per_edge_bits && !((touched[w] >> k) & 1)) continue;
        const glm::dvec3 &s0 = loop[j], &s1 = loop[(j + 1) % n];
        glm::dvec3 normal = glm::cross(s1 - s0, wp - s0);
        const double length = glm::length(normal);
        if (!(length > 0.0)) continue;
        normal /= length;
        // The light's inside next to this edge, on one side of the plane (never in it: w would
        // be in the light's plane).
        const glm::dvec3 inward = glm::normalize(glm::cross(light_normal, s1 - s0));
        const double light_side = glm::dot(normal, inward);
        if (std::fabs(light_side) <= 1e-9) continue;
        if (light_side < 0.0) normal = -normal;
        pieces.clear();
        ev_pieces(s0, s1, wp, normal, ring, convex, scratch, pieces);
        for (const EvPiece& piece : pieces) {
          ShadowEvent ev;
          ev.shape = EventShape::edge_vertex;
          ev.kind = piece.kind;
          ev.source0 = s0 + piece.u0 * (s1 - s0), ev.source1 = s0 + piece.u1 * (s1 - s0);
          ev.blocker0 = ev.blocker1 = wp;
          ev.blocker_v0 = ev.blocker_v1 = w;
          ev.light = light_index, ev.blocker = b.object;
          out.push_back(ev);
        }
      }
    }
  }
}

}  // namespace

void find_shadow_events(const BlockerView& b, const EdgeLight& light, uint32_t light_index,
                        std::vector<ShadowEvent>& out) {
  const EdgeMesh& m = *b.mesh;
  if (light.type == EdgeLight::Type::area) return area_light_events(b, light, light_index, out);
  const glm::dmat4 world_to_object = glm::inverse(b.object_to_world);
  std::vector<uint32_t> edges;
  if (light.type == EdgeLight::Type::point) {
    silhouettes(b, m.local_point(transform_point(world_to_object, light.position)), edges);
  } else {
    silhouettes(b, EdgeMesh::local_direction(-transform_vector(world_to_object, light.direction)), edges);
  }
  // Border edges bound an open surface's shadow from every viewpoint (unless seen edge-on).
  const Viewpoint v = light.type == EdgeLight::Type::point
                          ? m.local_point(transform_point(world_to_object, light.position))
                          : EdgeMesh::local_direction(-transform_vector(world_to_object, light.direction));
  // A face seen edge-on from the light within rounding (the light in its plane) casts a shadow of
  // no width: where the light lies in both faces' planes, rounding alone would decide Equation 1.
  auto edge_on = [&](uint32_t f) {
    const float facing = m.nx[f] * v.x + m.ny[f] * v.y + m.nz[f] * v.z - m.d[f] * v.w;  // unit normal
    const float scale = std::abs(v.x) + std::abs(v.y) + std::abs(v.z) + std::abs(m.d[f] * v.w);
    return std::abs(facing) <= 1e-5f * scale;
  };
  for (uint32_t e : m.border_edges)
    if (!edge_on(m.face0[e])) edges.push_back(e);
  for (uint32_t e : edges) {
    if (edge_on(m.face0[e]) && edge_on(m.face1[e])) continue;
    // A non-manifold edge bounds the shadow only when all its faces (not just the two of
    // Equation 1) lie on one side of the plane through the light and the edge.
    if (m.flags[e] & kNonManifold) {
      const glm::dvec3 a = glm::dvec3(m.positions[m.v0[e]]) - m.origin, c = glm::dvec3(m.positions[m.v1[e]]) - m.origin;
      const glm::dvec3 towards = glm::dvec3(v.x, v.y, v.z) - double(v.w) * a;
      const glm::dvec3 normal = glm::cross(c - a, towards);
      uint32_t scratch[2];
      int common = 0;
      bool one_side = true;
      for (uint32_t f : m.edge_faces(e, scratch)) {
        const glm::dvec3 o = glm::dvec3(m.positions[opposite(m.faces[f], m.v0[e], m.v1[e])]) - m.origin;
        const double s = glm::dot(normal, o - a);
        const double tolerance = 1e-9 * glm::length(normal) * glm::length(o - a);  // coplanar within rounding
        const int sign = s > tolerance ? 1 : s < -tolerance ? -1 : 0;
        if (sign == 0 || (common != 0 && sign != common)) one_side = false;
        common = sign;
      }
      if (!one_side) continue;
    }
    ShadowEvent event = hard_event(b, e, light_index);
    event.shape = light.type == EdgeLight::Type::point ? EventShape::vertex_edge : EventShape::parallel;
    event.source0 = event.source1 = light.type == EdgeLight::Type::point ? light.position : light.direction;
    out.push_back(event);
  }
}

}  // namespace epi::edges

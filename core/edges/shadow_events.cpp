#include "edges/shadow_events.h"

#include <algorithm>
#include <set>
#include <tuple>

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

  // Light vertices in the blocker's local frame, and their bounding box for the tree traversal.
  ViewBox box{{INFINITY, -INFINITY}, {INFINITY, -INFINITY}, {INFINITY, -INFINITY}, 1.0};
  std::vector<std::vector<Viewpoint>> local(light.outlines.size());
  for (size_t l = 0; l < light.outlines.size(); ++l)
    for (const glm::dvec3& p : light.outlines[l]) {
      const Viewpoint v = m.local_point(transform_point(world_to_object, p));
      local[l].push_back(v);
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

  std::set<std::tuple<size_t, size_t, uint32_t>> ev_seen;  // (loop, light edge start, blocker vertex)
  for (size_t l = 0; l < light.outlines.size(); ++l) {
    const auto& loop = light.outlines[l];
    const size_t n = loop.size();
    if (n < 3) continue;
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec3& v = loop[i];
      const glm::dvec3& prev = loop[(i + n - 1) % n];
      const glm::dvec3& next = loop[(i + 1) % n];
      for (uint32_t e : candidates) {
        if (!is_silhouette(m, e, local[l][i])) continue;
        // VE: the plane through v and e must leave both light neighbours of v on one side.
        const uint32_t a = m.v0[e], bv = m.v1[e];
        const glm::dvec3 normal = glm::cross(world_blocker[a] - v, world_blocker[bv] - v);
        const int s_prev = side(normal, v, prev, tolerance), s_next = side(normal, v, next, tolerance);
        if (s_prev * s_next < 0 || (s_prev == 0 && s_next == 0)) continue;
        const int light_side = s_prev != 0 ? s_prev : s_next;
        const int s0 = side(normal, v, world_blocker[opposite(m.faces[m.face0[e]], a, bv)], tolerance);
        const int s1 = side(normal, v, world_blocker[opposite(m.faces[m.face1[e]], a, bv)], tolerance);
        const int blocker_side = s0 != 0 ? s0 : s1;
        if (blocker_side == 0 || s0 * s1 < 0) continue;
        ShadowEvent event = hard_event(b, e, light_index);
        event.shape = EventShape::vertex_edge;
        event.source0 = event.source1 = v;
        event.kind = light_side == blocker_side ? EventKind::umbral : EventKind::penumbral;
        out.push_back(event);

        // EV: walk on along the shadow-volume boundary from each end of e, over the light
        // edges at v: the plane through that light edge and the blocker vertex is an event when
        // it is tangent to the blocker there and the light lies on one side of it.
        for (uint32_t w : {a, bv}) {
          for (size_t j : {(i + n - 1) % n, i}) {  // light edge (loop[j], loop[j + 1])
            if (!ev_seen.insert(std::make_tuple(l, j, w)).second) continue;
            const glm::dvec3 &s0p = loop[j], &s1p = loop[(j + 1) % n];
            const glm::dvec3 plane = glm::cross(s1p - s0p, world_blocker[w] - s0p);
            int lside = 0;
            bool light_split = false;
            for (size_t k = 0; k < n; ++k) {
              const int s = side(plane, s0p, loop[k], tolerance);
              if (s != 0 && lside != 0 && s != lside) light_split = true;
              if (s != 0) lside = s;
            }
            if (light_split || lside == 0) continue;
            int bside = 0;
            bool tangent = true;
            for (uint32_t r = m.ring_start[w]; r < m.ring_start[w + 1] && tangent; ++r)
              for (int k = 0; k < 3; ++k) {
                const int s = side(plane, s0p, world_blocker[m.faces[m.ring_faces[r]][k]], tolerance);
                if (s != 0 && bside != 0 && s != bside) tangent = false;
                if (s != 0) bside = s;
              }
            if (!tangent || bside == 0) continue;
            ShadowEvent ev;
            ev.shape = EventShape::edge_vertex;
            ev.kind = lside == bside ? EventKind::umbral : EventKind::penumbral;
            ev.source0 = s0p, ev.source1 = s1p;
            ev.blocker0 = ev.blocker1 = world_blocker[w];
            ev.blocker_v0 = ev.blocker_v1 = w;
            ev.light = light_index, ev.blocker = b.object;
            out.push_back(ev);
          }
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
  for (uint32_t e : edges) {
    ShadowEvent event = hard_event(b, e, light_index);
    event.shape = light.type == EdgeLight::Type::point ? EventShape::vertex_edge : EventShape::parallel;
    event.source0 = event.source1 = light.type == EdgeLight::Type::point ? light.position : light.direction;
    out.push_back(event);
  }
}

}  // namespace epi::edges

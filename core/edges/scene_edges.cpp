#include "edges/scene_edges.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

namespace epi::edges {
namespace {

glm::dvec3 transform_point(const glm::dmat4& m, const glm::dvec3& p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); }

struct Sphere {
  glm::dvec3 centre{0.0};
  double radius = 0.0;
};

Sphere world_sphere(const EdgeMesh& mesh, const glm::dmat4& object_to_world) {
  Bounds bounds;
  for (const glm::vec3& p : mesh.positions) bounds.extend(p);
  if (bounds.empty()) return {};
  Sphere s;
  std::vector<glm::dvec3> corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back(transform_point(object_to_world, {k & 1 ? bounds.max.x : bounds.min.x, k & 2 ? bounds.max.y : bounds.min.y,
                                                        k & 4 ? bounds.max.z : bounds.min.z}));
  for (const glm::dvec3& c : corners) s.centre += c / 8.0;
  for (const glm::dvec3& c : corners) s.radius = std::max(s.radius, glm::length(c - s.centre));
  s.radius = s.radius * (1.0 + 1e-9) + 1e-12;
  return s;
}

// Whether the receiver sphere may meet the shadow of the blocker sphere cast from a light point
// (apex) whose own extent is `light_radius` (see docs/edges.md for why this is conservative).
bool in_shadow_cone(const glm::dvec3& apex, double light_radius, const Sphere& blocker, const Sphere& receiver) {
  const double r = blocker.radius + light_radius;
  const glm::dvec3 to_blocker = blocker.centre - apex, to_receiver = receiver.centre - apex;
  const double db = glm::length(to_blocker), dr = glm::length(to_receiver);
  if (db <= r || dr <= receiver.radius) return true;
  // (A receiver nearer the light than the blocker stays: it may hide the blocker's events.)
  const double alpha = std::asin(std::min(1.0, r / db)), beta = std::asin(std::min(1.0, receiver.radius / dr));
  const double gamma = std::acos(std::clamp(glm::dot(to_blocker, to_receiver) / (db * dr), -1.0, 1.0));
  return gamma <= alpha + beta + 1e-9;
}

// A bounding-sphere hierarchy over the objects' world spheres, so that finding the receivers of
// one (light, blocker) pair costs about log(objects) + receivers instead of one test per object.
// Both tests used with it (the shadow cone, the directional cylinder) are monotone: a sphere that
// contains another meets the volume whenever the inner one does, so a node that fails prunes its
// subtree exactly.
class SphereTree {
 public:
  explicit SphereTree(const std::vector<Sphere>& spheres) : spheres_(spheres) {
    for (uint32_t i = 0; i < spheres.size(); ++i)
      if (spheres[i].radius > 0.0) order_.push_back(i);
    if (!order_.empty()) nodes_.resize(1), build(0, 0, uint32_t(order_.size()));
  }

  // Calls found(object) for every object whose sphere passes meets(sphere); counts the tests.
  template <class Meets, class Found>
  void query(const Meets& meets, const Found& found, uint64_t& tests) const {
    if (nodes_.empty()) return;
    uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      ++tests;
      if (!meets(node.bound)) continue;
      if (node.count > 0) {
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
          ++tests;
          if (meets(spheres_[order_[k]])) found(order_[k]);
        }
      } else if (top + 2 <= 128) {
        stack[top++] = node.left, stack[top++] = node.left + 1;
      }
    }
  }

 private:
  struct Node {
    Sphere bound;
    uint32_t first = 0, count = 0, left = 0;  // a leaf when count > 0; else children left, left + 1
  };

  void build(uint32_t index, uint32_t first, uint32_t last) {
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (uint32_t k = first; k < last; ++k) {
      const Sphere& s = spheres_[order_[k]];
      lo = glm::min(lo, s.centre - s.radius), hi = glm::max(hi, s.centre + s.radius);
    }
    Sphere bound{0.5 * (lo + hi), 0.0};
    for (uint32_t k = first; k < last; ++k) {
      const Sphere& s = spheres_[order_[k]];
      bound.radius = std::max(bound.radius, glm::length(s.centre - bound.centre) + s.radius);
    }
    nodes_[index].bound = {bound.centre, bound.radius * (1.0 + 1e-9) + 1e-12};
    if (last - first <= 4) {
      nodes_[index].first = first, nodes_[index].count = last - first;
      return;
    }
    // Median splits: depth stays below log2(objects) + 1, well inside the query's stack.
    const glm::dvec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const uint32_t middle = first + (last - first) / 2;
    std::nth_element(order_.begin() + first, order_.begin() + middle, order_.begin() + last,
                     [&](uint32_t a, uint32_t b) { return spheres_[a].centre[axis] < spheres_[b].centre[axis]; });
    const uint32_t left = uint32_t(nodes_.size());
    nodes_.resize(nodes_.size() + 2);
    nodes_[index].left = left;
    build(left, first, middle);
    build(left + 1, middle, last);
  }

  const std::vector<Sphere>& spheres_;
  std::vector<uint32_t> order_;
  std::vector<Node> nodes_;
};

bool same_light(const EdgeLight& a, const EdgeLight& b) {
  return a.type == b.type && a.position == b.position && a.direction == b.direction && a.outlines == b.outlines &&
         a.object == b.object && a.cone_cos == b.cone_cos;
}

// The parts of a shadow edge inside a spot light's cone (nothing outside it is lit, so nothing
// there is a shadow boundary): the cone test along the segment is a quadratic in its parameter.
void clip_to_cone(const ShadowEdge& edge, const EdgeLight& light, std::vector<ShadowEdge>& out) {
  if (light.cone_cos <= 0.0) {  // no cone, or one wider than a half-space: keep as is
    out.push_back(edge);
    return;
  }
  const glm::dvec3 q0 = edge.a - light.position, dq = edge.b - edge.a;
  const double c2 = light.cone_cos * light.cone_cos;
  const double a0 = glm::dot(light.direction, q0), a1 = glm::dot(light.direction, dq);
  // g(s) = (dir . q)^2 - c^2 |q|^2 = A s^2 + B s + C
  const double A = a1 * a1 - c2 * glm::dot(dq, dq), B = 2.0 * (a0 * a1 - c2 * glm::dot(q0, dq)),
               C = a0 * a0 - c2 * glm::dot(q0, q0);
  std::vector<double> cuts = {0.0, 1.0};
  if (A != 0.0) {
    const double disc = B * B - 4.0 * A * C;
    if (disc >= 0.0)
      for (double r : {(-B - std::sqrt(disc)) / (2.0 * A), (-B + std::sqrt(disc)) / (2.0 * A)})
        if (r > 0.0 && r < 1.0) cuts.push_back(r);
  } else if (B != 0.0 && -C / B > 0.0 && -C / B < 1.0) {
    cuts.push_back(-C / B);
  }
  std::sort(cuts.begin(), cuts.end());
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double m = 0.5 * (cuts[i] + cuts[i + 1]);
    if (a0 + m * a1 < 0.0 || (A * m + B) * m + C < 0.0) continue;
    ShadowEdge piece = edge;
    piece.a = edge.a + cuts[i] * dq, piece.b = edge.a + cuts[i + 1] * dq;
    if (!out.empty() && out.back().b == piece.a && out.back().event == piece.event) out.back().b = piece.b;
    else out.push_back(piece);
  }
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

const char* to_string(EdgeKind kind) {
  static const char* names[] = {"silhouette", "sharp", "border", "umbral", "penumbral", "shadow"};
  return names[int(kind)];
}

std::vector<EdgeLight> SceneEdgeFinder::scene_lights(const Scene& scene, std::vector<std::string>* names) {
  std::vector<EdgeLight> lights;
  for (const PunctualLight& p : scene.punctual_lights) {
    EdgeLight l;
    l.type = p.type == LightType::directional ? EdgeLight::Type::directional : EdgeLight::Type::point;
    l.position = p.position;
    l.direction = glm::normalize(glm::dvec3(p.direction));
    if (p.type == LightType::spot) l.cone_cos = p.outer_cone_cos;
    lights.push_back(l);
    if (names) names->push_back(p.name);
  }
  for (const AreaLight& a : scene.area_lights) {
    EdgeLight l;
    l.type = EdgeLight::Type::area;
    l.object = a.object;
    for (const auto& loop : a.outlines) l.outlines.emplace_back(loop.begin(), loop.end());
    lights.push_back(l);
    if (names) names->push_back(a.object < scene.objects.size() ? scene.objects[a.object].name : "area");
  }
  return lights;
}

SceneEdgeFinder::SceneEdgeFinder(const Scene& scene, const SceneEdgeSettings& settings) : settings_(settings) {
  const auto start = std::chrono::steady_clock::now();
  meshes_.resize(scene.meshes.size());
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    MeshData& data = meshes_[i];
    data.edges = build_edge_mesh(scene.meshes[i]);
    tbb::parallel_invoke([&] { data.tree = EdgeTree(data.edges, settings.tree); },
                         [&] {
                           if (settings.receiver_trees) data.receivers = ReceiverTree(data.edges);
                         });

    // The choice rule: estimated tree work over six viewpoints around the mesh against brute force.
    const EdgeMesh& m = data.edges;
    double radius = 0.0;
    for (const glm::vec3& p : m.positions) radius = std::max(radius, glm::length(glm::dvec3(p) - m.origin));
    double nodes = 0.0, edges = 0.0, silhouettes = 0.0;
    std::vector<uint32_t> found;
    for (int k = 0; k < 6; ++k) {
      glm::dvec3 offset(0.0);
      offset[k / 2] = (k % 2 ? -3.0 : 3.0) * std::max(radius, 1e-30);
      const ViewBox box = ViewBox::point(m.local_point(m.origin + offset));
      data.tree.silhouettes(m, m.local_point(m.origin + offset), found);
      silhouettes += found.size() / 6.0;
      const auto& tree_nodes = data.tree.nodes();
      std::vector<uint32_t> stack = tree_nodes.empty() ? std::vector<uint32_t>{} : std::vector<uint32_t>{0};
      while (!stack.empty()) {
        const EdgeTreeNode& node = tree_nodes[stack.back()];
        stack.pop_back();
        nodes += 1.0 / 6.0;
        if (!EdgeTree::may_hold_silhouette(node, box, m.max_abs_d)) continue;
        edges += node.count / 6.0;
        if (node.left != kNone) stack.push_back(node.left), stack.push_back(node.right);
      }
    }
    const FinderCost& c = settings.cost;
    data.choice.tree_ns = nodes * c.ns_per_node + edges * c.ns_per_tree_edge + silhouettes * c.ns_per_tree_silhouette;
    data.choice.brute_ns = double(m.face_count()) * c.ns_per_face + double(m.edge_count()) * c.ns_per_brute_edge +
                           silhouettes * c.ns_per_brute_silhouette;
    data.choice.tree = settings.force == 0 ? data.choice.tree_ns < data.choice.brute_ns : settings.force > 0;
    if (!data.choice.tree && !settings.keep_unchosen_trees) data.tree = EdgeTree();  // frees it
  }
  lights_ = scene_lights(scene, &light_names_);
  build_ms_ = ms_since(start);
}

size_t SceneEdgeFinder::memory_bytes() const {
  size_t bytes = 0;
  for (const MeshData& m : meshes_) bytes += m.edges.memory_bytes() + m.tree.memory_bytes() + m.receivers.memory_bytes();
  return bytes;
}

BlockerView SceneEdgeFinder::blocker_view(const Scene& scene, uint32_t object) const {
  const Object& o = scene.objects[object];
  const MeshData& data = meshes_[o.mesh];
  return {&data.edges, data.choice.tree ? &data.tree : nullptr, glm::dmat4(o.object_to_world), object};
}

void SceneEdgeFinder::view_edges(const Scene& scene, const glm::dvec3& eye, std::vector<SceneEdge>& out) const {
  std::vector<uint32_t> silhouettes, sharp, border;
  std::vector<uint8_t> facing;
  for (uint32_t o = 0; o < scene.objects.size(); ++o) {
    const Object& object = scene.objects[o];
    const MeshData& data = meshes_[object.mesh];
    const glm::dmat4 to_world(object.object_to_world);
    const Viewpoint v = data.edges.local_point(transform_point(glm::inverse(to_world), eye));
    if (data.choice.tree) data.tree.silhouettes(data.edges, v, silhouettes);
    else brute_force_silhouettes(data.edges, v, facing, silhouettes);
    visible_feature_edges(data.edges, v, sharp, border);
    const EdgeMesh& m = data.edges;
    auto emit = [&](const std::vector<uint32_t>& list, EdgeKind kind) {
      for (uint32_t e : list)
        out.push_back({kind, o, transform_point(to_world, m.positions[m.v0[e]]), transform_point(to_world, m.positions[m.v1[e]])});
    };
    emit(silhouettes, EdgeKind::silhouette);
    emit(sharp, EdgeKind::sharp);
    emit(border, EdgeKind::border);
  }
}

std::vector<LightBlockerReceiver> SceneEdgeFinder::find_triples(const Scene& scene) const {
  std::vector<Sphere> spheres;
  for (const Object& o : scene.objects) spheres.push_back(world_sphere(meshes_[o.mesh].edges, glm::dmat4(o.object_to_world)));
  const SphereTree tree(spheres);
  const std::vector<EdgeLight> lights = scene_lights(scene, nullptr);
  std::vector<LightBlockerReceiver> triples;
  std::vector<uint32_t> receivers;
  uint64_t tests = 0;
  for (uint32_t l = 0; l < lights.size(); ++l) {
    const EdgeLight& light = lights[l];
    glm::dvec3 apex(0.0);
    double light_radius = 0.0;
    if (light.type == EdgeLight::Type::area) {
      size_t count = 0;
      for (const auto& loop : light.outlines)
        for (const glm::dvec3& p : loop) apex += p, ++count;
      if (count == 0) continue;
      apex /= double(count);
      for (const auto& loop : light.outlines)
        for (const glm::dvec3& p : loop) light_radius = std::max(light_radius, glm::length(p - apex));
    } else {
      apex = light.position;
    }
    for (uint32_t b = 0; b < scene.objects.size(); ++b) {
      if (b == light.object || spheres[b].radius == 0.0) continue;
      const Sphere& blocker = spheres[b];
      receivers.clear();
      auto meets = [&](const Sphere& receiver) {
        if (light.type == EdgeLight::Type::directional) {  // before or beyond: see in_shadow_cone
          const glm::dvec3 offset = receiver.centre - blocker.centre;
          const double along = glm::dot(offset, light.direction);
          return glm::length(offset - along * light.direction) <= blocker.radius + receiver.radius;
        }
        return in_shadow_cone(apex, light_radius, blocker, receiver);
      };
      tree.query(meets, [&](uint32_t r) { receivers.push_back(r); }, tests);
      // Every object meets its own shadow volume; objects without a sphere (no positions) never do.
      std::sort(receivers.begin(), receivers.end());
      if (!std::binary_search(receivers.begin(), receivers.end(), b))
        receivers.insert(std::upper_bound(receivers.begin(), receivers.end(), b), b);
      for (uint32_t r : receivers)
        if (r != light.object) triples.push_back({l, b, r});
    }
  }
  triple_tests_ = tests;
  return triples;
}

void SceneEdgeFinder::shadow_edges(const Scene& scene, std::span<const LightBlockerReceiver> triples,
                                   std::vector<SceneEdge>& out) {
  if (!settings_.receiver_trees) throw std::logic_error("shadow edges from an edge finder built without receiver trees");
  light_names_.clear();  // called every frame: the names are rebuilt, not appended
  lights_ = scene_lights(scene, &light_names_);
  std::vector<LightBlockerReceiver> sorted(triples.begin(), triples.end());
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());

  std::map<std::pair<uint32_t, uint32_t>, PairState> next;
  for (size_t i = 0; i < sorted.size();) {
    const uint32_t l = sorted[i].light, b = sorted[i].blocker;
    PairState state;
    state.light = lights_[l];
    state.blocker_transform = glm::dmat4(scene.objects[b].object_to_world);
    for (; i < sorted.size() && sorted[i].light == l && sorted[i].blocker == b; ++i)
      state.receivers.push_back({sorted[i].receiver, glm::dmat4(scene.objects[sorted[i].receiver].object_to_world)});
    if (std::none_of(state.receivers.begin(), state.receivers.end(), [&](const auto& r) { return r.first == b; }))
      state.receivers.push_back({b, state.blocker_transform});  // the blocker always clips its own events

    const auto cached = pairs_.find({l, b});
    if (cached != pairs_.end() && same_light(cached->second.light, state.light) &&
        cached->second.blocker_transform == state.blocker_transform && cached->second.receivers == state.receivers) {
      state.edges = std::move(cached->second.edges);
    } else {
      ++pairs_recomputed_;
      std::vector<ShadowEvent> events;
      find_shadow_events(blocker_view(scene, b), state.light, l, events);
      std::vector<ReceiverView> receivers;
      for (const auto& [r, transform] : state.receivers) {
        const MeshData& data = meshes_[scene.objects[r].mesh];
        const Sphere bound = world_sphere(data.edges, transform);
        receivers.push_back({&data.edges, &data.receivers, transform, glm::inverse(transform), r, bound.centre,
                             bound.radius > 0.0 ? bound.radius : INFINITY});
      }
      // Events in parallel, each into its own list: the same output whatever the thread count.
      std::vector<std::vector<ShadowEdge>> per_event(events.size());
      std::vector<size_t> searched(events.size());
      tbb::parallel_for(tbb::blocked_range<size_t>(0, events.size(), 16), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t e = range.begin(); e != range.end(); ++e)
          searched[e] = shadow_edges_of_event(events[e], uint32_t(e), receivers, per_event[e]);
      });
      for (size_t n : searched) receiver_searches_ += n;
      for (auto& list : per_event)
        for (const ShadowEdge& e : list) clip_to_cone(e, state.light, state.edges);
    }
    next[{l, b}] = std::move(state);
  }
  pairs_ = std::move(next);

  for (const auto& [key, state] : pairs_)
    for (const ShadowEdge& s : state.edges) {
      const EdgeKind kind = s.kind == EventKind::hard ? EdgeKind::shadow
                            : s.kind == EventKind::umbral ? EdgeKind::umbral
                                                          : EdgeKind::penumbral;
      out.push_back({kind, s.receiver, s.a, s.b, s.blocker, s.light});
    }
}

}  // namespace epi::edges

// Shadow events and shadow edges checked against ray casting (a brute-force segment-triangle test
// over every triangle of the scene): visibility of the light must change across every reported
// shadow edge, every visibility change found by scanning the receivers must have an edge beside
// it, and umbral/penumbral edges must bound the fully and partly blocked regions of area lights.
#include <gtest/gtest.h>

#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/global_control.h>

#include "edges/scene_edges.h"
#include "edges/shadow_edges.h"
#include "ray_world.h"
#include "test_meshes.h"

namespace epi::edges {
namespace {

using namespace test;

World hard_shadow_world() {
  World w;
  w.add(grid(24, 10.0f), glm::mat4(1.0f));
  w.add(uv_sphere(24, 48, 0.6f), at({0, 1.5f, 0}));
  w.add(torus(32, 16, 0.6f, 0.2f), at({1.6f, 1.2f, 0.8f}, 35.0f, {1, 0, 0}));
  w.add(box({-0.4f, 0, -0.4f}, {0.4f, 0.9f, 0.4f}), at({-1.8f, 0, 1.0f}, 20.0f, {0, 1, 0}));
  w.footprints.push_back(glm::dmat4(at({-1.8f, 0, 1.0f}, 20.0f, {0, 1, 0})));
  return w;
}

// The world normal of a receiver face.
glm::dvec3 face_normal(const World& w, const SceneEdgeFinder& finder, uint32_t object, const glm::dvec3& near) {
  (void)finder;
  // Closest triangle of the object to the point.
  double best = INFINITY;
  glm::dvec3 normal(0, 1, 0);
  for (size_t i = 0; i < w.triangles.size(); i += 3) {
    if (w.triangle_object[i / 3] != object) continue;
    const glm::dvec3 c = (w.triangles[i] + w.triangles[i + 1] + w.triangles[i + 2]) / 3.0;
    const glm::dvec3 n = glm::normalize(glm::cross(w.triangles[i + 1] - w.triangles[i], w.triangles[i + 2] - w.triangles[i]));
    const double plane = std::fabs(glm::dot(near - w.triangles[i], n));
    const double score = plane + 1e-3 * glm::length(near - c);
    if (score < best) best = score, normal = n;
  }
  return normal;
}

// Fraction of edges whose two sides differ in visibility (sampled at their midpoints).
template <class Sees>
double fraction_separating(const World& w, const SceneEdgeFinder& finder, const std::vector<SceneEdge>& edges, Sees sees) {
  int good = 0, total = 0;
  for (const SceneEdge& e : edges) {
    const double length = glm::length(e.b - e.a);
    if (length < 2e-3) continue;  // too short to probe beside it
    const glm::dvec3 m = 0.5 * (e.a + e.b);
    const glm::dvec3 n = face_normal(w, finder, e.object, m);
    const glm::dvec3 across = glm::normalize(glm::cross(n, e.b - e.a));
    const double step = 2e-3;
    const glm::dvec3 lift = n * 1e-4;
    const bool ok = sees(m + step * across + lift) != sees(m - step * across + lift);
    good += ok;
    ++total;
  }
  return total ? double(good) / total : 0.0;
}

// Scans of random lines over the floor: where visibility changes between two samples, a shadow
// edge must pass within a sample step of them.
template <class Sees>
double fraction_found(const World& w, const std::vector<SceneEdge>& edges, Sees sees, int lines) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-4.5, 4.5);
  int changes = 0, found = 0;
  const double step = 0.02;
  for (int l = 0; l < lines; ++l) {
    const glm::dvec3 a(u(rng), 1e-4, u(rng)), b(u(rng), 1e-4, u(rng));
    const int samples = int(glm::length(b - a) / step);
    bool previous = sees(a);
    for (int s = 1; s <= samples; ++s) {
      const glm::dvec3 x = a + (b - a) * (double(s) / samples);
      const bool now = sees(x);
      if (now != previous && !w.inside(x) && !w.inside(a + (b - a) * (double(s - 1) / samples))) {
        ++changes;
        const glm::dvec3 y = a + (b - a) * (double(s - 1) / samples);
        for (const SceneEdge& e : edges) {
          if (e.object != 0) continue;
          // Distance from the sample pair's midpoint to the edge segment.
          const glm::dvec3 p = 0.5 * (x + y), d = e.b - e.a;
          const double t = std::clamp(glm::dot(p - e.a, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
          if (glm::length(p - (e.a + t * d)) < 1.5 * step) {
            ++found;
            break;
          }
        }
      }
      previous = now;
    }
  }
  (void)w;
  EXPECT_GT(changes, 20);
  return changes ? double(found) / changes : 0.0;
}

TEST(HardShadows, PointLightEdgesSeparateLitFromShadowedAndMissNone) {
  World w = hard_shadow_world();
  PunctualLight light;
  light.name = "key";
  light.position = {0.7f, 5.0f, 0.3f};
  w.scene.punctual_lights.push_back(light);
  for (int force : {1, -1}) {
    SceneEdgeSettings settings;
    settings.force = force;
    SceneEdgeFinder finder(w.scene, settings);
    std::vector<SceneEdge> edges;
    finder.shadow_edges(w.scene, finder.find_triples(w.scene), edges);
    ASSERT_GT(edges.size(), 100u);
    for (const SceneEdge& e : edges) EXPECT_EQ(e.kind, EdgeKind::shadow);
    const glm::dvec3 lp = light.position;
    auto sees = [&](const glm::dvec3& x) { return w.sees_point(x, lp); };
    EXPECT_GT(fraction_separating(w, finder, edges, sees), 0.97);
    EXPECT_GT(fraction_found(w, edges, sees, 150), 0.97);
  }
}

TEST(HardShadows, DirectionalLight) {
  World w = hard_shadow_world();
  PunctualLight light;
  light.name = "sun";
  light.type = LightType::directional;
  light.direction = glm::normalize(glm::vec3(0.4f, -1.0f, -0.3f));
  w.scene.punctual_lights.push_back(light);
  SceneEdgeFinder finder(w.scene);
  std::vector<SceneEdge> edges;
  finder.shadow_edges(w.scene, finder.find_triples(w.scene), edges);
  ASSERT_GT(edges.size(), 100u);
  const glm::dvec3 travel = light.direction;
  auto sees = [&](const glm::dvec3& x) { return w.sees_direction(x, travel); };
  EXPECT_GT(fraction_separating(w, finder, edges, sees), 0.97);
  EXPECT_GT(fraction_found(w, edges, sees, 150), 0.97);
}

TEST(HardShadows, SpotLightEdgesStayInsideItsCone) {
  World w = hard_shadow_world();
  PunctualLight light;
  light.type = LightType::spot;
  light.position = {0.7f, 5.0f, 0.3f};
  light.direction = {0, -1, 0};
  light.outer_cone_cos = std::cos(glm::radians(22.0f));  // about 2 m across on the floor: cuts the box's shadow
  w.scene.punctual_lights.push_back(light);
  SceneEdgeFinder finder(w.scene);
  std::vector<SceneEdge> spot;
  finder.shadow_edges(w.scene, finder.find_triples(w.scene), spot);
  w.scene.punctual_lights[0].type = LightType::point;
  SceneEdgeFinder point_finder(w.scene);
  std::vector<SceneEdge> point;
  point_finder.shadow_edges(w.scene, point_finder.find_triples(w.scene), point);
  auto inside = [&](const glm::dvec3& p) {
    return glm::dot(glm::normalize(p - glm::dvec3(light.position)), glm::dvec3(0, -1, 0)) >= light.outer_cone_cos - 1e-9;
  };
  ASSERT_GT(spot.size(), 50u);
  double spot_length = 0.0, point_inside_length = 0.0;
  for (const SceneEdge& e : spot) {
    EXPECT_TRUE(inside(e.a) && inside(e.b));
    spot_length += glm::length(e.b - e.a);
  }
  int outside = 0;
  for (const SceneEdge& e : point) {
    outside += !inside(e.a) || !inside(e.b);
    const int steps = 200;  // length of the point light's edges inside the cone, by sampling
    for (int k = 0; k < steps; ++k)
      if (inside(e.a + (e.b - e.a) * ((k + 0.5) / steps))) point_inside_length += glm::length(e.b - e.a) / steps;
  }
  EXPECT_GT(outside, 10);
  EXPECT_NEAR(spot_length, point_inside_length, 0.01 * point_inside_length);
}

TEST(HardShadows, NearerReceiverClipsTheEvent) {
  // A small plate between the sphere and the floor: the sphere's shadow edges stop on the plate
  // wherever the plate is in the way.
  World w;
  w.add(grid(8, 10.0f), glm::mat4(1.0f));
  w.add(uv_sphere(16, 32, 0.5f), at({0, 3, 0}));
  w.add(grid(4, 1.0f), at({0.5f, 1.5f, 0}));
  PunctualLight light;
  light.position = {0, 6, 0};
  w.scene.punctual_lights.push_back(light);
  SceneEdgeFinder finder(w.scene);
  std::vector<SceneEdge> edges;
  finder.shadow_edges(w.scene, finder.find_triples(w.scene), edges);
  int on_plate = 0;
  for (const SceneEdge& e : edges) {
    if (e.blocker != 1) continue;
    on_plate += e.object == 2;
    if (e.object != 0) continue;
    // Floor edges of the sphere's shadow never lie in the plate's shadow.
    for (const glm::dvec3& p : {e.a, e.b, 0.5 * (e.a + e.b)}) {
      const glm::dvec3 on_plate_plane = glm::dvec3(0, 6, 0) + (p - glm::dvec3(0, 6, 0)) * (4.5 / 6.0);
      const bool under_plate = on_plate_plane.x > 0.0 + 1e-6 && on_plate_plane.x < 1.0 - 1e-6 &&
                               std::fabs(on_plate_plane.z) < 0.5 - 1e-6;
      EXPECT_FALSE(under_plate) << p.x << " " << p.z;
    }
  }
  EXPECT_GT(on_plate, 0);
}

TEST(HardShadows, ReusedUntilSomethingMoves) {
  World w = hard_shadow_world();
  PunctualLight light;
  light.position = {0.7f, 5.0f, 0.3f};
  w.scene.punctual_lights.push_back(light);
  SceneEdgeFinder finder(w.scene);
  const auto triples = finder.find_triples(w.scene);
  std::vector<SceneEdge> first, second, third;
  finder.shadow_edges(w.scene, triples, first);
  const size_t pairs = finder.pairs_recomputed();
  finder.shadow_edges(w.scene, triples, second);
  EXPECT_EQ(finder.pairs_recomputed(), pairs);  // nothing moved: all reused
  ASSERT_EQ(first.size(), second.size());
  w.scene.objects[2].object_to_world = at({1.7f, 1.2f, 0.8f}, 35.0f, {1, 0, 0});  // move the torus
  finder.shadow_edges(w.scene, finder.find_triples(w.scene), third);
  EXPECT_GT(finder.pairs_recomputed(), pairs);
  EXPECT_LT(finder.pairs_recomputed(), 2 * pairs);  // the box's pair did not involve the torus
}

// --- Area lights ---

struct AreaSetup {
  World world;
  uint32_t light_object = 0;
  std::vector<glm::dvec3> light_points;  // samples over the light polygon, just inside it
  glm::dvec3 centroid{0.0};
};

AreaSetup area_world(bool torus_on_capsule) {
  AreaSetup s;
  World& w = s.world;
  w.add(grid(24, 10.0f), glm::mat4(1.0f));
  if (torus_on_capsule) {
    Mesh capsule = uv_sphere(24, 48, 1.0f);
    for (glm::vec3& p : capsule.positions) p = {p.x * 1.6f, p.y * 0.5f, p.z * 0.5f};
    w.add(capsule, at({0, 0.5f, 0}));
    w.add(torus(48, 24, 0.5f, 0.15f), at({0, 0.9f, 0}));  // lying on the capsule, sunk into it: they meet
  } else {
    w.add(uv_sphere(24, 48, 0.6f), at({0, 1.4f, 0}));
  }
  // A square emitter above, facing down.
  Mesh quad = grid(1, 1.2f);
  for (glm::uvec3& t : quad.triangles) std::swap(t.y, t.z);
  s.light_object = w.add(quad, at({0.3f, 4.0f, 0.2f}));
  AreaLight area;
  area.object = s.light_object;
  std::vector<glm::vec3> loop = {{-0.3f, 4, -0.4f}, {0.9f, 4, -0.4f}, {0.9f, 4, 0.8f}, {-0.3f, 4, 0.8f}};
  area.outlines = {loop};
  w.scene.area_lights.push_back(area);
  // The emitter itself must not block: drop its triangles from the ray caster.
  w.ranges.pop_back();
  for (const glm::vec3& p : loop) s.centroid += glm::dvec3(p) / 4.0;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j) {
      const glm::dvec3 p = glm::dvec3(-0.3 + 1.2 * i / 4.0, 4.0, -0.4 + 1.2 * j / 4.0);
      s.light_points.push_back(p + 1e-4 * (s.centroid - p));
    }
  return s;
}

struct AreaResult {
  std::vector<ShadowEvent> events;
  std::vector<ShadowEdge> edges;
};

AreaResult area_edges(const AreaSetup& s) {
  const Scene& scene = s.world.scene;
  SceneEdgeSettings keep;  // the blockers' trees whatever the cost model chose
  keep.keep_unchosen_trees = true;
  SceneEdgeFinder finder(scene, keep);
  const EdgeLight& light = finder.lights()[0];
  AreaResult result;
  std::vector<ReceiverView> receivers;
  for (uint32_t o = 0; o < scene.objects.size(); ++o) {
    if (o == s.light_object) continue;
    const glm::dmat4 m(scene.objects[o].object_to_world);
    const uint32_t mesh = scene.objects[o].mesh;
    static std::vector<ReceiverTree> trees;  // kept alive for the views below
    receivers.push_back({&finder.edge_mesh(mesh), nullptr, m, glm::inverse(m), o});
  }
  std::vector<ReceiverTree> trees;
  trees.reserve(receivers.size());
  for (ReceiverView& r : receivers) trees.emplace_back(*r.mesh), r.tree = &trees.back();
  for (uint32_t o = 1; o < scene.objects.size(); ++o) {
    if (o == s.light_object) continue;
    const BlockerView b{&finder.edge_mesh(scene.objects[o].mesh), &finder.edge_tree(scene.objects[o].mesh),
                        glm::dmat4(scene.objects[o].object_to_world), o};
    find_shadow_events(b, light, 0, result.events);
  }
  for (uint32_t e = 0; e < result.events.size(); ++e) shadow_edges_of_event(result.events[e], e, receivers, result.edges);
  return result;
}

// The light point whose visibility the event tracks at x: v for VE events, S(u) for EV events.
glm::dvec3 critical_point(const ShadowEvent& event, const glm::dvec3& x, const glm::dvec3& centroid) {
  glm::dvec3 c = event.source0;
  if (event.shape == EventShape::edge_vertex) {
    const double u = std::clamp(event_coordinates(event, x).x, 0.0, 1.0);
    c = event.source0 + u * (event.source1 - event.source0);
  }
  return c + 1e-4 * (centroid - c);
}

TEST(AreaShadows, TreeAndBruteForceFindTheSameEvents) {
  const AreaSetup s = area_world(true);
  const Scene& scene = s.world.scene;
  SceneEdgeSettings keep;  // every tree, to compare with brute force
  keep.keep_unchosen_trees = true;
  const SceneEdgeFinder finder(scene, keep);
  for (uint32_t o : {1u, 2u}) {
    const uint32_t mesh = scene.objects[o].mesh;
    BlockerView b{&finder.edge_mesh(mesh), &finder.edge_tree(mesh), glm::dmat4(scene.objects[o].object_to_world), o};
    std::vector<ShadowEvent> with_tree, brute;
    find_shadow_events(b, finder.lights()[0], 0, with_tree);
    b.tree = nullptr;
    find_shadow_events(b, finder.lights()[0], 0, brute);
    ASSERT_FALSE(brute.empty());
    ASSERT_EQ(with_tree.size(), brute.size());
    for (size_t k = 0; k < brute.size(); ++k) {
      EXPECT_EQ(with_tree[k].blocker_v0, brute[k].blocker_v0);
      EXPECT_EQ(with_tree[k].blocker_v1, brute[k].blocker_v1);
      EXPECT_EQ(with_tree[k].kind, brute[k].kind);
      EXPECT_EQ(with_tree[k].source0, brute[k].source0);
    }
  }
}

TEST(AreaShadows, SameEdgesWhateverTheThreadCount) {
  const AreaSetup s = area_world(true);
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    SceneEdgeFinder finder(s.world.scene);
    std::vector<SceneEdge> edges;
    finder.shadow_edges(s.world.scene, finder.find_triples(s.world.scene), edges);
    return edges;
  };
  const std::vector<SceneEdge> one = run(1), two = run(2);
  ASSERT_EQ(one.size(), two.size());
  for (size_t k = 0; k < one.size(); ++k) {
    EXPECT_EQ(one[k].a, two[k].a);
    EXPECT_EQ(one[k].b, two[k].b);
    EXPECT_EQ(one[k].object, two[k].object);
  }
}

// Distance from a point to the nearest edge of a kind on the floor.
double distance_to(const std::vector<ShadowEdge>& edges, EventKind kind, const glm::dvec3& p) {
  double best = INFINITY;
  for (const ShadowEdge& e : edges) {
    if (e.receiver != 0 || e.kind != kind) continue;
    const glm::dvec3 d = e.b - e.a;
    const double t = std::clamp(glm::dot(p - e.a, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
    best = std::min(best, glm::length(p - (e.a + t * d)));
  }
  return best;
}

TEST(AreaShadows, UmbralAndPenumbralEdgesBoundFullyAndPartlyBlockedRegions) {
  const AreaSetup s = area_world(false);
  const AreaResult r = area_edges(s);
  // Soundness: across every edge the visibility of the event's critical light point changes.
  int umbral = 0, penumbral = 0, good = 0, total = 0;
  for (const ShadowEdge& e : r.edges) {
    if (e.receiver != 0 || glm::length(e.b - e.a) < 2e-3) continue;  // floor edges
    umbral += e.kind == EventKind::umbral, penumbral += e.kind == EventKind::penumbral;
    const glm::dvec3 m = 0.5 * (e.a + e.b) + glm::dvec3(0, 1e-4, 0);
    const glm::dvec3 across = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), e.b - e.a)) * 2e-3;
    const glm::dvec3 c = critical_point(r.events[e.event], m, s.centroid);
    good += s.world.sees_point(m + across, c) != s.world.sees_point(m - across, c);
    ++total;
  }
  EXPECT_GT(umbral, 20);
  EXPECT_GT(penumbral, 20);
  EXPECT_GT(double(good) / total, 0.95) << good << " of " << total;

  // Completeness: scanning the floor, wherever the light turns from fully blocked to partly
  // blocked an umbral edge passes by, and wherever it turns from partly blocked to fully
  // visible a penumbral edge does.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  const double step = 0.02;
  int changes[2] = {0, 0}, found[2] = {0, 0};
  for (int line = 0; line < 24; ++line) {
    const glm::dvec3 a(u(rng), 1e-4, u(rng)), b(u(rng), 1e-4, u(rng));
    const int samples = int(glm::length(b - a) / step);
    int previous_state = -1;
    for (int k = 0; k <= samples; ++k) {
      const glm::dvec3 x = a + (b - a) * (double(k) / samples);
      int visible = 0;
      for (const glm::dvec3& p : s.light_points) visible += s.world.sees_point(x, p);
      const int state = visible == 0 ? 0 : visible == int(s.light_points.size()) ? 2 : 1;  // umbra, penumbra, lit
      if (previous_state >= 0 && state != previous_state && std::abs(state - previous_state) == 1) {
        const glm::dvec3 mid = x - (b - a) * (0.5 / samples);
        const int which = std::min(state, previous_state);  // 0: umbra boundary, 1: penumbra boundary
        ++changes[which];
        found[which] += distance_to(r.edges, which == 0 ? EventKind::umbral : EventKind::penumbral, mid) < 1.5 * step;
      }
      previous_state = state;
    }
  }
  EXPECT_GT(changes[0], 10);
  EXPECT_GT(changes[1], 10);
  EXPECT_GE(found[0], 0.9 * changes[0]) << found[0] << " of " << changes[0];
  EXPECT_GE(found[1], 0.9 * changes[1]) << found[1] << " of " << changes[1];
}

TEST(AreaShadows, TorusOnCapsuleUmbraAndPenumbraMeetAtTheContact) {
  // Where the torus meets the capsule the penumbra closes: umbral and penumbral edges of the
  // torus's shadow on the capsule come together there (the hardening of Figure 9), and nowhere
  // else.
  const AreaSetup s = area_world(true);
  const AreaResult r = area_edges(s);
  const glm::dmat4 torus_to_world = glm::dmat4(s.world.scene.objects[2].object_to_world);
  auto torus_distance = [&](const glm::dvec3& p) {
    const glm::dvec3 q = glm::dvec3(glm::inverse(torus_to_world) * glm::dvec4(p, 1.0));
    return std::fabs(std::hypot(std::hypot(q.x, q.z) - 0.5, q.y) - 0.15);
  };
  std::vector<glm::dvec3> points[2];
  int good = 0, total = 0;
  for (const ShadowEdge& e : r.edges) {
    if (e.receiver != 1 || e.blocker != 2) continue;  // the torus's shadow on the capsule
    for (int k = 0; k <= 4; ++k) points[e.kind == EventKind::umbral ? 0 : 1].push_back(e.a + (e.b - e.a) * (k / 4.0));
    if (glm::length(e.b - e.a) < 2e-3) continue;
    // Visibility of the event's critical light point changes across the edge.
    const glm::dvec3 m = 0.5 * (e.a + e.b);
    const glm::dvec3 n = glm::normalize(glm::dvec3(m.x / (1.6 * 1.6), (m.y - 0.5) / 0.25, m.z / 0.25));
    const glm::dvec3 across = glm::normalize(glm::cross(n, e.b - e.a)) * 2e-3;
    const glm::dvec3 c = critical_point(r.events[e.event], m, s.centroid);
    const glm::dvec3 lift = n * 1e-3;
    good += s.world.sees_point(m + across + lift, c) != s.world.sees_point(m - across + lift, c);
    ++total;
  }
  ASSERT_GT(points[0].size(), 10u);
  ASSERT_GT(points[1].size(), 10u);
  ASSERT_GT(total, 10);
  EXPECT_GT(double(good) / total, 0.9) << good << " of " << total;
  // The closest umbral-penumbral pair: close together, and at the torus.
  double closest = INFINITY, widest = 0.0;
  glm::dvec3 meeting(0.0);
  for (const glm::dvec3& a : points[0]) {
    double nearest = INFINITY;
    for (const glm::dvec3& b : points[1]) {
      const double d = glm::length(a - b);
      nearest = std::min(nearest, d);
      if (d < closest) closest = d, meeting = 0.5 * (a + b);
    }
    widest = std::max(widest, nearest);
  }
  // All around the contact, wherever an umbral edge reaches the torus, a penumbral edge reaches
  // it too: the penumbra closes there (not at one lucky place only).
  auto distance_to_kind = [&](const glm::dvec3& p, EventKind kind) {
    double best = INFINITY;
    for (const ShadowEdge& e : r.edges) {
      if (e.receiver != 1 || e.blocker != 2 || e.kind != kind) continue;
      const glm::dvec3 d = e.b - e.a;
      const double t = std::clamp(glm::dot(p - e.a, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
      best = std::min(best, glm::length(p - (e.a + t * d)));
    }
    return best;
  };
  int at_contact = 0;
  std::vector<double> met;  // angles around the torus's axis where umbra and penumbra meet
  for (const ShadowEdge& e : r.edges) {
    if (e.receiver != 1 || e.blocker != 2 || e.kind != EventKind::umbral) continue;
    for (const glm::dvec3& p : {e.a, e.b}) {
      if (torus_distance(p) > 2e-3) continue;
      ++at_contact;
      if (distance_to_kind(p, EventKind::penumbral) < 0.02) met.push_back(std::atan2(p.z, p.x));
    }
  }
  // (Umbral edges are whole event wedges: some run on inside the penumbra and reach the torus
  // there, so not every umbral end at the contact has a penumbral edge beside it.)
  std::sort(met.begin(), met.end());
  int places = met.empty() ? 0 : 1, sides = 0;
  for (size_t k = 1; k < met.size(); ++k) places += met[k] - met[k - 1] > 0.5;
  for (double a : met) sides |= (a > 0.5 ? 1 : a < -0.5 ? 2 : 0);
  EXPECT_GT(at_contact, 20);
  EXPECT_GE(met.size(), 20u);
  EXPECT_GE(places, 3);    // separate places around the ring
  EXPECT_EQ(sides, 3);     // on both sides of the capsule's long axis
  EXPECT_LT(closest, 0.02);
  EXPECT_LT(torus_distance(meeting), 0.03);
  EXPECT_GT(widest, 5 * closest + 0.05);  // elsewhere the penumbra is wide
}

}  // namespace
}  // namespace epi::edges

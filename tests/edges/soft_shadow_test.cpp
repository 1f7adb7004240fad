// Shadow edges of saddle-shaped blockers, open surfaces, many-sided and non-convex area lights and
// interpenetrating receivers, checked against ray casting: the boundaries of the fully blocked,
// partly blocked and fully lit regions found by scanning the floor must each have an umbral or
// penumbral edge beside them everywhere, and the outlines must be closed.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "edges/scene_edges.h"
#include "edges/shadow_edges.h"
#include "ray_world.h"
#include "test_meshes.h"

namespace epi::edges {
namespace {

using namespace test;

struct SoftScene {
  World world;
  std::vector<glm::dvec3> outline;  // the light polygon, world space
  std::vector<glm::dvec3> samples;  // dense points along the outline (just inside) and its centroid
  std::vector<SceneEdge> edges;

  // Light fully blocked (0), partly (1) or not at all (2) at x. Where the light first shows
  // through a gap it shows on its outline, so outline samples find the umbra and penumbra.
  int state(const glm::dvec3& x) const {
    bool seen = false, hidden = false;
    for (const glm::dvec3& s : samples) {
      (world.sees_point(x, s) ? seen : hidden) = true;
      if (seen && hidden) return 1;
    }
    return seen ? 2 : 0;
  }
};

// A floor (object 0) and an emitter polygon (not a blocker for the ray caster); blockers added by
// the caller before finish().
SoftScene soft_scene(const std::vector<glm::dvec3>& outline) {
  SoftScene s;
  s.world.add(grid(16, 8.0f), glm::mat4(1.0f));
  s.outline = outline;
  return s;
}

void add_light_and_find_edges(SoftScene& s, int samples_per_edge = 24) {
  // The emitter: a fan over the outline (a convex-enough stand-in; only its outline matters here).
  Mesh emitter;
  for (const glm::dvec3& p : s.outline) emitter.positions.push_back(glm::vec3(p));
  for (uint32_t i = 1; i + 1 < s.outline.size(); ++i) emitter.triangles.push_back({0, i + 1, i});
  emitter = finish(std::move(emitter), "emitter");
  const uint32_t light = s.world.add(emitter, glm::mat4(1.0f));
  s.world.ranges.pop_back();
  AreaLight area;
  area.object = light;
  std::vector<glm::vec3> loop;
  for (const glm::dvec3& p : s.outline) loop.push_back(glm::vec3(p));
  area.outlines = {loop};
  s.world.scene.area_lights.push_back(area);
  glm::dvec3 centroid(0.0);
  for (const glm::dvec3& p : s.outline) centroid += p / double(s.outline.size());
  const size_t n = s.outline.size();
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < samples_per_edge; ++k) {
      const glm::dvec3 p = s.outline[i] + (s.outline[(i + 1) % n] - s.outline[i]) * (double(k) / samples_per_edge);
      s.samples.push_back(p + 1e-5 * (centroid - p));
    }
  s.samples.push_back(centroid);
  SceneEdgeFinder finder(s.world.scene);
  finder.shadow_edges(s.world.scene, finder.find_triples(s.world.scene), s.edges);
}

double distance_to(const std::vector<SceneEdge>& edges, EdgeKind kind, const glm::dvec3& p) {
  double best = INFINITY;
  for (const SceneEdge& e : edges) {
    if (e.object != 0 || e.kind != kind) continue;
    const glm::dvec3 d = e.b - e.a;
    const double t = std::clamp(glm::dot(p - e.a, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
    best = std::min(best, glm::length(p - (e.a + t * d)));
  }
  return best;
}

struct BoundaryCheck {
  int changes[2] = {0, 0};  // umbra/penumbra, penumbra/lit transitions found by scanning
  int missed[2] = {0, 0};   // of which no edge of the right kind lies within the tolerance
  double worst[2] = {0.0, 0.0};
};

// Scans lines along x and along z over the square [lo, hi]^2 of the floor (2 cm steps, each
// transition located to 0.3 mm by bisection): every umbra/penumbra transition needs an umbral edge
// within `tolerance`, every penumbra/lit transition a penumbral one.
BoundaryCheck check_boundaries(const SoftScene& s, double lo, double hi, int lines, double tolerance) {
  BoundaryCheck result;
  const double step = 0.02;
  for (int axis = 0; axis < 2; ++axis)
    for (int l = 0; l < lines; ++l) {
      const double across = lo + (hi - lo) * (l + 0.5) / lines;
      auto point = [&](double along) { return axis == 0 ? glm::dvec3(along, 1e-4, across) : glm::dvec3(across, 1e-4, along); };
      int previous = s.state(point(lo));
      for (double a = lo + step; a <= hi + 1e-9; a += step) {
        const int now = s.state(point(a));
        if (now == previous) continue;
        double x0 = a - step, x1 = a;
        int s1 = now;
        while (x1 - x0 > 3e-4) {
          const double m = 0.5 * (x0 + x1);
          const int sm = s.state(point(m));
          if (sm == previous) x0 = m;
          else x1 = m, s1 = sm;
        }
        if (std::abs(s1 - previous) == 1) {
          const int which = std::min(s1, previous);
          const double d = distance_to(s.edges, which == 0 ? EdgeKind::umbral : EdgeKind::penumbral, point(0.5 * (x0 + x1)));
          ++result.changes[which];
          result.missed[which] += d > tolerance;
          result.worst[which] = std::max(result.worst[which], d);
        }
        previous = now;
      }
    }
  return result;
}

// Ends of floor edges of a kind that meet no other edge of that kind (within eps) and lie on the
// boundary the kind stands for (the states around them differ): gaps in the outline. An umbral
// edge may run on past a corner of the umbra into the penumbra (whole event wedges): its end
// then lies inside one region and is no gap.
int open_ends(const SoftScene& s, EdgeKind kind, double eps) {
  std::vector<glm::dvec3> ends;
  for (const SceneEdge& e : s.edges)
    if (e.object == 0 && e.kind == kind) ends.push_back(e.a), ends.push_back(e.b);
  int open = 0;
  for (size_t i = 0; i < ends.size(); ++i) {
    bool met = false;
    for (size_t j = 0; j < ends.size() && !met; ++j) met = j != i && glm::length(ends[i] - ends[j]) < eps;
    for (size_t j = 0; j + 1 < ends.size() && !met; j += 2) {  // or ends on another edge (a T)
      if (j == i || j + 1 == i) continue;
      const glm::dvec3 d = ends[j + 1] - ends[j];
      const double t = std::clamp(glm::dot(ends[i] - ends[j], d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
      met = glm::length(ends[i] - (ends[j] + t * d)) < eps;
    }
    if (met) continue;
    std::set<int> states;
    for (int k = 0; k < 8; ++k) {
      const double angle = 2.0 * M_PI * k / 8;
      states.insert(s.state(ends[i] + 0.006 * glm::dvec3(std::cos(angle), 0.0, std::sin(angle))));
    }
    const bool on_boundary = kind == EdgeKind::umbral ? states.count(0) && states.count(1) : states.count(1) && states.count(2);
    open += on_boundary;
  }
  return open;
}

// Penumbral floor edges that do not separate fully lit from partly blocked points 3 mm either side
// (sampled at their middles; edges shorter than 1 cm skipped). Against a convex light every
// penumbral event is a plane touching both the light and the blocker from opposite sides, so with
// a convex blocker every point of it beyond the blocker is on the penumbra's boundary. (Not so
// with a torus or a non-convex light: a local event there may lie where another part of the
// blocker already hides part of the light.)
int misplaced_penumbral(const SoftScene& s, int& total) {
  int bad = 0;
  total = 0;
  for (const SceneEdge& e : s.edges) {
    if (e.object != 0 || e.kind != EdgeKind::penumbral || glm::length(e.b - e.a) < 0.01) continue;
    const glm::dvec3 m = 0.5 * (e.a + e.b);
    const glm::dvec3 across = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), e.b - e.a)) * 0.003;
    const int a = s.state(m + across), b = s.state(m - across);
    bad += !((a == 2 && b == 1) || (a == 1 && b == 2));
    ++total;
  }
  return bad;
}

std::vector<glm::dvec3> square(double half, double height, glm::dvec2 centre = {0.0, 0.0}) {
  // Counter-clockwise seen from below (the light shines down).
  return {{centre.x - half, height, centre.y - half},
          {centre.x + half, height, centre.y - half},
          {centre.x + half, height, centre.y + half},
          {centre.x - half, height, centre.y + half}};
}

int count(const std::vector<SceneEdge>& edges, EdgeKind kind, uint32_t receiver = 0) {
  int n = 0;
  for (const SceneEdge& e : edges) n += e.kind == kind && e.object == receiver;
  return n;
}

TEST(SoftShadows, TorusSaddleVerticesCloseTheInnerUmbra) {
  // A torus lying flat: the inner ring's vertices are saddles, where the umbral EV events that
  // close the annular umbra live.
  SoftScene s = soft_scene(square(0.25, 2.5));
  s.world.add(torus(64, 24, 0.6f, 0.15f), at({0, 0.5f, 0}));
  add_light_and_find_edges(s);
  const BoundaryCheck c = check_boundaries(s, -1.0, 1.0, 30, 0.006);
  EXPECT_GT(c.changes[0], 60);
  EXPECT_GT(c.changes[1], 60);
  EXPECT_EQ(c.missed[0], 0) << "of " << c.changes[0] << " umbra boundary crossings; worst " << c.worst[0];
  EXPECT_EQ(c.missed[1], 0) << "of " << c.changes[1] << " penumbra boundary crossings; worst " << c.worst[1];
  EXPECT_EQ(open_ends(s, EdgeKind::umbral, 1e-6), 0);
  EXPECT_EQ(open_ends(s, EdgeKind::penumbral, 1e-6), 0);
}

TEST(SoftShadows, BoxUnderManySidedLightHasClosedOutlines) {
  // A box corner sees a run of EV events, one per light edge of a 16-sided light.
  std::vector<glm::dvec3> polygon;
  for (int k = 0; k < 16; ++k) {
    const double angle = -2.0 * M_PI * k / 16;  // counter-clockwise seen from below
    polygon.push_back({0.35 * std::cos(angle), 3.0, 0.35 * std::sin(angle)});
  }
  SoftScene s = soft_scene(polygon);
  s.world.add(box({-0.3f, 0.0f, -0.25f}, {0.3f, 0.4f, 0.25f}), at({0.1f, 0.8f, 0.05f}, 25.0f, {0, 1, 0}));
  add_light_and_find_edges(s, 16);
  const BoundaryCheck c = check_boundaries(s, -1.0, 1.0, 16, 0.006);
  int penumbral_edges = 0;
  EXPECT_EQ(misplaced_penumbral(s, penumbral_edges), 0) << "of " << penumbral_edges;
  EXPECT_GT(c.changes[0], 20);
  EXPECT_GT(c.changes[1], 40);
  EXPECT_EQ(c.missed[0], 0) << "of " << c.changes[0] << "; worst " << c.worst[0];
  EXPECT_EQ(c.missed[1], 0) << "of " << c.changes[1] << "; worst " << c.worst[1];
  EXPECT_EQ(open_ends(s, EdgeKind::umbral, 1e-6), 0);
  EXPECT_EQ(open_ends(s, EdgeKind::penumbral, 1e-6), 0);
}

TEST(SoftShadows, NonConvexLight) {
  // An L-shaped light: its reflex vertex starts no event, its edges still do.
  SoftScene s = soft_scene({{-0.3, 3.0, -0.3}, {0.3, 3.0, -0.3}, {0.3, 3.0, 0.0}, {0.0, 3.0, 0.0}, {0.0, 3.0, 0.3}, {-0.3, 3.0, 0.3}});
  std::reverse(s.outline.begin(), s.outline.end());  // counter-clockwise seen from below
  s.world.add(box({-0.3f, 0.0f, -0.25f}, {0.3f, 0.4f, 0.25f}), at({0.1f, 0.8f, 0.05f}, 25.0f, {0, 1, 0}));
  add_light_and_find_edges(s, 16);
  const BoundaryCheck c = check_boundaries(s, -1.0, 1.0, 16, 0.006);
  EXPECT_GT(c.changes[1], 40);
  EXPECT_EQ(c.missed[0], 0) << "of " << c.changes[0] << "; worst " << c.worst[0];
  EXPECT_EQ(c.missed[1], 0) << "of " << c.changes[1] << "; worst " << c.worst[1];
  EXPECT_EQ(open_ends(s, EdgeKind::penumbral, 1e-6), 0);
  // The reflex corner (0, 3, 0) starts no VE event: the light covers both sides of every line
  // through it, so no blocker edge can just cover or just uncover the light there.
  SceneEdgeSettings keep;  // the box's tree whatever the cost model chose
  keep.keep_unchosen_trees = true;
  SceneEdgeFinder finder(s.world.scene, keep);
  const Object& box_object = s.world.scene.objects[1];
  const BlockerView blocker{&finder.edge_mesh(box_object.mesh), &finder.edge_tree(box_object.mesh),
                            glm::dmat4(box_object.object_to_world), 1};
  std::vector<ShadowEvent> events;
  find_shadow_events(blocker, finder.lights()[0], 0, events);
  int from_corners = 0;
  for (const ShadowEvent& e : events) {
    if (e.shape != EventShape::vertex_edge) continue;
    EXPECT_GT(glm::length(e.source0 - glm::dvec3(0.0, 3.0, 0.0)), 1e-6);
    ++from_corners;
  }
  EXPECT_GT(from_corners, 4);
}

TEST(SoftShadows, OpenPlateUnderAnAreaLight) {
  SoftScene s = soft_scene(square(0.25, 2.5));
  s.world.add(grid(3, 0.6f), at({0.1f, 1.0f, 0.0f}, 20.0f, {0, 0, 1}));  // one-sided, tilted
  add_light_and_find_edges(s);
  EXPECT_GT(count(s.edges, EdgeKind::umbral), 3);
  EXPECT_GT(count(s.edges, EdgeKind::penumbral), 3);
  const BoundaryCheck c = check_boundaries(s, -1.0, 1.0, 16, 0.006);
  int penumbral_edges = 0;
  EXPECT_EQ(misplaced_penumbral(s, penumbral_edges), 0) << "of " << penumbral_edges;
  EXPECT_GT(c.changes[0], 20);
  EXPECT_GT(c.changes[1], 20);
  EXPECT_EQ(c.missed[0], 0) << "of " << c.changes[0] << "; worst " << c.worst[0];
  EXPECT_EQ(c.missed[1], 0) << "of " << c.changes[1] << "; worst " << c.worst[1];
  EXPECT_EQ(open_ends(s, EdgeKind::umbral, 1e-6), 0);
  EXPECT_EQ(open_ends(s, EdgeKind::penumbral, 1e-6), 0);
}

TEST(HardShadowsOfOpenSurfaces, PlateUnderAPointLight) {
  // A one-sided floating plate, lit from above (its front) and from below (its back): its border
  // is its shadow's outline either way.
  for (const float light_y : {3.0f, -3.0f}) {
    World w;
    if (light_y > 0) w.add(grid(16, 8.0f), glm::mat4(1.0f));
    else w.add(grid(16, 8.0f), at({0, 4.0f, 0}, 180.0f, {1, 0, 0}));  // a ceiling facing down
    w.add(grid(3, 0.8f), at({0.0f, 1.0f, 0.1f}, 15.0f, {1, 0, 0}));
    PunctualLight light;
    light.position = {0.3f, light_y, -0.2f};
    w.scene.punctual_lights.push_back(light);
    SceneEdgeFinder finder(w.scene);
    std::vector<SceneEdge> edges;
    finder.shadow_edges(w.scene, finder.find_triples(w.scene), edges);
    const uint32_t receiver = 0;
    const glm::dvec3 up(0, light_y > 0 ? 1 : -1, 0);
    int on_receiver = 0, separating = 0;
    for (const SceneEdge& e : edges) {
      if (e.object != receiver || e.blocker != 1) continue;
      ++on_receiver;
      const glm::dvec3 m = 0.5 * (e.a + e.b) + 1e-4 * up;
      const glm::dvec3 across = glm::normalize(glm::cross(up, e.b - e.a)) * 2e-3;
      separating += w.sees_point(m + across, light.position) != w.sees_point(m - across, light.position);
    }
    EXPECT_GE(on_receiver, 4) << light_y;
    EXPECT_EQ(separating, on_receiver) << light_y;
    // Completeness: the shadow's outline, found by scanning, has an edge beside it everywhere.
    const double y = light_y > 0 ? 1e-4 : 4.0 - 1e-4;
    int changes = 0, found = 0;
    for (int axis = 0; axis < 2; ++axis)
      for (int l = 0; l < 30; ++l) {
        const double c = -1.5 + 3.0 * (l + 0.5) / 30;
        auto point = [&](double a) { return axis == 0 ? glm::dvec3(a, y, c) : glm::dvec3(c, y, a); };
        bool previous = w.sees_point(point(-1.5), light.position);
        for (double a = -1.5 + 0.01; a <= 1.5; a += 0.01) {
          const bool now = w.sees_point(point(a), light.position);
          if (now == previous) continue;
          previous = now;
          ++changes;
          double best = INFINITY;
          for (const SceneEdge& e : edges) {
            if (e.object != receiver) continue;
            const glm::dvec3 p = point(a - 0.005), d = e.b - e.a;
            const double t = std::clamp(glm::dot(p - e.a, d) / glm::dot(d, d), 0.0, 1.0);
            best = std::min(best, glm::length(p - (e.a + t * d)));
          }
          found += best < 0.011;
        }
      }
    EXPECT_GT(changes, 30) << light_y;
    EXPECT_EQ(found, changes) << light_y;
  }
}

TEST(HardShadowsOfOpenSurfaces, PlateUnderADirectionalLight) {
  World w;
  w.add(grid(16, 8.0f), glm::mat4(1.0f));
  w.add(grid(3, 0.8f), at({0.0f, 1.0f, 0.1f}, 15.0f, {1, 0, 0}));
  PunctualLight sun;
  sun.type = LightType::directional;
  sun.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, 0.2f));
  w.scene.punctual_lights.push_back(sun);
  SceneEdgeFinder finder(w.scene);
  std::vector<SceneEdge> edges;
  finder.shadow_edges(w.scene, finder.find_triples(w.scene), edges);
  const glm::dvec3 travel(sun.direction);
  int on_floor = 0, separating = 0;
  for (const SceneEdge& e : edges) {
    if (e.object != 0 || e.blocker != 1) continue;
    ++on_floor;
    const glm::dvec3 m = 0.5 * (e.a + e.b) + glm::dvec3(0, 1e-4, 0);
    const glm::dvec3 across = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), e.b - e.a)) * 2e-3;
    separating += w.sees_direction(m + across, travel) != w.sees_direction(m - across, travel);
  }
  EXPECT_GE(on_floor, 12);  // the plate's 12 border edges (no silhouette on a flat plate)
  EXPECT_EQ(separating, on_floor);
}

TEST(ShadowClipping, InterpenetratingReceivers) {
  // A tilted plate passing through the floor: the sphere's hard shadow falls across the line
  // where they cross. Every shadow edge must lie on the surface nearest the light, on either side
  // of the crossing.
  World w;
  w.add(grid(4, 6.0f), glm::mat4(1.0f));
  w.add(grid(3, 3.0f), at({0.2f, 0.0f, 0.0f}, 30.0f, {0, 0, 1}));  // crosses the floor along x = 0.2, inside its faces
  w.add(uv_sphere(12, 24, 0.4f), at({0.2f, 2.0f, 0.0f}));
  PunctualLight light;
  light.position = {0.25f, 5.0f, 0.1f};
  w.scene.punctual_lights.push_back(light);
  SceneEdgeFinder finder(w.scene);
  std::vector<SceneEdge> edges;
  finder.shadow_edges(w.scene, finder.find_triples(w.scene), edges);
  World receivers_only;  // the floor and the plate, without the blocker
  receivers_only.add(w.scene.meshes[0], w.scene.objects[0].object_to_world);
  receivers_only.add(w.scene.meshes[1], w.scene.objects[1].object_to_world);
  int on_floor = 0, on_plate = 0, hidden = 0, samples = 0;
  for (const SceneEdge& e : edges) {
    if (e.blocker != 2 || e.object == 2) continue;
    (e.object == 0 ? on_floor : on_plate)++;
    for (int k = 0; k <= 4; ++k) {
      const glm::dvec3 p = e.a + (e.b - e.a) * (0.05 + 0.9 * k / 4.0);
      const glm::dvec3 towards = glm::dvec3(light.position) - p;
      hidden += receivers_only.blocked(p + 1e-6 * towards, towards, 1.0);
      ++samples;
    }
  }
  EXPECT_GT(on_floor, 5);
  EXPECT_GT(on_plate, 5);
  EXPECT_EQ(hidden, 0) << "of " << samples << " points on shadow edges are hidden from the light by the other receiver";
}


TEST(HardShadowsOfOpenSurfaces, PlateSeenEdgeOnCastsNoShadowEdges) {
  // A point light in the plane of a tilted open plate (in float, within rounding of it): the
  // plate casts a shadow of zero width, so no event may come from its border edges; an exact
  // zero test lets rounding make the plate's own plane an event plane across the floor.
  World w;
  w.add(grid(16, 8.0f), glm::mat4(1.0f));
  const glm::mat4 place = at({0.0f, 1.0f, 0.1f}, 15.0f, {0, 0, 1});
  w.add(grid(3, 0.8f), place);
  // height: the light's offset from the plate's plane (0: in it; 0.02: just above, a real shadow).
  auto plate_events = [&](float height) {
    int count = 0;
    for (const float s : {1.7f, 2.3f, -1.9f, 2.9f})
      for (const float t : {0.3f, -0.45f, 0.05f}) {
        Scene scene = w.scene;
        PunctualLight light;
        light.position = glm::vec3(place * glm::vec4(s, height, t, 1.0f));
        scene.punctual_lights.push_back(light);
        SceneEdgeFinder finder(scene);
        std::vector<SceneEdge> edges;
        const std::vector<LightBlockerReceiver> triples = {{0, 1, 0}};
        finder.shadow_edges(scene, triples, edges);
        for (const SceneEdge& e : edges) count += e.blocker == 1;
      }
    return count;
  };
  EXPECT_EQ(plate_events(0.0f), 0);
  EXPECT_GT(plate_events(0.02f), 0);
}

}  // namespace
}  // namespace epi::edges

// View edges with analytic answers: the exact silhouette and sharp sets of a cube seen from known
// viewpoints, the sharp cutoff, borders seen from both sides, non-manifold edges, and the light
// names that the renderer's per-frame calls must not grow.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "edges/scene_edges.h"
#include "test_meshes.h"

namespace epi::edges {
namespace {

using namespace test;
using Segment = std::pair<glm::ivec3, glm::ivec3>;  // integer corners of a unit cube, sorted

Segment segment(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::ivec3 p(glm::round(a)), q(glm::round(b));
  return std::lexicographical_compare(&p.x, &p.x + 3, &q.x, &q.x + 3) ? Segment{p, q} : Segment{q, p};
}

struct Less {
  bool operator()(const Segment& a, const Segment& b) const {
    const int x[6] = {a.first.x, a.first.y, a.first.z, a.second.x, a.second.y, a.second.z};
    const int y[6] = {b.first.x, b.first.y, b.first.z, b.second.x, b.second.y, b.second.z};
    return std::lexicographical_compare(x, x + 6, y, y + 6);
  }
};
using Segments = std::set<Segment, Less>;

// The cube [-1, 1]^3 (two triangles per face: the diagonals are flat edges, never drawn).
struct CubeView {
  Segments silhouette, sharp, border;
};

CubeView view_cube(const glm::dvec3& eye, float sharp_degrees = 85.0f) {
  Scene scene;
  scene.meshes.push_back(box({-1, -1, -1}, {1, 1, 1}));
  scene.meshes.back().sharp_angle_degrees = sharp_degrees;
  scene.objects.push_back({"cube", 0, glm::mat4(1.0f)});
  const SceneEdgeFinder finder(scene);
  std::vector<SceneEdge> edges;
  finder.view_edges(scene, eye, edges);
  CubeView view;
  for (const SceneEdge& e : edges) {
    Segments& set = e.kind == EdgeKind::silhouette ? view.silhouette : e.kind == EdgeKind::sharp ? view.sharp : view.border;
    EXPECT_TRUE(set.insert(segment(e.a, e.b)).second) << "reported twice";
  }
  return view;
}

// The cube's edges along which coordinate `axis` varies, at the given signs of the other two.
Segment cube_edge(int axis, int s1, int s2) {
  glm::dvec3 a(0.0), b(0.0);
  a[axis] = -1, b[axis] = 1;
  a[(axis + 1) % 3] = b[(axis + 1) % 3] = s1;
  a[(axis + 2) % 3] = b[(axis + 2) % 3] = s2;
  return segment(a, b);
}

TEST(ViewEdges, CubeFacingOneFace) {
  // From +z only the +z face is front-facing: its four edges are the silhouette, no sharp edge
  // is drawn (each of the 12 is either a silhouette or between two back faces).
  const CubeView v = view_cube({0.3, -0.2, 6.0});
  const Segments expected = {cube_edge(0, -1, 1), cube_edge(0, 1, 1), cube_edge(1, 1, -1), cube_edge(1, 1, 1)};
  EXPECT_EQ(v.silhouette, expected);
  EXPECT_TRUE(v.sharp.empty());
  EXPECT_TRUE(v.border.empty());
}

TEST(ViewEdges, CubeFromAnEdgeSide) {
  // From (5, 5, 0.2): the +x and +y faces are front-facing; the silhouette is the six outer edges
  // of those two faces and the edge between them (x = y = 1) is sharp, not a silhouette.
  const CubeView v = view_cube({5.0, 5.0, 0.2});
  const Segments silhouette = {cube_edge(2, 1, -1), cube_edge(2, -1, 1),   // along z: x=1,y=-1 and x=-1,y=1
                               cube_edge(1, 1, 1), cube_edge(1, -1, 1),    // along y at x=1: z=1, z=-1
                               cube_edge(0, 1, 1), cube_edge(0, 1, -1)};   // along x at y=1: z=1, z=-1
  EXPECT_EQ(v.silhouette, silhouette);
  EXPECT_EQ(v.sharp, Segments({cube_edge(2, 1, 1)}));
}

TEST(ViewEdges, CubeFromACorner) {
  // From (4, 5, 6): three faces front-facing; the silhouette is a hexagon and the three edges at
  // the corner (1, 1, 1) are sharp.
  const CubeView v = view_cube({4.0, 5.0, 6.0});
  EXPECT_EQ(v.silhouette, Segments({cube_edge(0, 1, -1), cube_edge(0, -1, 1), cube_edge(1, 1, -1), cube_edge(1, -1, 1),
                                    cube_edge(2, 1, -1), cube_edge(2, -1, 1)}));
  EXPECT_EQ(v.sharp, Segments({cube_edge(0, 1, 1), cube_edge(1, 1, 1), cube_edge(2, 1, 1)}));
  // With the cutoff above the cube's 90 degree dihedral angle nothing is sharp; the silhouette is
  // the same (a silhouette does not depend on the cutoff).
  const CubeView blunt = view_cube({4.0, 5.0, 6.0}, 91.0f);
  EXPECT_EQ(blunt.silhouette, v.silhouette);
  EXPECT_TRUE(blunt.sharp.empty());
  EXPECT_EQ(view_cube({4.0, 5.0, 6.0}, 89.0f).sharp, v.sharp);
}

TEST(ViewEdges, BordersFromBothSides) {
  // An open square: its four outer edges (8 mesh edges) are borders from the front and from behind;
  // the flat inner edges are nothing.
  for (const double y : {3.0, -3.0}) {
    Scene scene;
    scene.meshes.push_back(grid(2, 2.0f));
    scene.objects.push_back({"plate", 0, glm::mat4(1.0f)});
    const SceneEdgeFinder finder(scene);
    std::vector<SceneEdge> edges;
    finder.view_edges(scene, {0.2, y, 0.1}, edges);
    ASSERT_EQ(edges.size(), 8u) << y;
    for (const SceneEdge& e : edges) {
      EXPECT_EQ(e.kind, EdgeKind::border);
      EXPECT_TRUE((std::fabs(e.a.x) == 1.0 && e.a.x == e.b.x) || (std::fabs(e.a.z) == 1.0 && e.a.z == e.b.z));
    }
  }
}

TEST(ViewEdges, NonManifoldEdgeSeenThroughAThirdFace) {
  // Three fins on the edge (0,0,0)-(1,0,0). From the viewpoint chosen, the first two fins face
  // away and the third faces the viewer: the edge is drawn (as sharp), though Equation 1 on its first
  // two faces says nothing.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0.2f}, {0.5f, 1, -0.2f}, {0.5f, -1, 0.0f}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  m = finish(std::move(m), "fins");
  const EdgeMesh mesh = build_edge_mesh(m);
  uint32_t edge = kNone;
  for (uint32_t e = 0; e < mesh.edge_count(); ++e)
    if (mesh.flags[e] & kNonManifold) edge = e;
  ASSERT_NE(edge, kNone);
  uint32_t scratch[2];
  EXPECT_EQ(mesh.edge_faces(edge, scratch).size(), 3u);
  const Viewpoint v = mesh.local_point({0.5, 10.0, -1.0});
  ASSERT_FALSE(front_facing(mesh, mesh.face0[edge], v));
  ASSERT_FALSE(front_facing(mesh, mesh.face1[edge], v));
  ASSERT_FALSE(is_silhouette(mesh, edge, v));
  std::vector<uint32_t> sharp, border;
  visible_feature_edges(mesh, v, sharp, border);
  EXPECT_NE(std::find(sharp.begin(), sharp.end(), edge), sharp.end());
  // From where no fin faces the viewer the edge is not drawn.
  const Viewpoint behind = mesh.local_point({0.5, 10.0, 1.0});
  bool any = false;
  for (uint32_t f : mesh.edge_faces(edge, scratch)) any |= front_facing(mesh, f, behind);
  ASSERT_FALSE(any);
  visible_feature_edges(mesh, behind, sharp, border);
  EXPECT_EQ(std::find(sharp.begin(), sharp.end(), edge), sharp.end());
}

TEST(ShadowEvents, NonManifoldEdgeInsideItsOwnShadowIsNoEvent) {
  // Three fins on one edge under a point light straight above it: the first two fins hang on one
  // side of the vertical plane through the edge (Equation 1 calls it a silhouette), the third on
  // the other, so the edge's image is covered on both sides: no shadow event from it.
  Mesh m;
  m.positions = {{-0.5f, 0, 0}, {0.5f, 0, 0}, {0, -0.4f, 0.3f}, {0, 0.3f, 0.4f}, {0, -0.3f, -0.4f}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  m = finish(std::move(m), "fins");
  const EdgeMesh mesh = build_edge_mesh(m);
  uint32_t edge = kNone;
  for (uint32_t e = 0; e < mesh.edge_count(); ++e)
    if (mesh.flags[e] & kNonManifold) edge = e;
  ASSERT_NE(edge, kNone);
  EdgeLight light;
  light.position = {0.0, 3.0, 0.0};
  const Viewpoint v = mesh.local_point(light.position);
  ASSERT_TRUE(is_silhouette(mesh, edge, v));  // by its first two faces
  std::vector<ShadowEvent> events;
  find_shadow_events({&mesh, nullptr, glm::dmat4(1.0), 0}, light, 0, events);
  EXPECT_FALSE(events.empty());  // the fins' borders
  for (const ShadowEvent& e : events)
    EXPECT_FALSE(std::min(e.blocker_v0, e.blocker_v1) == std::min(mesh.v0[edge], mesh.v1[edge]) &&
                 std::max(e.blocker_v0, e.blocker_v1) == std::max(mesh.v0[edge], mesh.v1[edge]));
}

TEST(SceneEdgeFinder, LightNamesDoNotGrowFromFrameToFrame) {
  Scene scene;
  scene.meshes.push_back(grid(2, 4.0f));
  scene.meshes.push_back(uv_sphere(8, 16, 0.5f));
  scene.objects.push_back({"floor", 0, glm::mat4(1.0f)});
  scene.objects.push_back({"ball", 1, glm::translate(glm::mat4(1.0f), glm::vec3(0, 1, 0))});
  PunctualLight light;
  light.name = "sun";
  light.position = {0, 4, 0};
  scene.punctual_lights.push_back(light);
  SceneEdgeFinder finder(scene);
  std::vector<SceneEdge> edges;
  for (int frame = 0; frame < 3; ++frame) finder.shadow_edges(scene, finder.find_triples(scene), edges);
  ASSERT_EQ(finder.light_names().size(), 1u);
  EXPECT_EQ(finder.light_names()[0], "sun");
}

}  // namespace
}  // namespace epi::edges

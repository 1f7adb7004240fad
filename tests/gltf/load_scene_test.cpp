// Valid scenes: hierarchy, instancing, names, buffers in all three containers, index types,
// materials, cameras, lights, camera paths, strips and fans, repairs.
#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "gltf_builder.h"
#include "load_scene.h"

namespace epi {
namespace {

using test::GltfBuilder;
using test::json;
using test::TempDir;

constexpr float kPi = 3.14159265358979f;

glm::vec3 apply(const glm::mat4& m, const glm::vec3& p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

void expect_near(const glm::vec3& a, const glm::vec3& b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

const Object& object_named(const Scene& scene, const std::string& name) {
  for (const Object& o : scene.objects)
    if (o.name == name) return o;
  ADD_FAILURE() << "no object named " << name;
  static Object none;
  return none;
}

// One triangle mesh "tri" instanced by five nodes in a small hierarchy.
GltfBuilder hierarchy_scene() {
  GltfBuilder b;
  const int tri = b.add_mesh("tri", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  const float s = std::sqrt(0.5f);  // quaternion of 90 degrees about +Z: (0, 0, s, s)
  const int c = b.add_node({{"name", "C"}, {"mesh", tri},
                            {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1}}});  // translate (1,0,0)
  const int bn = b.add_node({{"name", "B"}, {"mesh", tri}, {"translation", {0, 0, 5}}, {"rotation", {0, 0, s, s}},
                             {"children", {c}}});
  const int a = b.add_node({{"name", "A"}, {"mesh", tri}, {"scale", {2, 2, 2}}});
  const int a2 = b.add_node({{"name", "A"}, {"mesh", tri}});
  const int unnamed = b.add_node({{"mesh", tri}});
  const int root = b.add_node({{"name", "root"}, {"translation", {1, 2, 3}}, {"children", {a, bn, a2, unnamed}}});
  b.set_scene({root});
  return b;
}

TEST(LoadScene, HierarchyInstancingAndWorldTransforms) {
  TempDir dir;
  const Scene scene = load_scene(hierarchy_scene().write_gltf(dir / "h.gltf"));
  ASSERT_EQ(scene.meshes.size(), 1u);  // one glTF mesh -> one Mesh, however many nodes use it
  ASSERT_EQ(scene.objects.size(), 5u);
  for (const Object& o : scene.objects) EXPECT_EQ(o.mesh, 0u);
  EXPECT_EQ(scene.meshes[0].triangles.size(), 1u);
  EXPECT_EQ(scene.triangle_count(), 5u);

  // Preorder, children in file order: A, B, C, A#2, tri.
  ASSERT_EQ(scene.objects[0].name, "A");
  EXPECT_EQ(scene.objects[1].name, "B");
  EXPECT_EQ(scene.objects[2].name, "C");
  EXPECT_EQ(scene.objects[3].name, "A#2");
  EXPECT_EQ(scene.objects[4].name, "tri");  // unnamed node: the mesh name

  const glm::vec3 p(0.3f, 0.7f, -0.2f);
  // A = T(1,2,3) S(2)
  expect_near(apply(object_named(scene, "A").object_to_world, p), glm::vec3(1, 2, 3) + 2.0f * p);
  // B = T(1,2,3) T(0,0,5) Rz(90): (x, y, z) -> (-y, x, z)
  expect_near(apply(object_named(scene, "B").object_to_world, p), glm::vec3(1, 2, 8) + glm::vec3(-p.y, p.x, p.z));
  // C = B T(1,0,0)
  expect_near(apply(object_named(scene, "C").object_to_world, p),
              glm::vec3(1, 2, 8) + glm::vec3(-p.y, p.x + 1.0f, p.z));
  expect_near(apply(object_named(scene, "A#2").object_to_world, p), glm::vec3(1, 2, 3) + p);
  // Geometry stays in object space.
  expect_near(scene.meshes[0].positions[1], glm::vec3(1, 0, 0), 0.0f);
  EXPECT_EQ(scene.source, (dir / "h.gltf").string());
  EXPECT_TRUE(scene.repairs.empty());
}

TEST(LoadScene, NamesAreUniqueEvenAgainstExistingSuffixes) {
  TempDir dir;
  GltfBuilder b;
  const int m = b.add_mesh("", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {});
  std::vector<int> roots;
  for (const char* name : {"x", "x#2", "x", ""}) {
    json node = {{"mesh", m}};
    if (*name) node["name"] = name;
    roots.push_back(b.add_node(node));
  }
  b.set_scene(roots);
  const Scene scene = load_scene(b.write_gltf(dir / "n.gltf"));
  ASSERT_EQ(scene.objects.size(), 4u);
  EXPECT_EQ(scene.objects[0].name, "x");
  EXPECT_EQ(scene.objects[1].name, "x#2");
  EXPECT_EQ(scene.objects[2].name, "x#3");
  EXPECT_EQ(scene.objects[3].name, "node3");  // neither node nor mesh name
}

TEST(LoadScene, GlbEmbeddedAndExternalBuffersGiveTheSameScene) {
  TempDir dir;
  GltfBuilder b = hierarchy_scene();
  const Scene external = load_scene(b.write_gltf(dir / "a.gltf"));
  const Scene embedded = load_scene(b.write_embedded(dir / "b.gltf"));
  const Scene binary = load_scene(b.write_glb(dir / "c.glb"));
  for (const Scene* s : {&embedded, &binary}) {
    ASSERT_EQ(s->objects.size(), external.objects.size());
    ASSERT_EQ(s->meshes.size(), 1u);
    EXPECT_EQ(s->meshes[0].positions, external.meshes[0].positions);
    EXPECT_EQ(s->meshes[0].triangles, external.meshes[0].triangles);
    for (size_t i = 0; i < s->objects.size(); ++i) {
      EXPECT_EQ(s->objects[i].name, external.objects[i].name);
      EXPECT_EQ(s->objects[i].object_to_world, external.objects[i].object_to_world);
    }
  }
}

TEST(LoadScene, EveryIndexTypeAndNonIndexedGiveTheSameTriangles) {
  TempDir dir;
  const std::vector<glm::vec3> quad = test::unit_quad_positions();
  for (int type : {5121, 5123, 5125}) {
    GltfBuilder b;
    json primitive = {{"attributes", {{"POSITION", b.add_vec3(quad)}}}, {"indices", b.add_indices(test::unit_quad_indices(), type)}};
    b.doc["meshes"].push_back({{"primitives", {primitive}}});
    b.set_scene({b.add_node({{"mesh", 0}})});
    const Scene scene = load_scene(b.write_glb(dir / ("indices" + std::to_string(type) + ".glb")));
    ASSERT_EQ(scene.meshes[0].triangles.size(), 2u) << type;
    EXPECT_EQ(scene.meshes[0].triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(scene.meshes[0].triangles[1], glm::uvec3(0, 2, 3));
  }
  GltfBuilder b;
  b.add_mesh("flat", {quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]}, {});
  b.set_scene({b.add_node({{"mesh", 0}})});
  const Scene scene = load_scene(b.write_gltf(dir / "flat.gltf"));
  ASSERT_EQ(scene.meshes[0].triangles.size(), 2u);
  EXPECT_EQ(scene.meshes[0].triangles[1], glm::uvec3(3, 4, 5));
  EXPECT_TRUE(scene.meshes[0].normals.empty());
}

TEST(LoadScene, InterleavedAttributesWithByteStride) {
  TempDir dir;
  GltfBuilder b;
  // position and normal interleaved: 24-byte stride.
  std::vector<glm::vec3> interleaved;
  for (const glm::vec3& p : test::unit_quad_positions()) interleaved.insert(interleaved.end(), {p, glm::vec3(0, 0, 2)});
  const int view = b.add_view(interleaved.data(), interleaved.size() * 12, 24);
  const int position = b.add_accessor(view, 5126, 4, "VEC3");
  const int normal = b.add_accessor(view, 5126, 4, "VEC3");
  b.doc["accessors"][normal]["byteOffset"] = 12;
  json primitive = {{"attributes", {{"POSITION", position}, {"NORMAL", normal}}},
                    {"indices", b.add_indices(test::unit_quad_indices(), 5123)}};
  b.doc["meshes"].push_back({{"primitives", {primitive}}});
  b.set_scene({b.add_node({{"mesh", 0}})});
  const Scene scene = load_scene(b.write_gltf(dir / "s.gltf"));
  EXPECT_EQ(scene.meshes[0].positions, test::unit_quad_positions());
  ASSERT_EQ(scene.meshes[0].normals.size(), 4u);
  for (const glm::vec3& n : scene.meshes[0].normals) expect_near(n, glm::vec3(0, 0, 1));  // normalised
}

TEST(LoadScene, MaterialsRangesAndDefaultMaterial) {
  TempDir dir;
  GltfBuilder b;
  const int red = b.add_material({{"name", "red"},
                                  {"pbrMetallicRoughness",
                                   {{"baseColorFactor", {1.0, 0.0, 0.0, 1.0}}, {"metallicFactor", 0.25}, {"roughnessFactor", 0.5}}}});
  const int glow = b.add_material({{"name", "glow"},
                                   {"emissiveFactor", {1.0, 0.5, 0.25}},
                                   {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}});
  const std::vector<glm::vec3> tri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  json mesh = {{"name", "multi"},
               {"primitives",
                {b.make_primitive(tri, {0, 1, 2}, red), b.make_primitive(tri, {0, 2, 1, 0, 1, 2}, glow),
                 b.make_primitive(tri, {0, 1, 2})}}};
  b.doc["meshes"].push_back(mesh);
  b.set_scene({b.add_node({{"mesh", 0}})});
  b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
  b.doc["extensionsRequired"] = {"KHR_materials_emissive_strength"};
  const Scene scene = load_scene(b.write_gltf(dir / "m.gltf"));
  ASSERT_EQ(scene.materials.size(), 3u);
  EXPECT_EQ(scene.materials[0].name, "red");
  expect_near(scene.materials[0].base_color, glm::vec3(1, 0, 0));
  EXPECT_FLOAT_EQ(scene.materials[0].metallic, 0.25f);
  EXPECT_FLOAT_EQ(scene.materials[0].roughness, 0.5f);
  EXPECT_FALSE(scene.materials[0].emissive());
  expect_near(scene.materials[1].emission, glm::vec3(4.0f, 2.0f, 1.0f));
  EXPECT_EQ(scene.materials[2].name, "default");
  expect_near(scene.materials[2].base_color, glm::vec3(0.8f));

  const Mesh& m = scene.meshes[0];
  ASSERT_EQ(m.triangles.size(), 4u);
  ASSERT_EQ(m.materials.size(), 3u);
  EXPECT_EQ(m.materials[0].first_triangle, 0u);
  EXPECT_EQ(m.materials[1].first_triangle, 1u);
  EXPECT_EQ(m.materials[1].triangle_count, 2u);
  EXPECT_EQ(m.materials[2].first_triangle, 3u);
  EXPECT_EQ(m.material_of(0), 0u);
  EXPECT_EQ(m.material_of(2), 1u);
  EXPECT_EQ(m.material_of(3), 2u);
  EXPECT_EQ(m.positions.size(), 9u);  // primitives concatenated
  EXPECT_EQ(m.triangles[3], glm::uvec3(6, 7, 8));
  // An emissive material: one area light for the one object.
  ASSERT_EQ(scene.area_lights.size(), 1u);
  EXPECT_EQ(scene.area_lights[0].triangle_vertices.size(), 6u);
}

TEST(LoadScene, PerspectiveCameraFromNodeTransform) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("tri", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  b.doc["cameras"] = {{{"type", "perspective"}, {"name", "cam"}, {"perspective", {{"yfov", kPi / 3}, {"znear", 0.1}}}}};
  // Rotated 90 degrees about +Y: local -Z looks down world -X; placed at (5, 1, 0).
  const float s = std::sqrt(0.5f);
  const int cam = b.add_node({{"camera", 0}, {"translation", {5, 1, 0}}, {"rotation", {0, s, 0, s}}});
  b.set_scene({b.add_node({{"mesh", 0}}), cam});
  const Scene scene = load_scene(b.write_gltf(dir / "c.gltf"));
  ASSERT_EQ(scene.cameras.size(), 1u);
  const Camera& c = scene.cameras[0];
  EXPECT_EQ(c.name, "cam");
  expect_near(c.eye, glm::vec3(5, 1, 0));
  expect_near(glm::normalize(c.target - c.eye), glm::vec3(-1, 0, 0));
  expect_near(c.up, glm::vec3(0, 1, 0));
  EXPECT_NEAR(c.yfov_degrees, 60.0f, 1e-4f);
  EXPECT_FLOAT_EQ(c.znear, 0.1f);
}

TEST(LoadScene, DefaultCameraFramesTheWorldBounds) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("box", {{-1, -2, -3}, {3, 2, 1}, {3, -2, 1}}, {0, 1, 2});
  b.set_scene({b.add_node({{"mesh", 0}})});
  const Scene scene = load_scene(b.write_gltf(dir / "d.gltf"));
  ASSERT_EQ(scene.cameras.size(), 1u);
  const Camera& c = scene.cameras[0];
  const glm::vec3 centre(1, 0, -1);
  const float radius = 0.5f * glm::length(glm::vec3(4, 4, 4));
  expect_near(c.target, centre);
  expect_near(c.eye, centre + glm::vec3(0, 0, radius / std::sin(glm::radians(22.5f))), 1e-4f);
  expect_near(c.up, glm::vec3(0, 1, 0));
  EXPECT_FLOAT_EQ(c.yfov_degrees, 45.0f);
  // The bounding sphere fits: every corner is inside the vertical field of view.
  for (const glm::vec3& p : scene.meshes[0].positions) {
    const glm::vec3 d = p - c.eye;
    EXPECT_LE(std::abs(d.y) / -d.z, std::tan(glm::radians(22.5f)) + 1e-5f);
  }
}

TEST(LoadScene, PunctualLights) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("tri", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 8.0}, {"name", "bulb"}},
      {{"type", "spot"}, {"intensity", 2.0}, {"range", 10.0}, {"spot", {{"innerConeAngle", 0.25}, {"outerConeAngle", 0.5}}}},
      {{"type", "directional"}}};
  const float s = std::sqrt(0.5f);
  // A point light needs no direction: even a zero scale is fine.
  const int point = b.add_node({{"translation", {1, 2, 3}}, {"scale", {0, 0, 0}},
                                {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  // Rotated -90 degrees about X: local -Z points down world -Y.
  const int spot = b.add_node({{"name", "spotnode"}, {"translation", {0, 4, 0}}, {"rotation", {-s, 0, 0, s}},
                               {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  const int sun = b.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  const int parent = b.add_node({{"translation", {10, 0, 0}}, {"children", {point}}});
  b.set_scene({b.add_node({{"mesh", 0}}), parent, spot, sun});
  const Scene scene = load_scene(b.write_glb(dir / "l.glb"));
  ASSERT_EQ(scene.punctual_lights.size(), 3u);
  const PunctualLight& p = scene.punctual_lights[0];
  EXPECT_EQ(p.type, LightType::point);
  EXPECT_EQ(p.name, "bulb");
  expect_near(p.position, glm::vec3(11, 2, 3));
  expect_near(p.intensity, glm::vec3(8, 4, 2));
  EXPECT_EQ(p.range, 0.0f);
  const PunctualLight& sp = scene.punctual_lights[1];
  EXPECT_EQ(sp.type, LightType::spot);
  EXPECT_EQ(sp.name, "spotnode");
  expect_near(sp.position, glm::vec3(0, 4, 0));
  expect_near(sp.direction, glm::vec3(0, -1, 0));
  EXPECT_NEAR(sp.inner_cone_cos, std::cos(0.25f), 1e-6f);
  EXPECT_NEAR(sp.outer_cone_cos, std::cos(0.5f), 1e-6f);
  EXPECT_FLOAT_EQ(sp.range, 10.0f);
  expect_near(sp.intensity, glm::vec3(2));
  const PunctualLight& d = scene.punctual_lights[2];
  EXPECT_EQ(d.type, LightType::directional);
  expect_near(d.direction, glm::vec3(0, 0, -1));
  expect_near(d.intensity, glm::vec3(1));
  EXPECT_TRUE(scene.area_lights.empty());
}

TEST(LoadScene, CameraPathFromSceneExtras) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("tri", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  b.set_scene({b.add_node({{"mesh", 0}})});
  b.doc["extras"] = {{"epi",
                      {{"camera_path",
                        {{{"eye", {0, 0, 5}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"yfov", 30}},
                         {{"eye", {5, 0, 0}}, {"target", {0, 0, 0}}}}}}}};
  const Scene scene = load_scene(b.write_gltf(dir / "p.gltf"));
  ASSERT_EQ(scene.camera_path.size(), 2u);
  expect_near(scene.camera_path[0].eye, glm::vec3(0, 0, 5));
  EXPECT_FLOAT_EQ(scene.camera_path[0].yfov_degrees, 30.0f);
  expect_near(scene.camera_path[1].eye, glm::vec3(5, 0, 0));
  expect_near(scene.camera_path[1].up, glm::vec3(0, 1, 0));
  EXPECT_FLOAT_EQ(scene.camera_path[1].yfov_degrees, 45.0f);
}

TEST(LoadScene, CameraPathInTheChosenSceneWinsOverTheRoot) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("tri", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  b.set_scene({b.add_node({{"mesh", 0}})});
  b.doc["extras"] = {{"epi", {{"camera_path", {{{"eye", {0, 0, 5}}, {"target", {0, 0, 0}}}}}}}};
  b.doc["scenes"][0]["extras"] = {
      {"epi", {{"camera_path", {{{"eye", {0, 3, 3}}, {"target", {0, 0, 0}}}, {{"eye", {3, 3, 0}}, {"target", {0, 0, 0}}},
                                {{"eye", {3, 0, 3}}, {"target", {0, 0, 0}}}}}}}};
  const Scene scene = load_scene(b.write_gltf(dir / "p.gltf"));
  ASSERT_EQ(scene.camera_path.size(), 3u);
  expect_near(scene.camera_path[0].eye, glm::vec3(0, 3, 3));

  b.doc["scenes"][0]["extras"]["epi"]["camera_path"][1] = {{"target", {0, 0, 0}}};
  try {
    load_scene(b.write_gltf(dir / "bad.gltf"));
    FAIL() << "expected SceneLoadError";
  } catch (const SceneLoadError& e) {
    EXPECT_NE(std::string(e.what()).find("scenes[0].extras.epi.camera_path[1]"), std::string::npos) << e.what();
  }
}

TEST(LoadScene, StripsAndFansAreTriangulatedWithConsistentWinding) {
  TempDir dir;
  GltfBuilder b;
  // Four vertices of the unit quad, as a strip (0,1,3,2) and as a fan (0,1,2,3): both face +Z.
  const std::vector<glm::vec3> quad = test::unit_quad_positions();
  json strip = b.make_primitive(quad, {0, 1, 3, 2});
  strip["mode"] = 5;
  json fan = b.make_primitive(quad, {0, 1, 2, 3});
  fan["mode"] = 6;
  b.doc["meshes"] = {{{"name", "strip"}, {"primitives", {strip}}}, {{"name", "fan"}, {"primitives", {fan}}}};
  b.set_scene({b.add_node({{"mesh", 0}}), b.add_node({{"mesh", 1}})});
  const Scene scene = load_scene(b.write_gltf(dir / "sf.gltf"));
  ASSERT_EQ(scene.meshes.size(), 2u);
  for (const Mesh& m : scene.meshes) {
    ASSERT_EQ(m.triangles.size(), 2u) << m.name;
    float area = 0;
    for (const glm::uvec3& t : m.triangles) {
      const glm::vec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
      EXPECT_GT(n.z, 0.0f) << m.name;  // counter-clockwise seen from +Z
      area += 0.5f * glm::length(n);
    }
    EXPECT_FLOAT_EQ(area, 1.0f) << m.name;
  }
}

TEST(LoadScene, DegenerateTrianglesAreDroppedAndReported) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("bad", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}}, {0, 1, 2, 0, 0, 1, 0, 1, 3});
  b.set_scene({b.add_node({{"mesh", 0}})});
  const Scene scene = load_scene(b.write_gltf(dir / "dg.gltf"));
  EXPECT_EQ(scene.meshes[0].triangles.size(), 1u);
  EXPECT_EQ(scene.meshes[0].degenerate_triangles_dropped, 2u);
  ASSERT_EQ(scene.repairs.size(), 1u);
  EXPECT_EQ(scene.repairs[0], "mesh 'bad': dropped 2 degenerate triangles");
}

TEST(LoadScene, MixedNormalsGetFlatNormalsWhereMissing) {
  TempDir dir;
  GltfBuilder b;
  const std::vector<glm::vec3> tri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  json with = b.make_primitive(tri, {0, 1, 2}, -1, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  json without = b.make_primitive({{0, 0, 1}, {0, 1, 1}, {1, 0, 1}}, {0, 1, 2});  // faces -Z
  b.doc["meshes"] = {{{"primitives", {with, without}}}};
  b.set_scene({b.add_node({{"mesh", 0}})});
  const Scene scene = load_scene(b.write_gltf(dir / "mn.gltf"));
  const Mesh& m = scene.meshes[0];
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (uint32_t v : {m.triangles[1].x, m.triangles[1].y, m.triangles[1].z}) expect_near(m.normals[v], glm::vec3(0, 0, -1));
}

TEST(LoadScene, ZeroNormalsAreRepaired) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("zn", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2}, -1, {{0, 0, 1}, {0, 0, 0}, {0, 0, 3}});
  b.set_scene({b.add_node({{"mesh", 0}})});
  const Scene scene = load_scene(b.write_gltf(dir / "zn.gltf"));
  for (const glm::vec3& n : scene.meshes[0].normals) expect_near(n, glm::vec3(0, 0, 1));
  ASSERT_EQ(scene.repairs.size(), 1u);
  EXPECT_EQ(scene.repairs[0], "mesh 'zn': replaced 1 zero-length normals by face normals");
}

TEST(LoadScene, DeepHierarchyNeedsNoRecursion) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("tri", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  const int depth = 20000;
  for (int i = 0; i < depth; ++i) {
    json node = {{"translation", {0.0, 0.0, 0.5}}};
    if (i + 1 < depth) node["children"] = {i + 1};
    else node["mesh"] = 0;
    b.add_node(node);
  }
  b.set_scene({0});
  const Scene scene = load_scene(b.write_glb(dir / "deep.glb"));
  ASSERT_EQ(scene.objects.size(), 1u);
  expect_near(apply(scene.objects[0].object_to_world, glm::vec3(0)), glm::vec3(0, 0, 0.5f * depth), 1e-3f);
}

TEST(LoadScene, SceneIndexPicksTheScene) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("one", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  b.add_mesh("two", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {0, 1, 2, 1, 3, 2});
  b.add_node({{"mesh", 0}});
  b.add_node({{"mesh", 1}});
  b.doc["scenes"] = {{{"nodes", {0}}}, {{"nodes", {1}}}};
  b.doc["scene"] = 1;
  Scene scene = load_scene(b.write_gltf(dir / "s1.gltf"));
  EXPECT_EQ(scene.triangle_count(), 2u);
  b.doc.erase("scene");  // none given: scene 0
  scene = load_scene(b.write_gltf(dir / "s0.gltf"));
  EXPECT_EQ(scene.triangle_count(), 1u);
  EXPECT_EQ(scene.meshes.size(), 1u);  // meshes of other scenes are not built
}

// Property test: random forests of nodes with random matrix or TRS transforms. World transforms
// must equal the product along the parent chain (computed here by walking up), and objects come
// in preorder.
TEST(LoadScene, RandomHierarchiesMatchParentChainProducts) {
  TempDir dir;
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> uniform(-2.0f, 2.0f);
  for (int trial = 0; trial < 30; ++trial) {
    GltfBuilder b;
    b.add_mesh("tri", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
    const int count = 1 + int(rng() % 40);
    std::vector<int> parent(static_cast<size_t>(count), -1);
    std::vector<glm::mat4> local(static_cast<size_t>(count));
    b.doc["nodes"] = json::array();
    for (int i = 0; i < count; ++i) {
      json node = {{"name", "random_node" + std::to_string(i)}, {"mesh", 0}};
      const glm::vec3 t(uniform(rng), uniform(rng), uniform(rng));
      const glm::vec3 scale(0.5f + 0.25f * (uniform(rng) + 2.0f), 0.5f + 0.25f * (uniform(rng) + 2.0f), -1.0f);
      const glm::quat q = glm::normalize(glm::quat(uniform(rng), uniform(rng), uniform(rng), uniform(rng)));
      local[size_t(i)] = glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(q) * glm::scale(glm::mat4(1.0f), scale);
      if (rng() % 2) {
        node["translation"] = {t.x, t.y, t.z};
        node["rotation"] = {q.x, q.y, q.z, q.w};
        node["scale"] = {scale.x, scale.y, scale.z};
      } else {
        const float* m = &local[size_t(i)][0][0];
        node["matrix"] = std::vector<float>(m, m + 16);
      }
      b.doc["nodes"].push_back(node);
    }
    std::vector<int> roots;
    for (int i = 0; i < count; ++i) {
      if (i > 0 && rng() % 4 != 0) {
        parent[size_t(i)] = int(rng() % unsigned(i));  // parents come first: no cycles
        b.doc["nodes"][parent[size_t(i)]]["children"].push_back(i);
      } else {
        roots.push_back(i);
      }
    }
    b.set_scene(roots);
    const Scene scene = load_scene(b.write_glb(dir / "r.glb"));
    ASSERT_EQ(scene.objects.size(), size_t(count));

    // Reference: preorder over the forest with the product along each parent chain.
    std::vector<int> order;
    std::vector<int> stack(roots.rbegin(), roots.rend());
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      order.push_back(n);
      const json& children = b.doc["nodes"][n].value("children", json::array());
      for (auto c = children.rbegin(); c != children.rend(); ++c) stack.push_back(c->get<int>());
    }
    for (size_t k = 0; k < order.size(); ++k) {
      glm::mat4 world(1.0f);
      for (int n = order[k]; n >= 0; n = parent[size_t(n)]) world = local[size_t(n)] * world;
      ASSERT_EQ(scene.objects[k].name, "random_node" + std::to_string(order[k]));
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
          ASSERT_NEAR(scene.objects[k].object_to_world[c][r], world[c][r], 2e-4f * (1.0f + std::abs(world[c][r])))
              << "trial " << trial << " node " << order[k];
    }
  }
}

}  // namespace
}  // namespace epi

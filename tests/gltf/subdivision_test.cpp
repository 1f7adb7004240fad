// Subdivision requests in mesh extras: cage welding, quads from triangle pairs, creases, levels.
#include <gtest/gtest.h>

#include "gltf_builder.h"
#include "load_scene.h"
#include "scene/topology.h"

namespace epi {
namespace {

using test::GltfBuilder;
using test::json;
using test::TempDir;

// The exporter-style cube (24 vertices) with a subdivision request.
GltfBuilder cube_scene(const json& subdivision, int primitives = 1) {
  GltfBuilder b;
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  test::unit_cube(positions, indices);
  json mesh = {{"name", "cube"}, {"primitives", json::array()}};
  for (int p = 0; p < primitives; ++p) {
    const int material = b.add_material({{"name", "material" + std::to_string(p)}});
    mesh["primitives"].push_back(b.make_primitive(positions, indices, material));
  }
  mesh["extras"]["epi"]["subdivision"] = subdivision;
  b.doc["meshes"].push_back(mesh);
  b.set_scene({b.add_node({{"mesh", 0}})});
  return b;
}

size_t pow4(int n) { return size_t(1) << (2 * n); }

TEST(Subdivision, CatmullClarkCubeWithQuadsGives6Times4PowNQuads) {
  TempDir dir;
  for (int level = 0; level <= 3; ++level) {
    SCOPED_TRACE(level);
    const Scene scene =
        load_scene(cube_scene({{"scheme", "catmull-clark"}, {"level", level}, {"quads", true}}).write_gltf(dir / "c.gltf"));
    const Mesh& mesh = scene.meshes[0];
    EXPECT_EQ(mesh.triangles.size(), 12 * pow4(level));  // 6 * 4^N quads, two triangles each
    EXPECT_TRUE(mesh.subdivided);
    EXPECT_EQ(mesh.subdivision.scheme, SubdivisionScheme::catmull_clark);
    EXPECT_EQ(mesh.subdivision.level, level);
    EXPECT_EQ(mesh.subdivision.control_faces, 6u);
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    // The welded cage makes one closed surface: no border edges (an unwelded one would have 24 patches).
    const EdgeTable table = build_edge_table(mesh);
    EXPECT_EQ(table.border_edges, 0u);
    EXPECT_EQ(table.non_manifold_edges, 0u);
    // Smooth limit surface inside the cage, normals pointing outwards.
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::vec3& p = mesh.positions[v];
      EXPECT_LT(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 0.5f);
      EXPECT_GT(glm::dot(mesh.normals[v], p), 0.0f);
    }
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_EQ(mesh.materials[0].triangle_count, mesh.triangles.size());
  }
}

TEST(Subdivision, LoopCubeGives12Times4PowNTriangles) {
  TempDir dir;
  for (int level = 0; level <= 3; ++level) {
    const Scene scene = load_scene(cube_scene({{"scheme", "loop"}, {"level", level}}).write_glb(dir / "l.glb"));
    EXPECT_EQ(scene.meshes[0].triangles.size(), 12 * pow4(level)) << level;
    EXPECT_EQ(scene.meshes[0].subdivision.scheme, SubdivisionScheme::loop);
    EXPECT_EQ(scene.meshes[0].subdivision.control_faces, 12u);
  }
}

TEST(Subdivision, LevelOverrideAppliesToMeshesThatAskForSubdivision) {
  TempDir dir;
  GltfBuilder b = cube_scene({{"level", 3}, {"quads", true}});
  b.add_mesh("plain", test::unit_quad_positions(), test::unit_quad_indices());
  b.doc["scenes"][0]["nodes"].push_back(b.add_node({{"mesh", 1}}));
  LoadOptions options;
  options.subdiv_level_override = 1;
  const Scene scene = load_scene(b.write_gltf(dir / "o.gltf"), options);
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[0].triangles.size(), 48u);
  EXPECT_EQ(scene.meshes[0].subdivision.level, 1);
  EXPECT_EQ(scene.meshes[1].triangles.size(), 2u);  // no request: untouched
  EXPECT_FALSE(scene.meshes[1].subdivided);
}

TEST(Subdivision, InfinitelySharpCreasesKeepTheCubeEdges) {
  TempDir dir;
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  test::unit_cube(positions, indices);
  // Every cube edge, named by the primitive's (split) vertex indices of the face that holds it.
  json creases = json::array();
  for (uint32_t face = 0; face < 6; ++face)
    for (uint32_t k = 0; k < 4; ++k) creases.push_back({4 * face + k, 4 * face + (k + 1) % 4, 10.0});
  const Scene scene = load_scene(
      cube_scene({{"level", 2}, {"quads", true}, {"creases", creases}}).write_gltf(dir / "sharp.gltf"));
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.subdivision.crease_count, 24u);
  EXPECT_EQ(mesh.triangles.size(), 12 * pow4(2));
  // All edges and corners sharp: the limit surface is the cube itself.
  for (const glm::vec3& p : mesh.positions)
    EXPECT_NEAR(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 0.5f, 1e-5f);
}

TEST(Subdivision, EachPrimitiveIsSubdividedThenConcatenated) {
  TempDir dir;
  const Scene scene = load_scene(cube_scene({{"level", 1}, {"quads", true}}, 2).write_gltf(dir / "two.gltf"));
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.triangles.size(), 2 * 48u);
  EXPECT_EQ(mesh.subdivision.control_faces, 12u);
  ASSERT_EQ(mesh.materials.size(), 2u);
  EXPECT_EQ(mesh.materials[0].triangle_count, 48u);
  EXPECT_EQ(mesh.materials[1].first_triangle, 48u);
  EXPECT_EQ(mesh.material_of(95), 1u);
}

TEST(Subdivision, SharpAngleIsReadWithoutSubdivision) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("m", test::unit_quad_positions(), test::unit_quad_indices());
  b.doc["meshes"][0]["extras"] = {{"epi", {{"sharp_angle", 30}}}, {"other", "ignored"}};
  b.set_scene({b.add_node({{"mesh", 0}})});
  const Scene scene = load_scene(b.write_gltf(dir / "a.gltf"));
  EXPECT_FLOAT_EQ(scene.meshes[0].sharp_angle_degrees, 30.0f);
  EXPECT_FALSE(scene.meshes[0].subdivided);
}

}  // namespace
}  // namespace epi

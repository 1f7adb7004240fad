// Emissive meshes as area lights: world-space triangles, power CDF, area, and outlines.
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "area_lights.h"
#include "gltf_builder.h"
#include "load_scene.h"

namespace epi {
namespace {

using test::GltfBuilder;
using test::json;
using test::TempDir;

// Newell's vector: twice the signed area of a closed loop, as a normal-direction vector.
glm::vec3 loop_area_vector(const std::vector<glm::vec3>& loop) {
  glm::vec3 sum(0.0f);
  for (size_t i = 0; i < loop.size(); ++i) sum += glm::cross(loop[i], loop[(i + 1) % loop.size()]);
  return 0.5f * sum;
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

json emissive_material(const glm::vec3& factor, double strength = 1.0) {
  json m = {{"emissiveFactor", {factor.x, factor.y, factor.z}}};
  if (strength != 1.0) m["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = strength;
  return m;
}

TEST(AreaLights, EmissiveQuadOutlineIsItsFourCornersCounterClockwise) {
  TempDir dir;
  GltfBuilder b;
  const int glow = b.add_material(emissive_material({1, 1, 1}, 5.0));
  b.add_mesh("panel", test::unit_quad_positions(), test::unit_quad_indices(), glow);
  // Scaled by 2, turned 90 degrees about +X (the +Z normal becomes -Y), moved up to y = 3.
  const float s = std::sqrt(0.5f);
  b.set_scene({b.add_node({{"mesh", 0}, {"translation", {0, 3, 0}}, {"rotation", {s, 0, 0, s}}, {"scale", {2, 2, 2}}})});
  const Scene scene = load_scene(b.write_gltf(dir / "q.gltf"));
  ASSERT_EQ(scene.area_lights.size(), 1u);
  const AreaLight& light = scene.area_lights[0];
  const glm::mat4& m = scene.objects[0].object_to_world;
  const glm::vec3 world_normal = glm::normalize(glm::mat3(m) * glm::vec3(0, 0, 1));
  expect_near(world_normal, glm::vec3(0, -1, 0));
  EXPECT_EQ(light.object, 0u);
  EXPECT_NEAR(light.area, 4.0f, 1e-5f);
  EXPECT_NEAR(light.power, 4.0f * 5.0f, 1e-4f);  // luminance(5, 5, 5) * area
  ASSERT_EQ(light.triangle_vertices.size(), 6u);
  ASSERT_EQ(light.triangle_materials, std::vector<uint32_t>({0, 0}));
  ASSERT_EQ(light.triangle_cdf.size(), 2u);
  EXPECT_NEAR(light.triangle_cdf[0], 0.5f, 1e-6f);
  EXPECT_EQ(light.triangle_cdf[1], 1.0f);

  ASSERT_EQ(light.outlines.size(), 1u);
  const std::vector<glm::vec3>& loop = light.outlines[0];
  ASSERT_EQ(loop.size(), 4u);
  // The four world corners, each once, in the cyclic order 0-1-2-3 of the quad.
  std::vector<glm::vec3> corners;
  for (const glm::vec3& p : test::unit_quad_positions()) corners.push_back(glm::vec3(m * glm::vec4(p, 1.0f)));
  size_t start = 4;
  for (size_t i = 0; i < 4; ++i)
    if (glm::length(loop[0] - corners[i]) < 1e-5f) start = i;
  ASSERT_LT(start, 4u);
  for (size_t i = 0; i < 4; ++i) expect_near(loop[i], corners[(start + i) % 4]);
  // Counter-clockwise seen from the side it faces: the loop's area vector points along the normal.
  expect_near(loop_area_vector(loop), 4.0f * world_normal, 1e-4f);
}

TEST(AreaLights, CdfFollowsPowerAcrossMaterials) {
  TempDir dir;
  GltfBuilder b;
  const int dim = b.add_material(emissive_material({0, 1, 0}));        // luminance 0.7152
  const int bright = b.add_material(emissive_material({1, 0, 0}, 4));  // luminance 4 * 0.2126
  const int dark = b.add_material({{"name", "dark"}});
  const std::vector<glm::vec3> tri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};        // area 0.5
  const std::vector<glm::vec3> big = {{0, 0, 1}, {2, 0, 1}, {0, 2, 1}};        // area 2
  b.doc["meshes"] = {{{"primitives", {b.make_primitive(tri, {0, 1, 2}, dim), b.make_primitive(tri, {0, 1, 2}, dark),
                                      b.make_primitive(big, {0, 1, 2}, bright)}}}};
  b.set_scene({b.add_node({{"mesh", 0}})});
  const Scene scene = load_scene(b.write_glb(dir / "cdf.glb"));
  ASSERT_EQ(scene.area_lights.size(), 1u);
  const AreaLight& light = scene.area_lights[0];
  ASSERT_EQ(light.triangle_materials, std::vector<uint32_t>({uint32_t(dim), uint32_t(bright)}));  // dark left out
  const double p0 = 0.5 * 0.7152, p1 = 2.0 * 4 * 0.2126;
  EXPECT_NEAR(light.power, p0 + p1, 1e-5);
  EXPECT_NEAR(light.area, 2.5f, 1e-6f);
  EXPECT_NEAR(light.triangle_cdf[0], p0 / (p0 + p1), 1e-6);
  EXPECT_EQ(light.triangle_cdf[1], 1.0f);
  // Two separate triangles: two outlines, each counter-clockwise about +Z.
  ASSERT_EQ(light.outlines.size(), 2u);
  for (const auto& loop : light.outlines) {
    EXPECT_EQ(loop.size(), 3u);
    EXPECT_GT(loop_area_vector(loop).z, 0.0f);
  }
}

TEST(AreaLights, ClosedEmissiveMeshHasNoOutline) {
  TempDir dir;
  GltfBuilder b;
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  test::unit_cube(positions, indices);  // split at the seams: welding must close it
  b.add_mesh("lamp", positions, indices, b.add_material(emissive_material({1, 1, 1})));
  b.add_mesh("floor", test::unit_quad_positions(), test::unit_quad_indices());
  b.set_scene({b.add_node({{"mesh", 1}}), b.add_node({{"mesh", 0}, {"translation", {0, 0, 3}}})});
  const Scene scene = load_scene(b.write_gltf(dir / "cube.gltf"));
  ASSERT_EQ(scene.area_lights.size(), 1u);
  EXPECT_EQ(scene.area_lights[0].object, 1u);  // only the emissive object
  EXPECT_TRUE(scene.area_lights[0].outlines.empty());
  EXPECT_NEAR(scene.area_lights[0].area, 6.0f, 1e-5f);
  EXPECT_EQ(scene.area_lights[0].triangle_cdf.size(), 12u);
}

TEST(AreaLights, MirroredObjectKeepsCounterClockwiseOutline) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("panel", test::unit_quad_positions(), test::unit_quad_indices(), b.add_material(emissive_material({1, 1, 1})));
  b.set_scene({b.add_node({{"mesh", 0}, {"scale", {-1, 1, 1}}})});
  const Scene scene = load_scene(b.write_gltf(dir / "mirror.gltf"));
  ASSERT_EQ(scene.area_lights.size(), 1u);
  const AreaLight& light = scene.area_lights[0];
  // glTF: a mirrored node keeps its front face where the object-space normal maps, +Z here.
  for (size_t t = 0; t < 2; ++t) {
    const glm::vec3* v = &light.triangle_vertices[3 * t];
    EXPECT_GT(glm::cross(v[1] - v[0], v[2] - v[0]).z, 0.0f);
  }
  ASSERT_EQ(light.outlines.size(), 1u);
  EXPECT_GT(loop_area_vector(light.outlines[0]).z, 0.0f);
}

TEST(AreaLights, NoEmissiveMaterialNoAreaLights) {
  TempDir dir;
  GltfBuilder b;
  b.add_mesh("panel", test::unit_quad_positions(), test::unit_quad_indices());
  b.set_scene({b.add_node({{"mesh", 0}})});
  EXPECT_TRUE(load_scene(b.write_gltf(dir / "none.gltf")).area_lights.empty());
}

// Property: for random planar surfaces (grids with random holes, random winding of cell
// diagonals, vertices split per cell as exporters do), the loops' signed areas add up to the
// surface area, every loop edge is a grid edge, and outlines vanish only for empty surfaces.
TEST(AreaLights, OutlineAreasSumToSurfaceAreaOnRandomGrids) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + int(rng() % 6);
    Mesh mesh;
    int cells = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        if (rng() % 3 == 0) continue;  // a hole
        ++cells;
        const uint32_t v = uint32_t(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {glm::vec3(x, y, 0), glm::vec3(x + 1, y, 0),
                                                     glm::vec3(x + 1, y + 1, 0), glm::vec3(x, y + 1, 0)});
        if (rng() % 2) mesh.triangles.insert(mesh.triangles.end(), {{v, v + 1, v + 2}, {v, v + 2, v + 3}});
        else mesh.triangles.insert(mesh.triangles.end(), {{v, v + 1, v + 3}, {v + 1, v + 2, v + 3}});
      }
    const auto loops = boundary_loops(mesh);
    float signed_area = 0.0f;
    size_t loop_edges = 0;
    for (const auto& loop : loops) {
      signed_area += loop_area_vector(loop).z;
      loop_edges += loop.size();
      for (size_t i = 0; i < loop.size(); ++i)
        ASSERT_NEAR(glm::length(loop[(i + 1) % loop.size()] - loop[i]), 1.0f, 1e-6f);
    }
    EXPECT_NEAR(signed_area, float(cells), 1e-4f) << "trial " << trial;
    EXPECT_EQ(loops.empty(), cells == 0);
    // Border edges of the cell union: each cell contributes 4, shared sides remove 2 each.
    EXPECT_EQ(loop_edges % 2, 0u);
  }
}

}  // namespace
}  // namespace epi

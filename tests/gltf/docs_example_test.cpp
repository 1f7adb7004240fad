// The complete example in docs/scene-format.md must load and mean what the text says.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "gltf_builder.h"
#include "load_scene.h"

namespace epi {
namespace {

// The first ```json block of the document that holds a whole glTF file.
std::string example_json() {
  std::ifstream in(std::string(EPI_SOURCE_DIR) + "/docs/scene-format.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  for (size_t at = doc.find("```json"); at != std::string::npos; at = doc.find("```json", at + 1)) {
    const size_t begin = doc.find('\n', at) + 1, end = doc.find("```", begin);
    const std::string block = doc.substr(begin, end - begin);
    if (block.find("\"asset\"") != std::string::npos) return block;
  }
  return "";
}

TEST(DocsExample, LoadsAsDescribed) {
  const std::string json = example_json();
  ASSERT_FALSE(json.empty()) << "no complete example in docs/scene-format.md";
  test::TempDir dir;
  test::GltfBuilder::write_text(dir / "example.gltf", json);
  const Scene scene = load_scene(dir / "example.gltf");

  ASSERT_EQ(scene.meshes.size(), 2u);
  const Mesh& cube = scene.meshes[0];
  EXPECT_TRUE(cube.subdivided);
  EXPECT_EQ(cube.subdivision.level, 3);
  EXPECT_EQ(cube.subdivision.control_faces, 6u);
  EXPECT_EQ(cube.subdivision.crease_count, 1u);
  EXPECT_EQ(cube.triangles.size(), 768u);
  EXPECT_FLOAT_EQ(cube.sharp_angle_degrees, 70.0f);

  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.objects[0].name, "cube");
  EXPECT_EQ(scene.objects[1].name, "lamp");
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_EQ(scene.cameras[0].name, "cam");
  EXPECT_NEAR(scene.cameras[0].eye.z, 6.0f, 1e-6f);
  ASSERT_EQ(scene.punctual_lights.size(), 1u);
  EXPECT_EQ(scene.punctual_lights[0].type, LightType::directional);
  EXPECT_EQ(scene.punctual_lights[0].name, "sun");
  EXPECT_LT(scene.punctual_lights[0].direction.y, 0.0f);  // the sun shines downwards
  EXPECT_EQ(scene.camera_path.size(), 2u);

  ASSERT_EQ(scene.area_lights.size(), 1u);
  const AreaLight& lamp = scene.area_lights[0];
  EXPECT_EQ(lamp.object, 1u);
  EXPECT_NEAR(lamp.area, 1.0f, 1e-5f);
  ASSERT_EQ(lamp.outlines.size(), 1u);
  EXPECT_EQ(lamp.outlines[0].size(), 4u);
  for (const glm::vec3& p : lamp.outlines[0]) EXPECT_NEAR(p.y, 3.0f, 1e-5f);
  // The panel faces down: its outline is counter-clockwise seen from below.
  glm::vec3 area_vector(0.0f);
  const auto& loop = lamp.outlines[0];
  for (size_t i = 0; i < loop.size(); ++i) area_vector += 0.5f * glm::cross(loop[i], loop[(i + 1) % loop.size()]);
  EXPECT_NEAR(area_vector.y, -1.0f, 1e-5f);
  EXPECT_TRUE(scene.repairs.empty());
}

}  // namespace
}  // namespace epi

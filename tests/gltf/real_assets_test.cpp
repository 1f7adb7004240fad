// Real files: the glTF2 folder of Debian's assimp-testmodels (fetched by the test set-up into
// ${build}/testdata/glTF2; when absent, skipped, or failed if CI is set). Valid assets must load with the expected
// triangle counts; broken ones must give a clean one-line SceneLoadError naming the problem.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "load_scene.h"

namespace epi {
namespace {

namespace fs = std::filesystem;

fs::path data_root() { return fs::path(EPI_BINARY_DIR) / "testdata" / "glTF2"; }

// Without the files: a failure in CI (the environment variable CI is set), a skip elsewhere.
#define REQUIRE_DATA()                                                                                   \
  if (!fs::is_directory(data_root())) {                                                                  \
    if (std::getenv("CI") != nullptr)                                                                    \
      FAIL() << "no " << data_root() << ": the gltf_fetch_testdata set-up could not fetch it, and CI is set"; \
    GTEST_SKIP() << "no " << data_root() << " (the gltf_fetch_testdata set-up could not fetch it)";      \
  }

// Triangles over all objects (instanced), as loaded; degenerate ones already dropped.
const std::map<std::string, size_t> kValid = {
    {"2CylinderEngine-glTF-Binary/2CylinderEngine.glb", 110336},
    {"BoxBadNormals-glTF-Binary/BoxBadNormals.glb", 12},
    {"BoxTexcoords-glTF/boxTexcoords.gltf", 12},
    {"BoxTextured-glTF/BoxTextured.gltf", 12},
    {"BoxTextured-glTF-Binary/BoxTextured.glb", 12},
    {"BoxTextured-glTF-Embedded/BoxTextured.gltf", 12},
    {"BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf", 12},
    {"ClearCoat-glTF/ClearCoatTest.gltf", 37116},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf", 2},  // triangles
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_05.gltf", 2},  // strip
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_06.gltf", 2},  // fan
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf", 2},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf", 2},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf", 2},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_14.gltf", 2},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_15.gltf", 2},
    {"glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", 12},  // morph targets ignored
    {"issue_3269/texcoord_crash.gltf", 10},
    {"simple_skin/simple_skin.gltf", 8},  // skin ignored
    {"textureTransform/TextureTransformTest.gltf", 24},
};

// Broken (or unsupported) files and the problem their message must name.
const std::map<std::string, std::string> kBroken = {
    {"BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", "required extension KHR_technique_webgl is not supported"},
    {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "is not finite"},
    {"IncorrectVertexArrays/Cube.gltf", "past the end of buffer 0"},
    {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "vertex index 65535 at position 0 out of range"},
    {"IndexOutOfRange/IndexOutOfRange.gltf", "vertex index 255 at position 0 out of range"},
    {"MissingBin/BoxTextured.gltf", "BoxTextured0.bin"},
    {"RecursiveNodes/RecursiveNodes.gltf", "node cycle"},
    {"SchemaFailures/sceneWrongType.gltf", "scene: expected a non-negative integer"},
    {"TestNoRootNode/NoScene.gltf", "no scenes"},
    {"TestNoRootNode/SceneWithoutNodes.gltf", "empty scene"},
    {"cameras/Cameras.gltf", "orthographic cameras are not supported"},
    {"draco/2CylinderEngine.gltf", "required extension KHR_draco_mesh_compression is not supported"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf", "primitive mode 0"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_01.gltf", "primitive mode 1"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_02.gltf", "primitive mode 2"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_03.gltf", "primitive mode 3"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_07.gltf", "primitive mode 0"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_08.gltf", "primitive mode 1"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_09.gltf", "primitive mode 2"},
    {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_10.gltf", "primitive mode 3"},
    {"wrongTypes/badArray.gltf", "meshes[0].primitives: expected an array"},
    {"wrongTypes/badExtension.gltf", "extensions.KHR_texture_transform: expected an object"},
    {"wrongTypes/badNumber.gltf", "materials[0].normalTexture.scale: expected a number"},
    {"wrongTypes/badObject.gltf", "materials[0].pbrMetallicRoughness: expected an object"},
    {"wrongTypes/badString.gltf", "scenes[0].name: expected a string"},
    {"wrongTypes/badUint.gltf", "baseColorTexture.index: expected a non-negative integer"},
};

void expect_consistent(const Scene& scene) {
  for (const Object& o : scene.objects) ASSERT_LT(o.mesh, scene.meshes.size());
  for (const Mesh& m : scene.meshes) {
    for (const glm::uvec3& t : m.triangles) ASSERT_LT(std::max({t.x, t.y, t.z}), m.positions.size());
    ASSERT_TRUE(m.normals.empty() || m.normals.size() == m.positions.size());
    uint32_t next = 0;
    for (const MaterialRange& r : m.materials) {
      ASSERT_EQ(r.first_triangle, next);
      ASSERT_LT(r.material, scene.materials.size());
      next += r.triangle_count;
    }
    ASSERT_EQ(next, m.triangles.size());
  }
  ASSERT_FALSE(scene.cameras.empty());
}

TEST(RealAssets, TwoCylinderEngineHas75730Triangles) {
  REQUIRE_DATA();
  const Scene scene = load_scene(data_root() / "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
  size_t file_triangles = 0, dropped = 0;
  for (const Mesh& m : scene.meshes) {
    file_triangles += m.triangles.size() + m.degenerate_triangles_dropped;
    dropped += m.degenerate_triangles_dropped;
  }
  EXPECT_EQ(file_triangles, 75730u);  // the triangles of its 29 meshes, as in the file
  EXPECT_EQ(scene.meshes.size(), 29u);
  EXPECT_EQ(dropped, 10419u);  // exactly zero-area triangles of the CAD export, reported as repairs
  EXPECT_EQ(scene.repairs.size(), 25u);
  EXPECT_EQ(scene.triangle_count(), 110336u);  // instanced over its objects
  EXPECT_EQ(scene.cameras.size(), 1u);
  expect_consistent(scene);
}

TEST(RealAssets, ValidAssetsLoad) {
  REQUIRE_DATA();
  for (const auto& [name, triangles] : kValid) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(fs::exists(data_root() / name));
    try {
      const Scene scene = load_scene(data_root() / name);
      EXPECT_EQ(scene.triangle_count(), triangles);
      expect_consistent(scene);
    } catch (const SceneLoadError& e) {
      ADD_FAILURE() << e.what();
    }
  }
}

TEST(RealAssets, BrokenFilesGiveCleanErrors) {
  REQUIRE_DATA();
  for (const auto& [name, problem] : kBroken) {
    SCOPED_TRACE(name);
    const fs::path file = data_root() / name;
    ASSERT_TRUE(fs::exists(file));
    try {
      load_scene(file);
      ADD_FAILURE() << "loaded";
    } catch (const SceneLoadError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(problem), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

// Every glTF file in the folder is listed above: a new one must be looked at.
TEST(RealAssets, EveryFileIsClassified) {
  REQUIRE_DATA();
  for (const auto& entry : fs::recursive_directory_iterator(data_root())) {
    const fs::path& path = entry.path();
    if (path.extension() != ".gltf" && path.extension() != ".glb") continue;
    const std::string name = fs::relative(path, data_root()).generic_string();
    EXPECT_TRUE(kValid.count(name) || kBroken.count(name)) << name;
  }
}

}  // namespace
}  // namespace epi

// Broken files: each must give a SceneLoadError "<file>: <problem>" on one line that names the problem.
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "gltf_builder.h"
#include "load_scene.h"

namespace epi {
namespace {

using test::GltfBuilder;
using test::json;
using test::TempDir;

// The loader's error for `file`, or "" if it loaded.
std::string load_error(const std::filesystem::path& file, const LoadOptions& options = {}) {
  try {
    load_scene(file, options);
  } catch (const SceneLoadError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::filesystem::path& file, const std::string& problem, const LoadOptions& options = {}) {
  const std::string what = load_error(file, options);
  ASSERT_FALSE(what.empty()) << file << " loaded, expected: " << problem;
  EXPECT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
  EXPECT_NE(what.find(problem), std::string::npos) << "message: " << what << "\nexpected to contain: " << problem;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

// A valid scene to break: a quad mesh with normals and a material, under a parent node.
GltfBuilder valid_scene() {
  GltfBuilder b;
  b.add_material({{"name", "grey"}});
  b.add_mesh("quad", test::unit_quad_positions(), test::unit_quad_indices(), 0,
             {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  const int child = b.add_node({{"name", "child"}, {"mesh", 0}});
  b.set_scene({b.add_node({{"name", "parent"}, {"children", {child}}})});
  return b;
}

struct Case {
  const char* name;
  std::function<void(GltfBuilder&)> mutate;
  const char* problem;
};

// Each case breaks the valid scene in one way; all are checked as .gltf and as .glb.
const std::vector<Case> kCases = {
    {"accessor index", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99; },
     "accessor index 99 out of range"},
    {"indices accessor index", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["indices"] = 42; },
     "accessor"},
    {"buffer view index", [](GltfBuilder& b) { b.doc["accessors"][0]["bufferView"] = 17; }, "buffer view"},
    {"buffer index", [](GltfBuilder& b) { b.doc["bufferViews"][0]["buffer"] = 5; }, "buffer"},
    {"vertex index", [](GltfBuilder& b) {
       const uint32_t bad[6] = {0, 1, 2, 0, 2, 7};
       const int view = b.add_view(bad, sizeof bad);
       b.doc["meshes"][0]["primitives"][0]["indices"] = b.add_accessor(view, 5125, 6, "SCALAR");
     }, "vertex index 7 at position 5 out of range (4 vertices)"},
    {"material index", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["material"] = 3; },
     "material index 3 out of range"},
    {"mesh index", [](GltfBuilder& b) { b.doc["nodes"][0]["mesh"] = 4; }, "mesh index 4 out of range"},
    {"camera index", [](GltfBuilder& b) { b.doc["nodes"][0]["camera"] = 0; }, "camera index 0 out of range"},
    {"light index", [](GltfBuilder& b) {
       b.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 2;
     }, "light index 2 out of range"},
    {"child index", [](GltfBuilder& b) { b.doc["nodes"][1]["children"] = {0, 9}; }, "node index 9 out of range"},
    {"scene node index", [](GltfBuilder& b) { b.doc["scenes"][0]["nodes"] = {6}; }, "node index 6 out of range"},
    {"scene index", [](GltfBuilder& b) { b.doc["scene"] = 3; }, "scene index 3 out of range"},
    {"accessor past view", [](GltfBuilder& b) { b.doc["accessors"][0]["count"] = 5; }, "past the end of buffer view"},
    {"accessor offset past view", [](GltfBuilder& b) { b.doc["accessors"][0]["byteOffset"] = 4; },
     "past the end of buffer view"},
    {"view past buffer", [](GltfBuilder& b) { b.doc["bufferViews"][1]["byteLength"] = 4096; },
     "past the end of buffer"},
    {"stride smaller than element", [](GltfBuilder& b) { b.doc["bufferViews"][0]["byteStride"] = 8; },
     "byteStride 8"},
    {"node cycle", [](GltfBuilder& b) { b.doc["nodes"][0]["children"] = {1}; }, "cycle"},
    {"two parents", [](GltfBuilder& b) {
       b.add_node({{"children", {0}}});
       b.doc["scenes"][0]["nodes"].push_back(2);
     }, "node 0 has two parents"},
    {"own child", [](GltfBuilder& b) { b.doc["nodes"][0]["children"] = {0}; }, "node 0 is its own child"},
    {"root is a child", [](GltfBuilder& b) { b.doc["scenes"][0]["nodes"].push_back(0); }, "scene root node 0"},
    {"primitives not an array", [](GltfBuilder& b) {
       b.doc["meshes"][0]["primitives"] = b.doc["meshes"][0]["primitives"][0];
     }, "meshes[0].primitives: expected an array"},
    {"name not a string", [](GltfBuilder& b) { b.doc["scenes"][0]["name"] = 42; },
     "scenes[0].name: expected a string"},
    {"scene not an integer", [](GltfBuilder& b) { b.doc["scene"] = "hello"; }, "scene: expected a non-negative integer"},
    {"negative index", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["material"] = -1; },
     "meshes[0].primitives[0].material: expected a non-negative integer, got an integer (-1)"},
    {"texture index", [](GltfBuilder& b) {
       b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = -1;
     }, "baseColorTexture.index"},
    {"factor not a number", [](GltfBuilder& b) { b.doc["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = "1"; },
     "metallicFactor: expected a number"},
    {"matrix length", [](GltfBuilder& b) { b.doc["nodes"][0]["matrix"] = {1, 0, 0, 1}; }, "expected 16 numbers"},
    {"extension not an object", [](GltfBuilder& b) { b.doc["nodes"][0]["extensions"]["EXT_whatever"] = "x"; },
     "nodes[0].extensions.EXT_whatever: expected an object"},
    {"draco required", [](GltfBuilder& b) {
       b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
       b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
     }, "required extension KHR_draco_mesh_compression is not supported"},
    {"unknown required extension", [](GltfBuilder& b) { b.doc["extensionsRequired"] = {"EXT_future"}; },
     "required extension EXT_future"},
    {"lines", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["mode"] = 1; }, "primitive mode 1"},
    {"points", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["mode"] = 0; }, "primitive mode 0"},
    {"invalid mode", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["mode"] = 9; }, "primitive mode 9"},
    {"position not vec3", [](GltfBuilder& b) {
       b.doc["accessors"][b.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()]["type"] = "VEC2";
     }, "wrong element type"},
    {"position not float", [](GltfBuilder& b) {
       auto& a = b.doc["accessors"][b.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
       a["componentType"] = 5125;
     }, "expected VEC3 of FLOAT"},
    {"no position", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["attributes"].erase("POSITION"); },
     "no POSITION"},
    {"float indices", [](GltfBuilder& b) {
       b.doc["accessors"][b.doc["meshes"][0]["primitives"][0]["indices"].get<int>()]["componentType"] = 5126;
     }, "indices must be unsigned"},
    {"index count", [](GltfBuilder& b) {
       b.doc["accessors"][b.doc["meshes"][0]["primitives"][0]["indices"].get<int>()]["count"] = 5;
     }, "index count 5 is not a multiple of 3"},
    {"normal count", [](GltfBuilder& b) {
       b.doc["accessors"][b.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].get<int>()]["count"] = 3;
     }, "NORMAL has 3 elements, POSITION has 4"},
    {"sparse", [](GltfBuilder& b) {
       b.doc["accessors"][0]["sparse"] = {{"count", 1},
                                          {"indices", {{"bufferView", 0}, {"componentType", 5125}}},
                                          {"values", {{"bufferView", 0}}}};
     }, "sparse"},
    {"accessor without buffer view", [](GltfBuilder& b) {
       b.doc["accessors"][0].erase("bufferView");
       b.doc["accessors"][0]["count"] = 2000000000;
     }, "accessor 0: has no buffer view"},
    {"no scenes", [](GltfBuilder& b) {
       b.doc.erase("scenes");
       b.doc.erase("scene");
     }, "no scenes"},
    {"scene without nodes", [](GltfBuilder& b) { b.doc["scenes"][0].erase("nodes"); }, "empty scene"},
    {"mesh without primitives", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"] = json::array(); },
     "empty scene"},
    {"orthographic", [](GltfBuilder& b) {
       b.doc["cameras"] = {{{"type", "orthographic"},
                            {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}}};
       b.doc["nodes"][0]["camera"] = 0;
     }, "orthographic cameras are not supported"},
    {"bad yfov", [](GltfBuilder& b) {
       b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 4.0}, {"znear", 0.1}}}}};
       b.doc["nodes"][0]["camera"] = 0;
     }, "camera 0: yfov"},
    {"matrix and trs", [](GltfBuilder& b) {
       b.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
       b.doc["nodes"][0]["scale"] = {1, 1, 1};
     }, "both a matrix and"},
    {"projective matrix", [](GltfBuilder& b) {
       b.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.5, 0, 0, 0, 1};
     }, "node 0: matrix is not affine"},
    {"child twice", [](GltfBuilder& b) { b.doc["nodes"][1]["children"] = {0, 0}; }, "node 1 lists child 0 twice"},
    {"zero quaternion", [](GltfBuilder& b) { b.doc["nodes"][0]["rotation"] = {0, 0, 0, 0}; }, "zero length"},
    {"transform overflow", [](GltfBuilder& b) {
       b.doc["nodes"][1]["scale"] = {1e30, 1e30, 1e30};
       b.doc["nodes"][0]["scale"] = {1e30, 1e30, 1e30};
     }, "not finite"},
    {"factor out of range", [](GltfBuilder& b) { b.doc["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = 1.5; },
     "material 'grey': roughnessFactor"},
    {"negative emissive strength", [](GltfBuilder& b) {
       b.doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = -2.0;
     }, "emissiveStrength"},
    {"bad light type", [](GltfBuilder& b) {
       b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "area"}}};
       b.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
     }, "unknown light type 'area'"},
    {"spot cone", [](GltfBuilder& b) {
       b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
           {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.8}, {"outerConeAngle", 0.5}}}}};
       b.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
     }, "spot cone angles"},
    {"spot without cone", [](GltfBuilder& b) {
       b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "spot"}}};
       b.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
     }, "light 0: a spot light needs a 'spot' object"},
    {"version", [](GltfBuilder& b) { b.doc["asset"]["version"] = "1.0"; }, "glTF version 1.0 is not supported"},
    {"camera path type", [](GltfBuilder& b) { b.doc["extras"]["epi"]["camera_path"] = {{{"eye", {0, 0, 1}}}}; },
     "extras.epi.camera_path[0].target: missing"},
    {"camera path value", [](GltfBuilder& b) {
       b.doc["extras"]["epi"]["camera_path"] = {{{"eye", {0, 0, 1}}, {"target", {0, 0}}}};
     }, "extras.epi.camera_path[0].target: expected an array of 3 numbers"},
};

TEST(Malformed, EveryCaseGivesACleanErrorAsGltfAndGlb) {
  TempDir dir;
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    GltfBuilder b = valid_scene();
    c.mutate(b);
    expect_error(b.write_gltf(dir / "case.gltf"), c.problem);
    expect_error(b.write_glb(dir / "case.glb"), c.problem);
  }
}

TEST(Malformed, TheValidSceneLoads) {
  TempDir dir;
  EXPECT_EQ(load_error(valid_scene().write_gltf(dir / "ok.gltf")), "");
  EXPECT_EQ(load_error(valid_scene().write_glb(dir / "ok.glb")), "");
}

TEST(Malformed, FileLevelProblems) {
  TempDir dir;
  expect_error(dir / "missing.gltf", "cannot open file");
  expect_error(dir.path(), "cannot open file");
  GltfBuilder::write_text(dir / "empty.gltf", "");
  expect_error(dir / "empty.gltf", "file is empty");
  GltfBuilder::write_text(dir / "text.gltf", "this is not json");
  expect_error(dir / "text.gltf", "invalid JSON");
  GltfBuilder::write_text(dir / "array.gltf", "[1, 2]");
  expect_error(dir / "array.gltf", "must be an object");
  GltfBuilder::write_text(dir / "noasset.gltf", "{}");
  expect_error(dir / "noasset.gltf", "asset.version is missing");
}

TEST(Malformed, BufferProblems) {
  TempDir dir;
  GltfBuilder b = valid_scene();
  const auto file = b.write_gltf(dir / "buf.gltf");
  // Short .bin file.
  auto bin = b.bin;
  bin.resize(bin.size() / 2);
  GltfBuilder::write_bytes(dir / "buf.bin", bin);
  expect_error(file, "buffers[0]: byteLength 120 but 'buf.bin' holds 60 bytes");
  // Missing .bin file.
  std::filesystem::remove(dir / "buf.bin");
  expect_error(file, "buf.bin");
  // A buffer without uri in a .gltf.
  json doc = json::parse(std::ifstream(file));
  doc["buffers"][0].erase("uri");
  GltfBuilder::write_text(dir / "nouri.gltf", doc.dump());
  expect_error(dir / "nouri.gltf", "uri");
  // A data: URI holding fewer bytes than byteLength.
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + GltfBuilder::base64({1, 2, 3, 4});
  GltfBuilder::write_text(dir / "shortdata.gltf", doc.dump());
  expect_error(dir / "shortdata.gltf", "buffers[0]: byteLength 120 but its data: URI holds 4 bytes");
  // A long bad data: URI is not quoted whole.
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + std::string(100000, 'A');
  GltfBuilder::write_text(dir / "longdata.gltf", doc.dump());
  EXPECT_NE(load_error(dir / "longdata.gltf"), "");
  EXPECT_LT(load_error(dir / "longdata.gltf").size(), 600u);
  // The buffer is not found through the working directory either.
  const auto cwd = std::filesystem::current_path();
  std::filesystem::create_directories(dir / "sub");
  b.write_gltf(dir / "sub" / "buf.gltf");
  std::filesystem::rename(dir / "sub" / "buf.bin", dir / "buf.bin");
  std::filesystem::current_path(dir.path());
  const std::string what = load_error(dir / "sub" / "buf.gltf");
  std::filesystem::current_path(cwd);
  EXPECT_NE(what, "");
}

TEST(Malformed, NonFiniteVertexData) {
  TempDir dir;
  for (const char* attribute : {"POSITION", "NORMAL"}) {
    for (float bad : {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
      GltfBuilder b = valid_scene();
      const int accessor = b.doc["meshes"][0]["primitives"][0]["attributes"][attribute].get<int>();
      const int view = b.doc["accessors"][accessor]["bufferView"].get<int>();
      const size_t offset = b.doc["bufferViews"][view]["byteOffset"].get<size_t>();
      std::memcpy(&b.bin[offset + 16], &bad, 4);  // second vertex, y
      expect_error(b.write_glb(dir / "nf.glb"), "accessor " + std::to_string(accessor) + ": element 1 is not finite");
    }
  }
}

// Numbers too large for the float scene model (1e300), and numbers too large for JSON (1e400).
TEST(Malformed, HugeNumbers) {
  TempDir dir;
  const std::vector<std::pair<std::function<void(GltfBuilder&)>, std::string>> cases = {
      {[](GltfBuilder& b) { b.doc["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = 0.123456; }, "metallicFactor"},
      {[](GltfBuilder& b) {
         b.doc["materials"][0]["emissiveFactor"] = {1, 0, 0};
         b.doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 0.123456;
       }, "emission is not finite"},
      {[](GltfBuilder& b) { b.doc["nodes"][0]["translation"] = {0.123456, 0, 0}; }, "world transform is not finite"},
      {[](GltfBuilder& b) {
         b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.123456}}}}};
         b.doc["nodes"][0]["camera"] = 0;
       }, "znear must be finite"},
      {[](GltfBuilder& b) {
         b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 0.123456}}};
         b.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       }, "color * intensity is not finite"},
      {[](GltfBuilder& b) {
         b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"range", 0.123456}}};
         b.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       }, "range must be finite"},
      {[](GltfBuilder& b) { b.doc["meshes"][0]["extras"]["epi"]["sharp_angle"] = 0.123456; }, "sharp_angle"},
      {[](GltfBuilder& b) { b.doc["extras"]["epi"]["camera_path"] = {{{"eye", {0.123456, 0, 1}}, {"target", {0, 0, 0}}}}; },
       "camera_path[0].eye: not finite"},
  };
  for (const char* huge : {"1e300", "1e400"}) {
    for (const auto& [mutate, problem] : cases) {
      GltfBuilder b = valid_scene();
      mutate(b);
      b.write_gltf(dir / "o.gltf");
      std::ifstream in(dir / "o.gltf");
      std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      const size_t at = text.find("0.123456");
      ASSERT_NE(at, std::string::npos);
      text.replace(at, 8, huge);
      GltfBuilder::write_text(dir / "o.gltf", text);
      expect_error(dir / "o.gltf", std::string(huge) == "1e400" ? "number overflow" : problem);
    }
  }
}

// Deep nesting is refused before anything recursive (tinygltf's extras parser) sees it.
TEST(Malformed, DeepJsonNesting) {
  TempDir dir;
  for (int depth : {65, 100000}) {
    GltfBuilder b = valid_scene();
    b.doc["extras"] = "DEEP";
    std::string text = b.doc.dump();  // no buffers: written as text by hand below
    text.replace(text.find("\"DEEP\""), 6, std::string(size_t(depth), '[') + std::string(size_t(depth), ']'));
    GltfBuilder::write_text(dir / "deep.gltf", text);
    expect_error(dir / "deep.gltf", "nested deeper than 64 levels");
  }
}

TEST(Malformed, GlbContainerProblems) {
  TempDir dir;
  GltfBuilder b = valid_scene();
  const auto file = b.write_glb(dir / "c.glb");
  std::ifstream in(file, std::ios::binary);
  const std::vector<unsigned char> glb((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto write_variant = [&](const std::vector<unsigned char>& bytes) {
    GltfBuilder::write_bytes(dir / "v.glb", bytes);
    return dir / "v.glb";
  };
  auto truncated = glb;
  truncated.resize(glb.size() - 10);
  expect_error(write_variant(truncated), "GLB header says");
  auto version = glb;
  version[4] = 1;
  expect_error(write_variant(version), "GLB version 1");
  auto json_length = glb;
  json_length[14] = 0x7f;  // JSON chunk length far past the end
  expect_error(write_variant(json_length), "JSON chunk runs past the end");
  expect_error(write_variant({'g', 'l', 'T', 'F', 2, 0, 0}), "truncated GLB header");
}

TEST(Malformed, SubdivisionRequests) {
  TempDir dir;
  auto with_subdivision = [](json request) {
    GltfBuilder b = valid_scene();
    b.doc["meshes"][0]["extras"]["epi"]["subdivision"] = request;
    return b;
  };
  expect_error(with_subdivision({{"scheme", "butterfly"}}).write_gltf(dir / "s.gltf"), "unknown scheme 'butterfly'");
  expect_error(with_subdivision({{"level", "2"}}).write_gltf(dir / "s.gltf"), "subdivision.level: expected an integer");
  expect_error(with_subdivision({{"level", 9}}).write_gltf(dir / "s.gltf"), "subdivision.level");
  expect_error(with_subdivision({{"quads", 1}}).write_gltf(dir / "s.gltf"), "quads: expected a boolean");
  expect_error(with_subdivision({{"scheme", "loop"}, {"quads", true}}).write_gltf(dir / "s.gltf"), "needs triangles");
  expect_error(with_subdivision({{"creases", {{0, 1}}}}).write_gltf(dir / "s.gltf"), "creases[0]");
  expect_error(with_subdivision({{"creases", {{0, 9, 2.0}}}}).write_gltf(dir / "s.gltf"), "crease vertex 9 out of range");
  expect_error(with_subdivision({{"creases", {{0, 1, -1.0}}}}).write_gltf(dir / "s.gltf"), "sharpness");
  // A crease on the quad's diagonal, which is no edge of the cage: subdivide() refuses it.
  expect_error(with_subdivision({{"quads", true}, {"creases", {{0, 2, 1.0}}}}).write_gltf(dir / "s.gltf"),
               "mesh 'quad' primitive 0: subdivision failed: ");
  expect_error(with_subdivision("yes").write_gltf(dir / "s.gltf"), "extras.epi.subdivision: expected an object");
  // A request that would exhaust memory: 1000 quads at level 8.
  GltfBuilder big = valid_scene();
  std::vector<glm::vec3> grid;
  std::vector<uint32_t> grid_indices;
  for (uint32_t i = 0; i <= 1000; ++i) grid.insert(grid.end(), {glm::vec3(float(i), 0, 0), glm::vec3(float(i), 1, 0)});
  for (uint32_t i = 0; i < 1000; ++i) grid_indices.insert(grid_indices.end(), {2 * i, 2 * i + 2, 2 * i + 3, 2 * i, 2 * i + 3, 2 * i + 1});
  big.doc["meshes"][0]["primitives"][0] = big.make_primitive(grid, grid_indices);
  big.doc["meshes"][0]["extras"]["epi"]["subdivision"] = {{"level", 8}, {"quads", true}};
  expect_error(big.write_gltf(dir / "big.gltf"), "would make up to 131072000 triangles (limit 67108864 for the scene)");
  // Quads whose triangle pairs do not share the (a, c) diagonal.
  GltfBuilder b = with_subdivision({{"quads", true}});
  const uint32_t not_pairs[6] = {0, 1, 2, 2, 3, 0};
  const int view = b.add_view(not_pairs, sizeof not_pairs);
  b.doc["meshes"][0]["primitives"][0]["indices"] = b.add_accessor(view, 5125, 6, "SCALAR");
  expect_error(b.write_gltf(dir / "s.gltf"), "triangles 0 and 1 do not form a quad");
  // The override is range-checked too.
  LoadOptions options;
  options.subdiv_level_override = 12;
  expect_error(valid_scene().write_gltf(dir / "o.gltf"), "subdivision level override 12", options);
  GltfBuilder sharp = valid_scene();
  sharp.doc["meshes"][0]["extras"]["epi"]["sharp_angle"] = 200;
  expect_error(sharp.write_gltf(dir / "a.gltf"), "sharp_angle");
}

// Property test: random corruption of valid files never crashes or hangs, and always ends
// in either a scene or a SceneLoadError.
TEST(Malformed, RandomCorruptionFailsCleanly) {
  TempDir dir;
  GltfBuilder b = valid_scene();
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}}};
  b.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
  const auto glb_file = b.write_glb(dir / "base.glb");
  const auto gltf_file = b.write_embedded(dir / "base.gltf");
  std::mt19937 rng(1234);
  int loaded = 0, rejected = 0;
  for (const auto& base : {glb_file, gltf_file}) {
    std::ifstream in(base, std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (int iteration = 0; iteration < 400; ++iteration) {
      std::vector<unsigned char> corrupt = bytes;
      const int kind = iteration % 3;
      if (kind == 0) {  // flip a few bytes
        for (int k = 0; k < 1 + iteration % 4; ++k) corrupt[rng() % corrupt.size()] = (unsigned char)(rng());
      } else if (kind == 1) {  // truncate
        corrupt.resize(rng() % corrupt.size());
      } else {  // replace a digit by another (keeps the JSON parseable more often)
        for (int tries = 0; tries < 100; ++tries) {
          const size_t at = rng() % corrupt.size();
          if (corrupt[at] >= '0' && corrupt[at] <= '9') {
            corrupt[at] = (unsigned char)('0' + rng() % 10);
            break;
          }
        }
      }
      const auto file = dir / ("corrupt" + base.extension().string());
      GltfBuilder::write_bytes(file, corrupt);
      try {
        const Scene scene = load_scene(file);
        // Loaded: it must be self-consistent.
        for (const Object& o : scene.objects) ASSERT_LT(o.mesh, scene.meshes.size());
        for (const Mesh& m : scene.meshes) {
          for (const glm::uvec3& t : m.triangles) ASSERT_LT(std::max({t.x, t.y, t.z}), m.positions.size());
          for (const MaterialRange& r : m.materials) ASSERT_LT(r.material, scene.materials.size());
        }
        ++loaded;
      } catch (const SceneLoadError& e) {
        const std::string what = e.what();
        ASSERT_EQ(what.find('\n'), std::string::npos) << what;
        ASSERT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
        ++rejected;
      }
    }
  }
  EXPECT_GT(rejected, 100);
  EXPECT_GT(loaded, 10);
}

// Property test at the JSON level: replace one number of a valid document (an index, a count,
// an offset, a factor) by an awkward value; the result loads consistently or fails cleanly.
TEST(Malformed, RandomNumberReplacementFailsCleanly) {
  TempDir dir;
  GltfBuilder base = valid_scene();
  base.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
  base.doc["nodes"][1]["camera"] = 0;
  base.doc["nodes"][1]["translation"] = {0, 0, 4};
  base.doc["materials"][0]["emissiveFactor"] = {1, 1, 1};
  base.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.6}}}}};
  base.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
  EXPECT_EQ(load_error(base.write_gltf(dir / "base.gltf")), "");
  // Paths to every number in the document.
  std::vector<json::json_pointer> numbers;
  const json flat = base.doc.flatten();
  for (const auto& [pointer, value] : flat.items())
    if (value.is_number()) numbers.emplace_back(pointer);
  const json awkward = {0, 1, 2, 3, 4, 7, 12, 13, 255, 65535, 4294967295u, 2147483647, -1, 0.5, 1e30, -1e30, 1e-30, 4.5};
  std::mt19937 rng(99);
  int loaded = 0, rejected = 0;
  for (int iteration = 0; iteration < 600; ++iteration) {
    GltfBuilder b = base;
    for (int k = 0; k < 1 + iteration % 2; ++k)
      b.doc[numbers[rng() % numbers.size()]] = awkward[rng() % awkward.size()];
    const auto file = iteration % 2 ? b.write_glb(dir / "n.glb") : b.write_gltf(dir / "n.gltf");
    try {
      const Scene scene = load_scene(file);
      for (const Object& o : scene.objects) ASSERT_LT(o.mesh, scene.meshes.size());
      for (const Mesh& m : scene.meshes)
        for (const glm::uvec3& t : m.triangles) ASSERT_LT(std::max({t.x, t.y, t.z}), m.positions.size());
      for (const AreaLight& l : scene.area_lights) ASSERT_EQ(l.triangle_vertices.size(), 3 * l.triangle_cdf.size());
      ++loaded;
    } catch (const SceneLoadError& e) {
      const std::string what = e.what();
      ASSERT_EQ(what.find('\n'), std::string::npos) << what;
      ASSERT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
      ++rejected;
    }
  }
  EXPECT_GT(loaded, 50);
  EXPECT_GT(rejected, 200);
}

// Property test: remove one member anywhere in a valid document (a required index, a type, a
// whole section); the result loads consistently or fails cleanly.
TEST(Malformed, RandomMemberRemovalFailsCleanly) {
  TempDir dir;
  GltfBuilder base = valid_scene();
  base.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.6}}}}};
  base.doc["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
  base.doc["meshes"][0]["extras"]["epi"]["subdivision"] = {{"level", 1}, {"quads", true}, {"creases", {{0, 1, 2.0}}}};
  base.doc["extras"]["epi"]["camera_path"] = {{{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}}};
  std::vector<json::json_pointer> members;  // every object member, at any depth
  std::vector<const json*> stack{&base.doc};
  std::vector<json::json_pointer> paths{json::json_pointer()};
  while (!stack.empty()) {
    const json* value = stack.back();
    const json::json_pointer path = paths.back();
    stack.pop_back();
    paths.pop_back();
    if (value->is_object())
      for (const auto& [key, child] : value->items()) {
        members.push_back(path / key);
        stack.push_back(&child);
        paths.push_back(path / key);
      }
    else if (value->is_array())
      for (size_t i = 0; i < value->size(); ++i) {
        stack.push_back(&(*value)[i]);
        paths.push_back(path / i);
      }
  }
  int loaded = 0, rejected = 0;
  for (size_t i = 0; i < members.size(); ++i) {
    GltfBuilder b = base;
    b.doc[members[i].parent_pointer()].erase(members[i].back());
    const auto file = i % 2 ? b.write_glb(dir / "m.glb") : b.write_gltf(dir / "m.gltf");
    try {
      const Scene scene = load_scene(file);
      for (const Object& o : scene.objects) ASSERT_LT(o.mesh, scene.meshes.size());
      ++loaded;
    } catch (const SceneLoadError& e) {
      const std::string what = e.what();
      ASSERT_EQ(what.find('\n'), std::string::npos) << what;
      ASSERT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
      ++rejected;
    }
  }
  EXPECT_GT(loaded, 10);
  EXPECT_GT(rejected, 10);
}

// ---------------------------------------------------------------------------------------------
// Issue 14: messages in epi's words, naming what is wrong (never tinygltf's or JSON's text).

std::vector<unsigned char> read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void put_u32(std::vector<unsigned char>& bytes, size_t offset, uint32_t v) { std::memcpy(bytes.data() + offset, &v, 4); }

TEST(Malformed, BufferAndLightProblemsAreNamedInEpisWords) {
  TempDir dir;
  {
    GltfBuilder b = valid_scene();
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"intensity", 2}}};
    expect_error(b.write_gltf(dir / "light.gltf"), "light 0: 'type' is missing");
  }
  {  // an external buffer that is not there: not tinygltf's "File not found : "
    const auto file = valid_scene().write_gltf(dir / "gone.gltf");
    std::filesystem::remove(dir / "gone.bin");
    expect_error(file, "buffers[0]: buffer file 'gone.bin' not found");
  }
  {  // a data: URI shorter than byteLength: the counts, not 240 characters of base64
    GltfBuilder b = valid_scene();
    const auto file = b.write_embedded(dir / "short.gltf");
    json doc = json::parse(std::ifstream(file));
    doc["buffers"][0]["byteLength"] = b.bin.size() + 100;
    GltfBuilder::write_text(file, doc.dump());
    const std::string what = load_error(file);
    EXPECT_NE(what.find("buffers[0]: byteLength " + std::to_string(b.bin.size() + 100) + " but its data: URI holds " +
                        std::to_string(b.bin.size()) + " bytes"),
              std::string::npos)
        << what;
    EXPECT_LT(what.size(), file.string().size() + 120) << what;
  }
}

TEST(Malformed, GlbChunkProblemsAreBlamedOnTheRightChunk) {
  TempDir dir;
  const auto good = valid_scene().write_glb(dir / "good.glb");
  const std::vector<unsigned char> bytes = read_bytes(good);
  const uint32_t json_length = [&] { uint32_t v; std::memcpy(&v, bytes.data() + 12, 4); return v; }();
  const size_t bin_header = 20 + json_length;
  {  // the BIN chunk's type changed
    std::vector<unsigned char> b = bytes;
    put_u32(b, bin_header + 4, 0x12345678u);
    GltfBuilder::write_bytes(dir / "type.glb", b);
    expect_error(dir / "type.glb", "GLB: the chunk after the JSON chunk has type 0x12345678, not BIN");
  }
  {  // a BIN chunk shorter than the buffer's byteLength (the file's lengths stay consistent)
    std::vector<unsigned char> b = bytes;
    const uint32_t bin_length = uint32_t(b.size() - bin_header - 8);
    put_u32(b, bin_header, 4);
    b.resize(bin_header + 8 + 4);
    put_u32(b, 8, uint32_t(b.size()));
    GltfBuilder::write_bytes(dir / "short.glb", b);
    expect_error(dir / "short.glb", "buffers[0]: byteLength " + std::to_string(bin_length) +
                                        " but the GLB's BIN chunk holds 4 bytes");
  }
  {  // a zero-length JSON chunk: blamed on the JSON chunk, not on BIN
    std::vector<unsigned char> b(bytes.begin(), bytes.begin() + 20);
    put_u32(b, 12, 0);
    put_u32(b, 8, uint32_t(b.size()));
    b.insert(b.end(), bytes.begin() + long(bin_header), bytes.end());
    put_u32(b, 8, uint32_t(b.size()));
    GltfBuilder::write_bytes(dir / "nojson.glb", b);
    expect_error(dir / "nojson.glb", "GLB: the JSON chunk is empty");
  }
}

TEST(Malformed, CameraValuesAreCheckedAsTheFloatsTheyBecome) {
  TempDir dir;
  for (const char* key : {"yfov", "znear"}) {
    SCOPED_TRACE(key);
    GltfBuilder b = valid_scene();
    json perspective = {{"yfov", 0.7}, {"znear", 0.1}};
    perspective[key] = 1e-300;  // > 0 as a double, 0 as a float
    b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", perspective}}};
    b.doc["nodes"][0]["camera"] = 0;
    expect_error(b.write_gltf(dir / "tiny.gltf"), "camera 0: ");
  }
  // Camera-path entries with large but finite coordinates are no "coincide" case; an up parallel
  // to the view direction is refused.
  GltfBuilder far = valid_scene();
  far.doc["extras"]["epi"]["camera_path"] = {{{"eye", {0, 0, 1e30}}, {"target", {0, 0, 0}}},
                                             {{"eye", {3e38, 0, 0}}, {"target", {-3e38, 0, 0}}}};
  EXPECT_EQ(load_error(far.write_gltf(dir / "far.gltf")), "");
  GltfBuilder parallel = valid_scene();
  parallel.doc["extras"]["epi"]["camera_path"] = {{{"eye", {0, 5, 0}}, {"target", {0, 0, 0}}, {"up", {0, 1e-3, 0}}}};
  expect_error(parallel.write_gltf(dir / "parallel.gltf"), "up is parallel to the view direction");
}

TEST(Malformed, SubdivisionBeyondTheMemoryLimitIsRefusedBeforeItRuns) {
  TempDir dir;
  GltfBuilder b = valid_scene();
  b.doc["meshes"][0]["extras"]["epi"]["subdivision"] = {{"level", 6}, {"quads", true}};  // 1 quad: 8192 triangles
  const auto file = b.write_gltf(dir / "sub.gltf");
  LoadOptions tight;
  tight.memory_limit = 4u << 20;  // 8192 * 600 bytes = 4.7 MiB estimated
  expect_error(file, "mesh 'quad' primitive 0: subdivision level 6 (up to 8192 refined triangles in the scene) needs "
                     "about 4.7 MiB (limit 4.0 MiB; --memory-limit GIB raises it)",
               tight);
  LoadOptions roomy;
  roomy.memory_limit = 8u << 20;
  EXPECT_EQ(load_error(file, roomy), "");
}

}  // namespace
}  // namespace epi

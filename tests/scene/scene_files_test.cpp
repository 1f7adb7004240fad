// The bundled scenes (scenes/*.gltf): valid glTF 2.0 with consistent buffers and accessors, the
// conventions epi reads (extras.epi, lights, cameras, camera paths), and the geometry each scene
// promises (triangle counts after subdivision, orientation, contacts, clearances).
// A small reader of our own, independent of the loader under io/gltf.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/subdivide.h"
#include "scene/topology.h"

namespace epi {
namespace {

using json = nlohmann::json;

std::vector<uint8_t> decode_base64(const std::string& text) {
  std::vector<uint8_t> out;
  uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    int value;
    if (c >= 'A' && c <= 'Z') value = c - 'A';
    else if (c >= 'a' && c <= 'z') value = c - 'a' + 26;
    else if (c >= '0' && c <= '9') value = c - '0' + 52;
    else if (c == '+') value = 62;
    else if (c == '/') value = 63;
    else if (c == '=') break;
    else throw std::runtime_error("bad base64 character");
    bits = bits << 6 | uint32_t(value);
    if (++count == 4) {
      out.insert(out.end(), {uint8_t(bits >> 16), uint8_t(bits >> 8), uint8_t(bits)});
      bits = 0, count = 0;
    }
  }
  if (count == 2) out.push_back(uint8_t(bits >> 4));
  if (count == 3) out.insert(out.end(), {uint8_t(bits >> 10), uint8_t(bits >> 2)});
  return out;
}

struct Primitive {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  int material = -1;
};

struct MeshInfo {
  std::string name;
  std::vector<Primitive> primitives;
  bool subdivided = false;
  SubdivisionScheme scheme = SubdivisionScheme::catmull_clark;
  int level = 0;
  bool quads = false;
  std::vector<Crease> creases;
  // After subdivision (or as is): one triangle mesh, object space.
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;
  std::vector<glm::vec3> normals;  // subdivided meshes only
};

struct Instance {
  std::string name;
  int mesh = -1;
  glm::mat4 transform{1.0f};
};

struct SceneFile {
  std::string name;
  json doc;
  std::vector<uint8_t> buffer;
  std::vector<MeshInfo> meshes;
  std::vector<Instance> instances;
  size_t triangles = 0;

  std::vector<glm::vec3> world_positions(const Instance& i) const {
    std::vector<glm::vec3> out;
    for (const glm::vec3& p : meshes[size_t(i.mesh)].positions) out.push_back(glm::vec3(i.transform * glm::vec4(p, 1.0f)));
    return out;
  }
  const Instance& instance(const std::string& name) const {
    for (const Instance& i : instances)
      if (i.name == name) return i;
    throw std::runtime_error("no node " + name);
  }
};

glm::mat4 read_matrix(const json& node) {
  glm::mat4 m(1.0f);
  if (!node.contains("matrix")) return m;
  const json& values = node["matrix"];
  EXPECT_EQ(values.size(), 16u);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m[c][r] = values[size_t(c * 4 + r)].get<float>();
  return m;
}

// Reads an accessor after checking it against its view and buffer; checks min/max.
template <class T, int Components>
std::vector<T> read_accessor(const SceneFile& file, int index) {
  const json& accessors = file.doc["accessors"];
  EXPECT_GE(index, 0);
  EXPECT_LT(size_t(index), accessors.size());
  const json& a = accessors[size_t(index)];
  const json& view = file.doc["bufferViews"][a["bufferView"].get<size_t>()];
  const size_t count = a["count"], offset = view["byteOffset"], length = view["byteLength"];
  EXPECT_EQ(view["buffer"], 0);
  EXPECT_EQ(offset % 4, 0u);
  EXPECT_LE(offset + length, file.buffer.size());
  EXPECT_EQ(count * sizeof(T) * Components, length) << "accessor " << index;
  EXPECT_EQ(a.value("byteOffset", 0), 0);
  std::vector<T> values(count * Components);
  if (offset + length <= file.buffer.size() && count * sizeof(T) * Components <= length)
    std::memcpy(values.data(), file.buffer.data() + offset, values.size() * sizeof(T));
  for (int c = 0; c < Components; ++c) {
    T lo = std::numeric_limits<T>::max(), hi = std::numeric_limits<T>::lowest();
    for (size_t i = 0; i < count; ++i) lo = std::min(lo, values[i * Components + c]), hi = std::max(hi, values[i * Components + c]);
    EXPECT_EQ(a["min"][size_t(c)].get<T>(), lo) << "accessor " << index << " min";
    EXPECT_EQ(a["max"][size_t(c)].get<T>(), hi) << "accessor " << index << " max";
  }
  return values;
}

// The cage of a subdivided primitive as a loader would build it: quads from triangle pairs.
ControlMesh cage_of(const MeshInfo& mesh) {
  const Primitive& p = mesh.primitives.front();
  ControlMesh cage;
  cage.positions = p.positions;
  cage.creases = mesh.creases;
  if (mesh.quads) {
    EXPECT_EQ(p.indices.size() % 6, 0u);
    for (size_t i = 0; i + 5 < p.indices.size(); i += 6) {
      const uint32_t* t = p.indices.data() + i;
      EXPECT_EQ(t[3], t[0]) << "quad pair " << i / 6 << " of " << mesh.name;
      EXPECT_EQ(t[4], t[2]) << "quad pair " << i / 6 << " of " << mesh.name;
      cage.face_sizes.push_back(4);
      cage.face_indices.insert(cage.face_indices.end(), {t[0], t[1], t[2], t[5]});
    }
  } else {
    cage.face_sizes.assign(p.indices.size() / 3, 3);
    cage.face_indices = p.indices;
  }
  return cage;
}

SceneFile read_scene(const std::string& name) {
  SceneFile file;
  file.name = name;
  const std::string path = std::string(EPI_SOURCE_DIR) + "/scenes/" + name + ".gltf";
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw std::runtime_error(path + ": cannot open");
  std::stringstream text;
  text << stream.rdbuf();
  file.doc = json::parse(text.str());  // throws on invalid JSON
  const json& doc = file.doc;

  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_EQ(doc["buffers"].size(), 1u);
  const std::string uri = doc["buffers"][0]["uri"];
  const std::string prefix = "data:application/octet-stream;base64,";
  EXPECT_EQ(uri.rfind(prefix, 0), 0u);
  file.buffer = decode_base64(uri.substr(prefix.size()));
  EXPECT_EQ(file.buffer.size(), doc["buffers"][0]["byteLength"].get<size_t>());

  for (const json& m : doc["meshes"]) {
    MeshInfo mesh;
    mesh.name = m["name"];
    for (const json& p : m["primitives"]) {
      Primitive primitive;
      EXPECT_EQ(p.value("mode", 4), 4);
      const json& position = doc["accessors"][p["attributes"]["POSITION"].get<size_t>()];
      EXPECT_EQ(position["componentType"], 5126);
      EXPECT_EQ(position["type"], "VEC3");
      const std::vector<float> flat = read_accessor<float, 3>(file, p["attributes"]["POSITION"]);
      for (size_t i = 0; i + 2 < flat.size(); i += 3) primitive.positions.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
      for (const glm::vec3& v : primitive.positions) EXPECT_TRUE(std::isfinite(v.x + v.y + v.z));
      const json& indices = doc["accessors"][p["indices"].get<size_t>()];
      EXPECT_EQ(indices["componentType"], 5125);
      EXPECT_EQ(indices["type"], "SCALAR");
      primitive.indices = read_accessor<uint32_t, 1>(file, p["indices"]);
      EXPECT_EQ(primitive.indices.size() % 3, 0u);
      for (uint32_t i : primitive.indices) EXPECT_LT(i, primitive.positions.size()) << mesh.name;
      primitive.material = p["material"];
      EXPECT_LT(size_t(primitive.material), doc["materials"].size());
      mesh.primitives.push_back(primitive);
    }
    const json& epi = m["extras"]["epi"];
    EXPECT_GE(epi["sharp_angle"].get<float>(), 0.0f);
    EXPECT_LE(epi["sharp_angle"].get<float>(), 180.0f);
    if (epi.contains("subdivision")) {
      const json& s = epi["subdivision"];
      mesh.subdivided = true;
      EXPECT_TRUE(s["scheme"] == "catmull-clark" || s["scheme"] == "loop");
      mesh.scheme = s["scheme"] == "loop" ? SubdivisionScheme::loop : SubdivisionScheme::catmull_clark;
      mesh.level = s["level"];
      mesh.quads = s["quads"];
      for (const json& c : s["creases"]) mesh.creases.push_back({c[0], c[1], c[2]});
      EXPECT_EQ(mesh.primitives.size(), 1u);
      if (mesh.scheme == SubdivisionScheme::loop) {
        EXPECT_FALSE(mesh.quads);
      }
      const SubdividedMesh refined = subdivide(cage_of(mesh), mesh.scheme, mesh.level);  // throws on a bad cage
      mesh.positions = refined.positions;
      mesh.triangles = refined.triangles;
      mesh.normals = refined.normals;
    } else {
      for (const Primitive& p : mesh.primitives) {
        const uint32_t base = uint32_t(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), p.positions.begin(), p.positions.end());
        for (size_t i = 0; i + 2 < p.indices.size(); i += 3)
          mesh.triangles.emplace_back(base + p.indices[i], base + p.indices[i + 1], base + p.indices[i + 2]);
      }
    }
    file.meshes.push_back(mesh);
  }

  // Every node is a root of the scene (the generator writes flat scenes), names are unique.
  const json& nodes = doc["nodes"];
  EXPECT_EQ(doc["scene"], 0);
  EXPECT_EQ(doc["scenes"][0]["nodes"].size(), nodes.size());
  std::set<std::string> names;
  for (const json& node : nodes) {
    EXPECT_TRUE(names.insert(node["name"].get<std::string>()).second) << node["name"];
    if (node.contains("mesh")) {
      EXPECT_LT(node["mesh"].get<size_t>(), file.meshes.size());
      file.instances.push_back({node["name"], node["mesh"], read_matrix(node)});
      file.triangles += file.meshes[node["mesh"].get<size_t>()].triangles.size();
    }
  }
  return file;
}

// Each file is read (and subdivided) once per test run.
const SceneFile& load(const std::string& name) {
  static std::map<std::string, SceneFile> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, read_scene(name)).first;
  return it->second;
}

const std::map<std::string, size_t> kTrianglesAfterSubdivision = {
    {"cornell_box", 36}, {"chains", 73730}, {"torus_capsule", 31748}, {"grid_dragon", 888028}, {"rooms", 12708}};

class SceneFiles : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneFiles, TrianglesAfterSubdivision) {
  const SceneFile& file = load(GetParam());
  EXPECT_EQ(file.triangles, kTrianglesAfterSubdivision.at(GetParam()));
}

TEST_P(SceneFiles, ClosedMeshesFaceOutward) {
  const SceneFile& file = load(GetParam());
  for (const MeshInfo& mesh : file.meshes) {
    Mesh m;
    m.positions = mesh.positions;
    m.triangles = mesh.triangles;
    const EdgeTable table = build_edge_table(m);
    EXPECT_EQ(table.non_manifold_edges, 0u) << mesh.name;
    if (table.border_edges != 0) continue;  // open surfaces (walls, floors, lights) are checked per scene
    double volume = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
      volume += glm::dot(glm::dvec3(m.positions[t.x]), glm::cross(glm::dvec3(m.positions[t.y]), glm::dvec3(m.positions[t.z])));
    EXPECT_GT(volume, 0.0) << mesh.name;
  }
}

TEST_P(SceneFiles, CamerasAndCameraPath) {
  const SceneFile& file = load(GetParam());
  const json& doc = file.doc;
  ASSERT_GE(doc["cameras"].size(), 1u);
  EXPECT_EQ(doc["cameras"][0]["type"], "perspective");
  const float yfov = doc["cameras"][0]["perspective"]["yfov"];
  EXPECT_GT(yfov, 0.1f);
  EXPECT_LT(yfov, 2.0f);  // radians
  bool camera_node = false;
  for (const json& node : doc["nodes"]) camera_node |= node.contains("camera") && node["camera"] == 0;
  EXPECT_TRUE(camera_node);
  const json& path = doc["scenes"][0]["extras"]["epi"]["camera_path"];
  EXPECT_EQ(path.size(), 60u);
  float longest_step = 0.0f;
  for (size_t k = 0; k < path.size(); ++k) {
    auto vec = [](const json& a) { return glm::vec3(a[0].get<float>(), a[1].get<float>(), a[2].get<float>()); };
    const glm::vec3 eye = vec(path[k]["eye"]), target = vec(path[k]["target"]), up = vec(path[k]["up"]);
    EXPECT_GT(glm::length(target - eye), 0.1f);
    EXPECT_GT(glm::length(glm::cross(glm::normalize(target - eye), up)), 0.2f);  // up not along the view
    EXPECT_GT(path[k]["yfov"].get<float>(), 10.0f);  // degrees
    EXPECT_LT(path[k]["yfov"].get<float>(), 120.0f);
    longest_step = std::max(longest_step, glm::length(vec(path[(k + 1) % path.size()]["eye"]) - eye));
  }
  // Smooth and closed: no key jumps more than a few percent of the scene's size.
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const Instance& i : file.instances)
    for (const glm::vec3& p : file.world_positions(i)) lo = glm::min(lo, p), hi = glm::max(hi, p);
  EXPECT_LT(longest_step, 0.12f * glm::length(hi - lo));
}

TEST_P(SceneFiles, MaterialsAndLights) {
  const SceneFile& file = load(GetParam());
  const json& doc = file.doc;
  std::set<std::string> used;
  for (const json& e : doc.value("extensionsUsed", json::array())) used.insert(e.get<std::string>());
  int emissive_materials = 0;
  for (const json& m : doc["materials"]) {
    const json& pbr = m["pbrMetallicRoughness"];
    for (const json& c : pbr["baseColorFactor"]) EXPECT_TRUE(c >= 0.0 && c <= 1.0);
    EXPECT_TRUE(pbr["metallicFactor"] >= 0.0 && pbr["metallicFactor"] <= 1.0);
    EXPECT_TRUE(pbr["roughnessFactor"] >= 0.0 && pbr["roughnessFactor"] <= 1.0);
    if (m.contains("emissiveFactor")) {
      ++emissive_materials;
      for (const json& c : m["emissiveFactor"]) EXPECT_TRUE(c >= 0.0 && c <= 1.0);
    }
    if (m.contains("extensions")) {
      EXPECT_TRUE(used.count("KHR_materials_emissive_strength"));
      EXPECT_GT(m["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"].get<float>(), 1.0f);
    }
  }
  size_t lights = 0;
  if (doc.contains("extensions")) {
    EXPECT_TRUE(used.count("KHR_lights_punctual"));
    const json& list = doc["extensions"]["KHR_lights_punctual"]["lights"];
    lights = list.size();
    for (const json& l : list) {
      EXPECT_TRUE(l["type"] == "point" || l["type"] == "spot" || l["type"] == "directional");
      EXPECT_GT(l["intensity"].get<float>(), 0.0f);
      if (l["type"] == "spot") {
        const float inner = l["spot"]["innerConeAngle"], outer = l["spot"]["outerConeAngle"];
        EXPECT_GE(inner, 0.0f);
        EXPECT_LT(inner, outer);
        EXPECT_LE(outer, 1.5707964f);
      }
    }
    std::set<int> referenced;
    for (const json& node : doc["nodes"])
      if (node.contains("extensions")) referenced.insert(node["extensions"]["KHR_lights_punctual"]["light"].get<int>());
    EXPECT_EQ(referenced.size(), lights);
    EXPECT_EQ(referenced.empty() ? -1 : *referenced.rbegin(), int(lights) - 1);
  }
  // Emitting objects: instances of meshes whose material emits.
  size_t area_lights = 0;
  for (const Instance& i : file.instances)
    for (const Primitive& p : file.meshes[size_t(i.mesh)].primitives)
      area_lights += doc["materials"][size_t(p.material)].contains("emissiveFactor");
  const std::map<std::string, std::pair<size_t, size_t>> expected = {  // punctual, area
      {"cornell_box", {0, 1}}, {"chains", {2, 0}}, {"torus_capsule", {0, 1}}, {"grid_dragon", {1, 1}}, {"rooms", {5, 2}}};
  EXPECT_EQ(lights, expected.at(GetParam()).first);
  EXPECT_EQ(area_lights, expected.at(GetParam()).second);
  EXPECT_GE(emissive_materials, area_lights ? 1 : 0);
}

INSTANTIATE_TEST_SUITE_P(Bundled, SceneFiles,
                         ::testing::Values("cornell_box", "chains", "torus_capsule", "grid_dragon", "rooms"));

float min_y(const std::vector<glm::vec3>& points) {
  float y = 1e30f;
  for (const glm::vec3& p : points) y = std::min(y, p.y);
  return y;
}

// Emitters and floors face where they should: the world-space normal of an open quad.
glm::vec3 facing(const SceneFile& file, const std::string& node) {
  const Instance& i = file.instance(node);
  const std::vector<glm::vec3> p = file.world_positions(i);
  const glm::uvec3 t = file.meshes[size_t(i.mesh)].triangles.front();
  return glm::normalize(glm::cross(p[t.y] - p[t.x], p[t.z] - p[t.x]));
}

float max_y(const std::vector<glm::vec3>& points) {
  float y = -1e30f;
  for (const glm::vec3& p : points) y = std::max(y, p.y);
  return y;
}

glm::vec3 centre(const std::vector<glm::vec3>& points) {
  glm::vec3 sum(0.0f);
  for (const glm::vec3& p : points) sum += p;
  return sum / float(points.size());
}

TEST(SceneGeometry, CornellBox) {
  const SceneFile& file = load("cornell_box");
  EXPECT_LT(facing(file, "ceiling_light").y, -0.99f);
  // Walls face into the box; the blocks stand on the floor.
  const glm::vec3 inside(0.278f, 0.274f, 0.28f);
  for (const char* wall : {"white_walls", "red_wall", "green_wall"}) {
    const Instance& i = file.instance(wall);
    const std::vector<glm::vec3> p = file.world_positions(i);
    for (const glm::uvec3& t : file.meshes[size_t(i.mesh)].triangles)
      EXPECT_GT(glm::dot(glm::cross(p[t.y] - p[t.x], p[t.z] - p[t.x]), inside - p[t.x]), 0.0f) << wall;
  }
  for (const char* block : {"short_block", "tall_block"}) EXPECT_EQ(min_y(file.world_positions(file.instance(block))), 0.0f);
  // The path looks in through the open front, never from beside or behind the walls.
  for (const json& key : file.doc["scenes"][0]["extras"]["epi"]["camera_path"]) {
    EXPECT_LT(key["eye"][2].get<float>(), -0.5f);
    EXPECT_GT(key["eye"][0].get<float>(), 0.0f);
    EXPECT_LT(key["eye"][0].get<float>(), 0.556f);
  }
}

TEST(SceneGeometry, ChainLinksDoNotTouch) {
  const SceneFile& file = load("chains");
  EXPECT_GT(facing(file, "floor").y, 0.99f);
  std::vector<std::vector<glm::vec3>> links;
  for (const Instance& i : file.instances)
    if (i.name != "floor") links.push_back(file.world_positions(i));
  ASSERT_EQ(links.size(), 12u);
  // Limit-surface points of different links stay apart (brute force over a subsample of one side).
  float closest = 1e30f;
  std::string closest_pair;
  for (size_t a = 0; a < links.size(); ++a) {
    EXPECT_GT(min_y(links[a]), 0.01f);  // above the floor
    for (size_t b = a + 1; b < links.size(); ++b) {
      float pair = 1e30f;
      for (size_t i = 0; i < links[a].size(); i += 3)
        for (const glm::vec3& q : links[b]) pair = std::min(pair, glm::length(links[a][i] - q));
      if (pair < closest) closest = pair, closest_pair = std::to_string(a) + "-" + std::to_string(b);
    }
  }
  EXPECT_GT(closest, 0.01f) << "links " << closest_pair;
  // Interlocked: consecutive links do not touch, yet their centres are closer than the sum of their
  // half lengths minus a tube width on each side, so each passes through the other's hole.
  const glm::vec3 c0 = centre(links[0]), c1 = centre(links[1]);
  float half_length = 0.0f;
  for (const glm::vec3& p : links[0]) half_length = std::max(half_length, glm::length(p - c0));
  EXPECT_LT(glm::length(c1 - c0), 1.5f * half_length);
  EXPECT_GT(glm::length(c1 - c0), 0.5f * half_length);
}

TEST(SceneGeometry, TorusTouchesCapsule) {
  const SceneFile& file = load("torus_capsule");
  const std::vector<glm::vec3> capsule = file.world_positions(file.instance("capsule"));
  const std::vector<glm::vec3> torus = file.world_positions(file.instance("torus"));
  EXPECT_NEAR(min_y(capsule), 0.0f, 1e-6f);
  EXPECT_NEAR(min_y(torus), max_y(capsule), 1e-6f);
  // The contact: lowest torus points right over the capsule's top line (z = 0), within its level part.
  int contacts = 0;
  for (const glm::vec3& p : torus) contacts += p.y < min_y(torus) + 1e-6f && std::abs(p.z) < 1e-4f && std::abs(p.x) < 0.21f;
  EXPECT_GE(contacts, 2);
  // No torus point inside the capsule: each lies on the outer side of the nearest capsule point's tangent plane.
  const MeshInfo& capsule_mesh = file.meshes[size_t(file.instance("capsule").mesh)];
  const glm::mat4 capsule_transform = file.instance("capsule").transform;
  float deepest = 0.0f;
  for (const glm::vec3& p : torus) {
    size_t nearest = 0;
    for (size_t q = 1; q < capsule.size(); ++q)
      if (glm::length(capsule[q] - p) < glm::length(capsule[nearest] - p)) nearest = q;
    const glm::vec3 normal = glm::mat3(capsule_transform) * capsule_mesh.normals[nearest];
    deepest = std::min(deepest, glm::dot(p - capsule[nearest], normal));
  }
  EXPECT_GT(deepest, -1e-5f);
  EXPECT_LT(facing(file, "area_light").y, -0.99f);
  EXPECT_GT(facing(file, "floor").y, 0.99f);
}

TEST(SceneGeometry, GridAboveDragon) {
  const SceneFile& file = load("grid_dragon");
  const Instance& dragon = file.instance("dragon");
  EXPECT_GE(file.meshes[size_t(dragon.mesh)].triangles.size(), 800000u);
  const std::vector<glm::vec3> body = file.world_positions(dragon);
  EXPECT_NEAR(min_y(body), 0.0f, 1e-6f);
  EXPECT_GT(min_y(file.world_positions(file.instance("grid"))), max_y(body) + 0.1f);
  const std::vector<glm::vec3> light = file.world_positions(file.instance("area_light"));
  EXPECT_GT(glm::dot(facing(file, "area_light"), glm::normalize(centre(body) - centre(light))), 0.9f);
}

TEST(SceneGeometry, RoomsFurnitureStandsInside) {
  const SceneFile& file = load("rooms");
  EXPECT_LT(facing(file, "panel_a").y, -0.99f);
  EXPECT_LT(facing(file, "ceiling").y, -0.99f);
  EXPECT_GT(facing(file, "floor").y, 0.99f);
  for (const Instance& i : file.instances) {
    if (i.name == "walls") continue;
    for (const glm::vec3& p : file.world_positions(i)) {
      EXPECT_GE(p.x, 0.0f) << i.name;
      EXPECT_LE(p.x, 8.0f) << i.name;
      EXPECT_GE(p.z, 0.0f) << i.name;
      EXPECT_LE(p.z, 8.0f) << i.name;
      EXPECT_GE(p.y, 0.0f) << i.name;
      EXPECT_LE(p.y, 2.6f) << i.name;
    }
  }
  for (const char* resting : {"pouf", "ball", "bed", "table_a"})
    EXPECT_NEAR(min_y(file.world_positions(file.instance(resting))), 0.0f, 1e-6f) << resting;
  EXPECT_NEAR(min_y(file.world_positions(file.instance("vase"))), 0.76f, 1e-6f);

  // The walk stays in the rooms, crosses the interior walls only through doorways (1 m wide,
  // centred at 2 and 6 m), and keeps clear of the outer walls and the shelf.
  const json& path = file.doc["scenes"][0]["extras"]["epi"]["camera_path"];
  auto in_doorway = [](float along) { return std::abs(along - 2.0f) < 0.35f || std::abs(along - 6.0f) < 0.35f; };
  for (size_t k = 0; k < path.size(); ++k) {
    const glm::vec3 eye(path[k]["eye"][0].get<float>(), path[k]["eye"][1].get<float>(), path[k]["eye"][2].get<float>());
    EXPECT_GT(std::min(eye.x, eye.z), 0.5f) << "key " << k;
    EXPECT_LT(std::max(eye.x, eye.z), 7.0f) << "key " << k;
    if (std::abs(eye.x - 4.0f) < 0.25f) {
      EXPECT_TRUE(in_doorway(eye.z)) << "key " << k << " in the wall x = 4";
    }
    if (std::abs(eye.z - 4.0f) < 0.25f) {
      EXPECT_TRUE(in_doorway(eye.x)) << "key " << k << " in the wall z = 4";
    }
    EXPECT_LT(eye.y, 2.1f);  // below the door lintels
  }
}

}  // namespace
}  // namespace epi

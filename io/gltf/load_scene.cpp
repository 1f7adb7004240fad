// glTF 2.0 -> Scene. Order of work: read the file (GLB container or JSON text), type-check the JSON,
// let tinygltf decode buffers, check every index and byte range, walk the node tree with an
// explicit stack, then build materials, meshes (with subdivision), objects, cameras and lights.
#include "load_scene.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "accessors.h"
#include "area_lights.h"
#include "json_check.h"
#include "scene/subdivide.h"
#include "scene/topology.h"

namespace epi {

namespace {

using gltf::describe_json;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxSubdivisionLevel = 8;
constexpr uint64_t kMaxRefinedTriangles = uint64_t(1) << 26;  // ~2.4 GB of refined mesh, over the whole scene
const std::set<std::string> kSupportedRequiredExtensions{"KHR_lights_punctual", "KHR_materials_emissive_strength"};

[[noreturn]] void fail(const std::string& problem) { throw std::runtime_error(problem); }

// Messages are one line: line breaks inside (tinygltf's, say) become "; ".
std::string one_line(const std::string& text) {
  std::string out;
  bool pending_break = false;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      pending_break = !out.empty();
      continue;
    }
    if (pending_break) out += "; ";
    pending_break = false;
    out += c;
  }
  return out;
}

// Finite once stored as float (the scene model's type); false for NaN and infinities.
bool fits_float(double v) { return std::abs(v) <= double(FLT_MAX); }
bool finite(const glm::dvec3& v) { return fits_float(v.x) && fits_float(v.y) && fits_float(v.z); }

// ---------------------------------------------------------------------------------------------
// The file: a GLB container or JSON text.

struct FileContents {
  std::vector<unsigned char> bytes;
  bool binary = false;
  std::string json_text;
  uint64_t bin_chunk_bytes = 0;  // GLB: the BIN chunk's length (0 when there is none)
  bool has_bin_chunk = false;
};

uint32_t read_u32(const std::vector<unsigned char>& bytes, size_t offset) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + offset, 4);
  return v;
}

FileContents read_file(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) fail("cannot open file (missing or not a regular file)");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail("cannot open file");
  FileContents contents;
  contents.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) fail("read error");
  if (contents.bytes.empty()) fail("file is empty");
  if (contents.bytes.size() >= 0x7fffffffu) fail("file is larger than 2 GiB");

  const auto& b = contents.bytes;
  contents.binary = b.size() >= 4 && std::memcmp(b.data(), "glTF", 4) == 0;
  if (!contents.binary) {
    contents.json_text.assign(b.begin(), b.end());
    return contents;
  }
  // GLB: 12-byte header, a JSON chunk, then optionally a BIN chunk.
  if (b.size() < 20) fail("truncated GLB header");
  if (read_u32(b, 4) != 2) fail("GLB version " + std::to_string(read_u32(b, 4)) + " is not supported (need 2)");
  if (read_u32(b, 8) != b.size())
    fail("GLB header says " + std::to_string(read_u32(b, 8)) + " bytes, file has " + std::to_string(b.size()));
  const uint64_t json_length = read_u32(b, 12);
  if (read_u32(b, 16) != 0x4E4F534Au) fail("GLB: first chunk is not JSON");
  if (json_length == 0) fail("GLB: the JSON chunk is empty");
  if (20 + json_length > b.size()) fail("GLB: JSON chunk runs past the end of the file");
  const uint64_t bin_start = 20 + json_length;
  if (bin_start < b.size()) {
    if (bin_start + 8 > b.size()) fail("GLB: truncated chunk header after the JSON chunk");
    if (bin_start + 8 + read_u32(b, size_t(bin_start)) > b.size()) fail("GLB: BIN chunk runs past the end of the file");
    if (read_u32(b, size_t(bin_start) + 4) != 0x004E4942u) {
      char type[16];
      std::snprintf(type, sizeof type, "0x%08X", read_u32(b, size_t(bin_start) + 4));
      fail(std::string("GLB: the chunk after the JSON chunk has type ") + type + ", not BIN (0x004E4942)");
    }
    contents.has_bin_chunk = true;
    contents.bin_chunk_bytes = read_u32(b, size_t(bin_start));
  }
  contents.json_text.assign(b.begin() + 20, b.begin() + long(20 + json_length));
  return contents;
}

// Bytes a base64 text decodes to (tinygltf's decoder ignores what follows the data).
uint64_t base64_decoded_bytes(std::string_view text) {
  while (!text.empty() && text.back() == '=') text.remove_suffix(1);
  return uint64_t(text.size()) * 3 / 4;
}

// Buffers, checked before tinygltf reads them so that its messages (which quote whole data: URIs
// or say "File not found : ") never reach the user: every buffer's bytes exist and hold byteLength.
void check_buffers(const json& document, const FileContents& contents, const std::filesystem::path& file) {
  if (!document.contains("buffers")) return;
  const json& buffers = document["buffers"];
  for (size_t i = 0; i < buffers.size(); ++i) {
    const json& buffer = buffers[i];
    const std::string where = "buffers[" + std::to_string(i) + "]";
    if (!buffer.contains("byteLength")) fail(where + ": byteLength is missing");
    const uint64_t length = buffer["byteLength"].get<uint64_t>();
    if (!buffer.contains("uri")) {
      if (!contents.binary || i != 0) fail(where + ": no uri (only a GLB's first buffer may omit it)");
      if (!contents.has_bin_chunk) fail(where + ": no uri and the GLB has no BIN chunk");
      if (contents.bin_chunk_bytes < length)
        fail(where + ": byteLength " + std::to_string(length) + " but the GLB's BIN chunk holds " +
             std::to_string(contents.bin_chunk_bytes) + " bytes");
      continue;
    }
    const std::string uri = buffer["uri"].get<std::string>();
    if (uri.rfind("data:", 0) == 0) {
      const size_t comma = uri.find(',');
      if (comma == std::string::npos || uri.substr(0, comma).find(";base64") == std::string::npos)
        fail(where + ": a data: URI must be base64 ('data:...;base64,...')");
      const uint64_t decoded = base64_decoded_bytes(std::string_view(uri).substr(comma + 1));
      if (decoded < length)
        fail(where + ": byteLength " + std::to_string(length) + " but its data: URI holds " + std::to_string(decoded) +
             " bytes");
      continue;
    }
    std::string name;  // the URI with %XX escapes decoded, as tinygltf reads it
    for (size_t k = 0; k < uri.size(); ++k) {
      unsigned code = 0;
      if (uri[k] == '%' && k + 2 < uri.size() && std::sscanf(uri.c_str() + k + 1, "%2x", &code) == 1) {
        name += char(code);
        k += 2;
      } else {
        name += uri[k];
      }
    }
    const std::filesystem::path path = std::filesystem::absolute(file).parent_path() / name;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) fail(where + ": buffer file '" + uri + "' not found beside the scene");
    const uint64_t size = std::filesystem::file_size(path, ec);
    if (ec || size < length)
      fail(where + ": byteLength " + std::to_string(length) + " but '" + uri + "' holds " + std::to_string(size) + " bytes");
  }
}

// tinygltf's file access, restricted to absolute paths (its default also searches the working
// directory and expands shell words in paths).
bool file_exists(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::path(path).is_absolute() && std::filesystem::is_regular_file(path, ec);
}
std::string expand_path(const std::string& path, void*) { return path; }
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (err) *err += "cannot open " + path + "\n";
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !in.bad();
}
bool write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is disabled\n";
  return false;
}
// Textures are ignored: images are neither decoded nor kept.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

tinygltf::Model parse_with_tinygltf(const FileContents& contents, const std::filesystem::path& file) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  loader.SetFsCallbacks({file_exists, expand_path, read_whole_file, write_whole_file, nullptr});
  const std::string base_dir = std::filesystem::absolute(file).parent_path().string();
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  if (contents.binary)
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn, contents.bytes.data(), unsigned(contents.bytes.size()),
                                     base_dir);
  else
    ok = loader.LoadASCIIFromString(&model, &err, &warn, contents.json_text.data(), unsigned(contents.json_text.size()),
                                    base_dir);
  if (!ok || !err.empty()) {
    std::string problem = one_line(err.empty() ? "tinygltf could not load the file" : err);
    if (problem.size() > 240) problem = problem.substr(0, 240) + "...";  // it may quote a whole data: URI
    fail(problem);
  }
  return model;
}

// ---------------------------------------------------------------------------------------------
// Checks of the decoded model: indices, byte ranges, node structure, values.

void check_index(int index, size_t count, const std::string& what, const std::string& where) {
  if (index < 0 || size_t(index) >= count)
    fail(where + ": " + what + " index " + std::to_string(index) + " out of range (" + std::to_string(count) + " " +
         what + (count == 1 ? "" : "s") + ")");
}

size_t component_bytes(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

size_t type_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

void check_accessors(const tinygltf::Model& model) {
  for (size_t i = 0; i < model.bufferViews.size(); ++i) gltf::check_buffer_view(model, int(i));
  for (size_t i = 0; i < model.accessors.size(); ++i) {
    const tinygltf::Accessor& a = model.accessors[i];
    const std::string where = "accessor " + std::to_string(i);
    const size_t element = component_bytes(a.componentType) * type_components(a.type);
    if (component_bytes(a.componentType) == 0)
      fail(where + ": invalid componentType " + std::to_string(a.componentType));
    if (type_components(a.type) == 0) fail(where + ": invalid type");
    if (a.bufferView < 0 || a.count == 0) continue;
    check_index(a.bufferView, model.bufferViews.size(), "buffer view", where);
    const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
    const uint64_t stride = view.byteStride != 0 ? view.byteStride : element;
    const uint64_t end = uint64_t(a.byteOffset) + (uint64_t(a.count) - 1) * stride + element;
    if (end > view.byteLength)
      fail(where + ": reads up to byte " + std::to_string(end) + ", past the end of buffer view " +
           std::to_string(a.bufferView) + " (" + std::to_string(view.byteLength) + " bytes)");
  }
}

// Children lists must form a forest: no node with two parents, no cycles, roots without parents.
std::vector<int> check_node_forest(const tinygltf::Model& model) {
  const size_t n = model.nodes.size();
  std::vector<int> parent(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const tinygltf::Node& node = model.nodes[i];
    const std::string where = "node " + std::to_string(i);
    for (int child : node.children) {
      check_index(child, n, "node", where + " children");
      if (size_t(child) == i) fail(where + " is its own child");
      if (parent[size_t(child)] == int(i)) fail(where + " lists child " + std::to_string(child) + " twice");
      if (parent[size_t(child)] != -1)
        fail("node " + std::to_string(child) + " has two parents (nodes " + std::to_string(parent[size_t(child)]) +
             " and " + std::to_string(i) + ")");
      parent[size_t(child)] = int(i);
    }
  }
  // With one parent each, a cycle is a parent chain that never reaches a root.
  std::vector<char> state(n, 0);  // 0 unknown, 1 on the current chain, 2 reaches a root
  for (size_t start = 0; start < n; ++start) {
    std::vector<size_t> chain;
    size_t at = start;
    while (state[at] == 0) {
      state[at] = 1;
      chain.push_back(at);
      if (parent[at] < 0) break;
      at = size_t(parent[at]);
    }
    if (state[at] == 1 && parent[at] >= 0) fail("node cycle through node " + std::to_string(at));
    for (size_t c : chain) state[c] = 2;
  }
  return parent;
}

void check_unit_range(double value, const std::string& what) {
  if (!std::isfinite(value) || value < 0.0 || value > 1.0)
    fail(what + " " + std::to_string(value) + " is outside [0, 1]");
}

void check_model(const tinygltf::Model& model) {
  check_accessors(model);
  for (size_t i = 0; i < model.scenes.size(); ++i)
    for (int node : model.scenes[i].nodes) check_index(node, model.nodes.size(), "node", "scene " + std::to_string(i));
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    const tinygltf::Node& node = model.nodes[i];
    const std::string where = "node " + std::to_string(i);
    if (node.mesh != -1) check_index(node.mesh, model.meshes.size(), "mesh", where);
    if (node.camera != -1) check_index(node.camera, model.cameras.size(), "camera", where);
    if (node.skin != -1) check_index(node.skin, model.skins.size(), "skin", where);
  }
  for (size_t m = 0; m < model.meshes.size(); ++m) {
    for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      const tinygltf::Primitive& primitive = model.meshes[m].primitives[p];
      const std::string where = "mesh " + std::to_string(m) + " primitive " + std::to_string(p);
      for (const auto& [name, accessor] : primitive.attributes)
        check_index(accessor, model.accessors.size(), "accessor", where + " attribute " + name);
      for (const auto& target : primitive.targets)
        for (const auto& [name, accessor] : target)
          check_index(accessor, model.accessors.size(), "accessor", where + " morph target " + name);
      if (primitive.indices != -1)
        check_index(primitive.indices, model.accessors.size(), "accessor", where + " indices");
      if (primitive.material != -1) check_index(primitive.material, model.materials.size(), "material", where);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Node transforms and the walk over the chosen scene.

glm::dmat4 local_transform(const tinygltf::Node& node, size_t index) {
  const std::string where = "node " + std::to_string(index);
  if (!node.matrix.empty()) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[size_t(c * 4 + r)];  // column-major, as glTF
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
      fail(where + ": matrix is not affine (its last row must be 0 0 0 1)");
    return m;
  }
  glm::dmat4 m(1.0);
  if (!node.translation.empty())
    m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (!node.rotation.empty()) {
    glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF: x, y, z, w
    const double length = glm::length(q);
    if (!(length > 1e-12) || !std::isfinite(length)) fail(where + ": rotation quaternion has zero length");
    m = m * glm::mat4_cast(q / length);
  }
  if (!node.scale.empty()) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

struct NodeVisit {
  size_t node;
  glm::dmat4 world;
};

// Preorder over the chosen scene's nodes, children in file order; iterative, so depth is not limited.
std::vector<NodeVisit> walk_scene(const tinygltf::Model& model, const tinygltf::Scene& scene,
                                  const std::vector<int>& parent) {
  std::vector<NodeVisit> visits;
  std::vector<NodeVisit> stack;
  std::vector<bool> seen(model.nodes.size(), false);
  for (auto root = scene.nodes.rbegin(); root != scene.nodes.rend(); ++root) {
    if (parent[size_t(*root)] != -1)
      fail("scene root node " + std::to_string(*root) + " is the child of node " +
           std::to_string(parent[size_t(*root)]));
    stack.push_back({size_t(*root), glm::dmat4(1.0)});
  }
  while (!stack.empty()) {
    NodeVisit visit = stack.back();
    stack.pop_back();
    if (seen[visit.node]) fail("node " + std::to_string(visit.node) + " is listed twice as a scene root");
    seen[visit.node] = true;
    const tinygltf::Node& node = model.nodes[visit.node];
    visit.world = visit.world * local_transform(node, visit.node);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!(std::abs(visit.world[c][r]) <= double(FLT_MAX)))  // scene transforms are floats
          fail("node " + std::to_string(visit.node) + ": world transform is not finite");
    visits.push_back(visit);
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
      stack.push_back({size_t(*child), visit.world});
  }
  return visits;
}

// ---------------------------------------------------------------------------------------------
// Materials.

Material convert_material(const tinygltf::Material& source, const json& source_json, size_t index) {
  Material material;
  material.name = source.name.empty() ? "material" + std::to_string(index) : source.name;
  const std::string where = "material '" + material.name + "'";
  const auto& pbr = source.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() == 4) {
    for (int c = 0; c < 4; ++c) check_unit_range(pbr.baseColorFactor[size_t(c)], where + ": baseColorFactor");
    material.base_color = glm::vec3(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]);
  }
  check_unit_range(pbr.metallicFactor, where + ": metallicFactor");
  check_unit_range(pbr.roughnessFactor, where + ": roughnessFactor");
  material.metallic = float(pbr.metallicFactor);
  material.roughness = float(pbr.roughnessFactor);
  glm::dvec3 emission(0.0);
  if (source.emissiveFactor.size() == 3) {
    for (int c = 0; c < 3; ++c) check_unit_range(source.emissiveFactor[size_t(c)], where + ": emissiveFactor");
    emission = glm::dvec3(source.emissiveFactor[0], source.emissiveFactor[1], source.emissiveFactor[2]);
  }
  double strength = 1.0;
  const json* extension = nullptr;
  if (source_json.contains("extensions") && source_json["extensions"].contains("KHR_materials_emissive_strength"))
    extension = &source_json["extensions"]["KHR_materials_emissive_strength"];
  if (extension && extension->contains("emissiveStrength")) {
    strength = (*extension)["emissiveStrength"].get<double>();
    if (!std::isfinite(strength) || strength < 0.0)
      fail(where + ": emissiveStrength " + std::to_string(strength) + " must be finite and >= 0");
  }
  if (!finite(emission * strength)) fail(where + ": emission is not finite");
  material.emission = glm::vec3(emission * strength);
  return material;
}

// ---------------------------------------------------------------------------------------------
// Mesh extras: the subdivision request and the sharp-edge angle.

struct MeshRequest {
  bool subdivide = false;
  SubdivisionScheme scheme = SubdivisionScheme::catmull_clark;
  int level = 1;
  bool quads = false;
  std::vector<Crease> creases;  // primitive vertex indices
  float sharp_angle_degrees = 85.0f;
};

const json& member(const json& object, const char* key, const std::string& where,
                   bool (json::*is_type)() const noexcept, const char* type_name) {
  const json& value = object[key];
  if (!(value.*is_type)()) fail(where + "." + key + ": expected " + type_name + ", got " + describe_json(value));
  return value;
}

MeshRequest read_mesh_request(const json& mesh_json, const std::string& where_mesh, const LoadOptions& options) {
  MeshRequest request;
  if (!mesh_json.contains("extras") || !mesh_json["extras"].is_object() || !mesh_json["extras"].contains("epi"))
    return request;
  const std::string where = where_mesh + " extras.epi";
  const json& epi = mesh_json["extras"]["epi"];
  if (!epi.is_object()) fail(where + ": expected an object, got " + describe_json(epi));
  if (epi.contains("sharp_angle")) {
    const double angle = member(epi, "sharp_angle", where, &json::is_number, "a number").get<double>();
    if (!(angle >= 0.0 && angle <= 180.0))
      fail(where + ".sharp_angle: " + std::to_string(angle) + " is outside [0, 180]");
    request.sharp_angle_degrees = float(angle);
  }
  if (!epi.contains("subdivision")) return request;
  const std::string sub_where = where + ".subdivision";
  const json& sub = member(epi, "subdivision", where, &json::is_object, "an object");
  request.subdivide = true;
  if (sub.contains("scheme")) {
    const std::string scheme = member(sub, "scheme", sub_where, &json::is_string, "a string").get<std::string>();
    if (scheme == "catmull-clark")
      request.scheme = SubdivisionScheme::catmull_clark;
    else if (scheme == "loop")
      request.scheme = SubdivisionScheme::loop;
    else
      fail(sub_where + ".scheme: unknown scheme '" + scheme + "' (catmull-clark or loop)");
  }
  if (sub.contains("level")) {
    const json& level = sub["level"];
    if (!level.is_number_integer() || level.get<int64_t>() < 0 || level.get<int64_t>() > kMaxSubdivisionLevel)
      fail(sub_where + ".level: expected an integer in [0, " + std::to_string(kMaxSubdivisionLevel) + "], got " +
           describe_json(level));
    request.level = level.get<int>();
  }
  if (options.subdiv_level_override >= 0) request.level = options.subdiv_level_override;
  if (sub.contains("quads"))
    request.quads = member(sub, "quads", sub_where, &json::is_boolean, "a boolean").get<bool>();
  if (request.quads && request.scheme == SubdivisionScheme::loop)
    fail(sub_where + ": the loop scheme needs triangles, not quads");
  if (sub.contains("creases")) {
    const json& creases = member(sub, "creases", sub_where, &json::is_array, "an array");
    for (size_t i = 0; i < creases.size(); ++i) {
      const json& c = creases[i];
      const std::string crease_where = sub_where + ".creases[" + std::to_string(i) + "]";
      if (!c.is_array() || c.size() != 3 || !c[0].is_number_unsigned() || !c[1].is_number_unsigned() ||
          !c[2].is_number() || c[0].get<uint64_t>() > 0xfffffffeu || c[1].get<uint64_t>() > 0xfffffffeu)
        fail(crease_where + ": expected [vertex, vertex, sharpness], got " + one_line(c.dump()).substr(0, 60));
      const double sharpness = c[2].get<double>();
      if (!(sharpness >= 0.0) || !std::isfinite(sharpness)) fail(crease_where + ": sharpness must be finite and >= 0");
      request.creases.push_back({c[0].get<uint32_t>(), c[1].get<uint32_t>(), float(std::min(sharpness, 10.0))});
    }
  }
  return request;
}

// ---------------------------------------------------------------------------------------------
// Meshes.

// One primitive as a triangle list.
struct PrimitiveData {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty when the primitive has none
  std::vector<uint32_t> corners;   // 3 per triangle
};

PrimitiveData read_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                             const std::string& where) {
  PrimitiveData data;
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) fail(where + ": no POSITION attribute");
  try {
    data.positions = gltf::read_vec3(model, position->second);
    if (const auto normal = primitive.attributes.find("NORMAL"); normal != primitive.attributes.end()) {
      data.normals = gltf::read_vec3(model, normal->second);
      if (data.normals.size() != data.positions.size())
        fail("NORMAL has " + std::to_string(data.normals.size()) + " elements, POSITION has " +
             std::to_string(data.positions.size()));
    }
    std::vector<uint32_t> indices;
    if (primitive.indices >= 0) {
      indices = gltf::read_indices(model, primitive.indices);
    } else {
      indices.resize(data.positions.size());
      std::iota(indices.begin(), indices.end(), 0u);
    }
    for (size_t i = 0; i < indices.size(); ++i)
      if (indices[i] >= data.positions.size())
        fail("vertex index " + std::to_string(indices[i]) + " at position " + std::to_string(i) + " out of range (" +
             std::to_string(data.positions.size()) + " vertices)");
    const int mode = primitive.mode == -1 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    const size_t n = indices.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (n % 3 != 0) fail("index count " + std::to_string(n) + " is not a multiple of 3");
      data.corners = std::move(indices);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t i = 0; i + 2 < n; ++i) {  // every other triangle flips to keep the winding
        const bool odd = i % 2 == 1;
        data.corners.insert(data.corners.end(), {indices[i], indices[i + (odd ? 2 : 1)], indices[i + (odd ? 1 : 2)]});
      }
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
      for (size_t i = 1; i + 1 < n; ++i)
        data.corners.insert(data.corners.end(), {indices[i], indices[i + 1], indices[0]});
    } else if (mode >= 0 && mode <= 3) {
      fail(std::string("primitive mode ") + std::to_string(mode) + " (points or lines) is not supported");
    } else {
      fail("invalid primitive mode " + std::to_string(mode));
    }
  } catch (const std::runtime_error& e) {
    fail(where + ": " + e.what());
  }
  return data;
}

glm::vec3 face_normal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 n = glm::cross(b - a, c - a);
  const float length = glm::length(n);
  return length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

// Unit shading normals; a zero normal is replaced by the area-weighted normal of its triangles.
uint32_t repair_normals(PrimitiveData& data) {
  uint32_t repaired = 0;
  std::vector<glm::vec3> face_sum;
  for (glm::vec3& n : data.normals) {
    const float length = glm::length(n);
    if (length > 1e-20f && std::isfinite(length)) {
      n /= length;
      continue;
    }
    if (face_sum.empty()) {
      face_sum.assign(data.positions.size(), glm::vec3(0.0f));
      for (size_t t = 0; t + 2 < data.corners.size(); t += 3) {
        const uint32_t* v = &data.corners[t];
        const glm::vec3 area_normal =
            glm::cross(data.positions[v[1]] - data.positions[v[0]], data.positions[v[2]] - data.positions[v[0]]);
        for (int k = 0; k < 3; ++k) face_sum[v[k]] += area_normal;
      }
    }
    const size_t vertex = size_t(&n - data.normals.data());
    const float sum_length = glm::length(face_sum[vertex]);
    n = sum_length > 0.0f && std::isfinite(sum_length) ? face_sum[vertex] / sum_length : glm::vec3(0.0f, 0.0f, 1.0f);
    ++repaired;
  }
  return repaired;
}

// The primitive as a welded control cage for OpenSubdiv.
ControlMesh build_cage(const PrimitiveData& data, const MeshRequest& request, const std::string& where) {
  std::vector<glm::uvec3> triangles_of_cage(data.corners.size() / 3);
  for (size_t t = 0; t < triangles_of_cage.size(); ++t)
    triangles_of_cage[t] = {data.corners[3 * t], data.corners[3 * t + 1], data.corners[3 * t + 2]};
  const Weld weld = weld_mesh(data.positions, triangles_of_cage);
  ControlMesh cage;
  cage.positions = weld.positions;
  const size_t triangles = data.corners.size() / 3;
  auto add_face = [&](std::initializer_list<uint32_t> corners) {
    std::vector<uint32_t> face;
    for (uint32_t c : corners) face.push_back(weld.remap[c]);
    for (size_t i = 0; i < face.size(); ++i)
      for (size_t j = i + 1; j < face.size(); ++j)
        if (face[i] == face[j])
          fail(where + ": cage face " + std::to_string(cage.face_sizes.size()) +
               " is degenerate (a vertex repeats after welding)");
    cage.face_sizes.push_back(uint32_t(face.size()));
    cage.face_indices.insert(cage.face_indices.end(), face.begin(), face.end());
  };
  if (request.quads) {
    if (triangles % 2 != 0) fail(where + ": quads need an even triangle count, got " + std::to_string(triangles));
    for (size_t t = 0; t < triangles; t += 2) {
      const uint32_t* a = &data.corners[3 * t];
      const uint32_t* b = &data.corners[3 * t + 3];
      if (b[0] != a[0] || b[1] != a[2])
        fail(where + ": triangles " + std::to_string(t) + " and " + std::to_string(t + 1) +
             " do not form a quad (expected (a,b,c),(a,c,d))");
      add_face({a[0], a[1], a[2], b[2]});
    }
  } else {
    for (size_t t = 0; t < triangles; ++t)
      add_face({data.corners[3 * t], data.corners[3 * t + 1], data.corners[3 * t + 2]});
  }
  for (const Crease& crease : request.creases) {
    if (crease.v0 >= data.positions.size() || crease.v1 >= data.positions.size())
      fail(where + ": crease vertex " + std::to_string(std::max(crease.v0, crease.v1)) + " out of range (" +
           std::to_string(data.positions.size()) + " vertices)");
    const uint32_t v0 = weld.remap[crease.v0], v1 = weld.remap[crease.v1];
    if (v0 == v1)
      fail(where + ": crease (" + std::to_string(crease.v0) + ", " + std::to_string(crease.v1) +
           ") joins a vertex to itself");
    cage.creases.push_back({v0, v1, crease.sharpness});
  }
  return cage;
}

struct BuiltMesh {
  Mesh mesh;
  std::vector<std::string> repairs;
};

// `refined_budget`: how many more triangles subdivision may make in this scene.
BuiltMesh build_mesh(const tinygltf::Model& model, const json& document, size_t mesh_index, uint32_t default_material,
                     const LoadOptions& options, uint64_t& refined_budget) {
  const tinygltf::Mesh& source = model.meshes[mesh_index];
  BuiltMesh built;
  Mesh& mesh = built.mesh;
  mesh.name = source.name.empty() ? "mesh" + std::to_string(mesh_index) : source.name;
  const std::string where = "mesh '" + mesh.name + "'";
  const MeshRequest request = read_mesh_request(document["meshes"][mesh_index], where, options);
  mesh.sharp_angle_degrees = request.sharp_angle_degrees;
  mesh.subdivided = request.subdivide;
  mesh.subdivision.scheme = request.scheme;
  mesh.subdivision.level = request.level;
  mesh.subdivision.crease_count = uint32_t(request.creases.size());

  bool any_normals = request.subdivide;
  for (const auto& primitive : source.primitives) any_normals |= primitive.attributes.count("NORMAL") > 0;
  uint32_t normals_repaired = 0;

  for (size_t p = 0; p < source.primitives.size(); ++p) {
    const tinygltf::Primitive& primitive = source.primitives[p];
    const std::string primitive_where = where + " primitive " + std::to_string(p);
    PrimitiveData data = read_primitive(model, primitive, primitive_where);
    const uint32_t first_vertex = uint32_t(mesh.positions.size());
    const uint32_t first_triangle = uint32_t(mesh.triangles.size());
    if (request.subdivide) {
      const ControlMesh cage = build_cage(data, request, primitive_where);
      mesh.subdivision.control_faces += uint32_t(cage.face_sizes.size());
      // At most 2 * 4^level triangles per cage face (quads split in two; triangles give 3 quads at level 1).
      const uint64_t refined_triangles = uint64_t(cage.face_sizes.size()) << (2 * request.level + 1);
      if (refined_triangles > refined_budget)
        fail(primitive_where + ": subdivision level " + std::to_string(request.level) + " would make up to " +
             std::to_string(refined_triangles) + " triangles (limit " + std::to_string(kMaxRefinedTriangles) +
             " for the scene)");
      refined_budget -= refined_triangles;
      const uint64_t scene_refined = kMaxRefinedTriangles - refined_budget;
      check_memory_estimate(primitive_where,
                            "subdivision level " + std::to_string(request.level) + " (up to " +
                                std::to_string(scene_refined) + " refined triangles in the scene)",
                            double(scene_refined) * kBytesPerRefinedTriangle, options.memory_limit);
      SubdividedMesh refined;
      try {
        refined = subdivide(cage, request.scheme, request.level);
      } catch (const std::exception& e) {
        fail(primitive_where + ": subdivision failed: " + e.what());
      }
      if (refined.normals.size() != refined.positions.size())
        fail(primitive_where + ": subdivision returned no normals");
      mesh.positions.insert(mesh.positions.end(), refined.positions.begin(), refined.positions.end());
      mesh.normals.insert(mesh.normals.end(), refined.normals.begin(), refined.normals.end());
      for (const glm::uvec3& t : refined.triangles) mesh.triangles.push_back(t + first_vertex);
    } else if (any_normals && data.normals.empty()) {
      // Others have normals, this one not: flat normals, one vertex per corner (glTF's rule).
      for (size_t t = 0; t < data.corners.size(); t += 3) {
        const glm::vec3 a = data.positions[data.corners[t]], b = data.positions[data.corners[t + 1]],
                        c = data.positions[data.corners[t + 2]];
        const glm::vec3 n = face_normal(a, b, c);
        const uint32_t v = uint32_t(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {a, b, c});
        mesh.normals.insert(mesh.normals.end(), {n, n, n});
        mesh.triangles.emplace_back(v, v + 1, v + 2);
      }
    } else {
      normals_repaired += repair_normals(data);
      mesh.positions.insert(mesh.positions.end(), data.positions.begin(), data.positions.end());
      mesh.normals.insert(mesh.normals.end(), data.normals.begin(), data.normals.end());
      for (size_t t = 0; t < data.corners.size(); t += 3)
        mesh.triangles.emplace_back(data.corners[t] + first_vertex, data.corners[t + 1] + first_vertex,
                                    data.corners[t + 2] + first_vertex);
    }
    if (mesh.positions.size() >= size_t(kNone)) fail(where + ": more than 2^32 vertices");
    const uint32_t count = uint32_t(mesh.triangles.size()) - first_triangle;
    const uint32_t material = primitive.material >= 0 ? uint32_t(primitive.material) : default_material;
    if (count == 0) continue;
    if (!mesh.materials.empty() && mesh.materials.back().material == material)
      mesh.materials.back().triangle_count += count;
    else
      mesh.materials.push_back({first_triangle, count, material});
  }
  if (!any_normals) mesh.normals.clear();
  if (normals_repaired > 0)
    built.repairs.push_back(where + ": replaced " + std::to_string(normals_repaired) +
                            " zero-length normals by face normals");
  mesh.degenerate_triangles_dropped = drop_degenerate_triangles(mesh);
  if (mesh.degenerate_triangles_dropped > 0)
    built.repairs.push_back(where + ": dropped " + std::to_string(mesh.degenerate_triangles_dropped) +
                            " degenerate triangles");
  return built;
}

// ---------------------------------------------------------------------------------------------
// Cameras and lights from node transforms.

struct Frame {
  glm::vec3 position, forward, up;
};

// glTF cameras and lights look down their local -Z, with +Y up.
Frame node_frame(const glm::dmat4& world, const std::string& where) {
  const glm::dvec3 position(world[3]);
  glm::dvec3 forward = glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);
  glm::dvec3 up = glm::dmat3(world) * glm::dvec3(0.0, 1.0, 0.0);
  const double forward_length = glm::length(forward);
  if (!(forward_length > 1e-12)) fail(where + ": transform collapses the viewing direction");
  forward /= forward_length;
  up -= glm::dot(up, forward) * forward;
  const double up_length = glm::length(up);
  if (!(up_length > 1e-12)) fail(where + ": transform collapses the up direction");
  up /= up_length;
  if (!finite(position) || !finite(forward) || !finite(up)) fail(where + ": transform is not finite");
  return {glm::vec3(position), glm::vec3(forward), glm::vec3(up)};
}

Camera convert_camera(const tinygltf::Camera& source, size_t camera_index, const tinygltf::Node& node,
                      const glm::dmat4& world, size_t node_index) {
  const std::string where = "camera " + std::to_string(camera_index);
  if (source.type == "orthographic") fail(where + ": orthographic cameras are not supported");
  if (source.type != "perspective") fail(where + ": unknown camera type '" + source.type + "'");
  const tinygltf::PerspectiveCamera& p = source.perspective;
  if (!(p.yfov > 0.0 && p.yfov < kPi)) fail(where + ": yfov " + std::to_string(p.yfov) + " must be in (0, pi)");
  if (!(p.znear > 0.0 && fits_float(p.znear))) fail(where + ": znear must be finite and > 0");
  if (p.zfar != 0.0 && !(p.zfar > p.znear && std::isfinite(p.zfar))) fail(where + ": zfar must be > znear");
  if (!(p.aspectRatio >= 0.0 && std::isfinite(p.aspectRatio))) fail(where + ": aspectRatio must be > 0");
  const Frame frame = node_frame(world, "node " + std::to_string(node_index));
  Camera camera;
  camera.name = !source.name.empty() ? source.name : !node.name.empty() ? node.name : where;
  camera.eye = frame.position;
  camera.target = frame.position + frame.forward;
  camera.up = frame.up;
  camera.yfov_degrees = float(p.yfov * 180.0 / kPi);
  camera.znear = float(p.znear);
  // The checks above are in double: a yfov or znear of 1e-300 passes them and is 0 as a float.
  const std::string problem = camera_problem(camera);
  if (!problem.empty()) fail(where + ": " + problem + " (as 32-bit floats: yfov " + std::to_string(p.yfov) + ", znear " +
                             std::to_string(p.znear) + ")");
  return camera;
}

PunctualLight convert_light(const json& source, size_t light_index, const tinygltf::Node& node, const glm::dmat4& world,
                            size_t node_index) {
  const std::string where = "light " + std::to_string(light_index);
  PunctualLight light;
  light.name = source.contains("name") ? source["name"].get<std::string>() : "";
  if (light.name.empty()) light.name = !node.name.empty() ? node.name : where;
  if (!source.contains("type")) fail(where + ": no type");
  const std::string type = source["type"].get<std::string>();
  if (type == "point")
    light.type = LightType::point;
  else if (type == "spot")
    light.type = LightType::spot;
  else if (type == "directional")
    light.type = LightType::directional;
  else
    fail(where + ": unknown light type '" + type + "'");
  glm::dvec3 color(1.0);
  if (source.contains("color"))
    color = glm::dvec3(source["color"][0].get<double>(), source["color"][1].get<double>(),
                       source["color"][2].get<double>());
  if (!finite(color) || color.x < 0.0 || color.y < 0.0 || color.z < 0.0)
    fail(where + ": color must be finite and >= 0");
  const double intensity = source.value("intensity", 1.0);
  if (!(intensity >= 0.0) || !std::isfinite(intensity)) fail(where + ": intensity must be finite and >= 0");
  if (!finite(color * intensity)) fail(where + ": color * intensity is not finite");
  light.intensity = glm::vec3(color * intensity);
  const double range = source.value("range", 0.0);
  if (source.contains("range") && !(range > 0.0 && fits_float(range))) fail(where + ": range must be finite and > 0");
  light.range = float(range);
  if (light.type == LightType::spot) {
    const json spot = source.value("spot", json::object());
    const double inner = spot.value("innerConeAngle", 0.0), outer = spot.value("outerConeAngle", kPi / 4.0);
    if (!(inner >= 0.0 && inner < outer && outer <= kPi / 2.0))
      fail(where + ": spot cone angles need 0 <= inner < outer <= pi/2");
    light.inner_cone_cos = float(std::cos(inner));
    light.outer_cone_cos = float(std::cos(outer));
  }
  light.position = glm::vec3(world[3]);
  if (light.type != LightType::point) light.direction = node_frame(world, "node " + std::to_string(node_index)).forward;
  return light;
}

// With no camera in the file: look at the world bounds' centre down -Z, from the distance at which
// the bounding sphere fills the 45-degree vertical field of view (docs/scene-format.md).
Camera default_camera(const Bounds& bounds) {
  const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
  float radius = 0.5f * glm::length(bounds.max - bounds.min);
  if (!(radius > 0.0f)) radius = 1.0f;
  Camera camera;
  camera.name = "default";
  camera.yfov_degrees = 45.0f;
  const float distance = radius / std::sin(0.5f * glm::radians(camera.yfov_degrees));
  camera.eye = centre + glm::vec3(0.0f, 0.0f, distance);
  camera.target = centre;
  camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  camera.znear = 0.001f * radius;
  return camera;
}

glm::vec3 read_vec3_json(const json& object, const char* key, const std::string& where) {
  if (!object.contains(key)) fail(where + "." + key + ": missing");
  const json& v = object[key];
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    fail(where + "." + key + ": expected an array of 3 numbers");
  const glm::dvec3 d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  if (!finite(d)) fail(where + "." + key + ": not finite");
  return glm::vec3(d);
}

// True when `holder` (a glTF object) carries extras.epi.camera_path.
bool has_camera_path(const json& holder) {
  return holder.is_object() && holder.contains("extras") && holder["extras"].is_object() &&
         holder["extras"].contains("epi") && holder["extras"]["epi"].is_object() &&
         holder["extras"]["epi"].contains("camera_path");
}

// The camera path in `holder`'s extras (`prefix` names the holder in messages).
std::vector<Camera> read_camera_path(const json& holder, const std::string& prefix, float znear) {
  std::vector<Camera> path;
  if (!holder.contains("extras") || !holder["extras"].is_object() || !holder["extras"].contains("epi"))
    return path;
  const json& epi = holder["extras"]["epi"];
  if (!epi.is_object()) fail(prefix + "extras.epi: expected an object, got " + describe_json(epi));
  if (!epi.contains("camera_path")) return path;
  const json& entries = epi["camera_path"];
  if (!entries.is_array()) fail(prefix + "extras.epi.camera_path: expected an array, got " + describe_json(entries));
  for (size_t i = 0; i < entries.size(); ++i) {
    const std::string where = prefix + "extras.epi.camera_path[" + std::to_string(i) + "]";
    const json& entry = entries[i];
    if (!entry.is_object()) fail(where + ": expected an object, got " + describe_json(entry));
    Camera camera;
    camera.name = "path" + std::to_string(i);
    camera.eye = read_vec3_json(entry, "eye", where);
    camera.target = read_vec3_json(entry, "target", where);
    if (entry.contains("up")) camera.up = read_vec3_json(entry, "up", where);
    if (entry.contains("yfov")) {
      if (!entry["yfov"].is_number()) fail(where + ".yfov: expected a number, got " + describe_json(entry["yfov"]));
      camera.yfov_degrees = entry["yfov"].get<float>();
      if (!(camera.yfov_degrees > 0.0f && camera.yfov_degrees < 180.0f))
        fail(where + ".yfov: must be in (0, 180) degrees");
    }
    camera.znear = znear;
    const std::string problem = camera_problem(camera);
    if (!problem.empty()) fail(where + ": " + problem);
    path.push_back(camera);
  }
  return path;
}

// Object names: node name, else mesh name, else node<i>; repeats get "#2", "#3"...
std::string unique_name(std::string name, std::map<std::string, int>& used) {
  if (used.emplace(name, 1).second) return name;
  for (int n = ++used[name];; n = ++used[name]) {
    std::string candidate = name + "#" + std::to_string(n);
    if (used.emplace(candidate, 1).second) return candidate;
  }
}

// ---------------------------------------------------------------------------------------------

Scene load(const std::filesystem::path& file, const LoadOptions& options) {
  if (options.subdiv_level_override > kMaxSubdivisionLevel)
    fail("subdivision level override " + std::to_string(options.subdiv_level_override) + " is outside [0, " +
         std::to_string(kMaxSubdivisionLevel) + "]");
  const FileContents contents = read_file(file);
  json document;
  try {
    document = json::parse(contents.json_text);
  } catch (const json::exception& e) {
    fail(std::string("invalid JSON: ") + e.what());
  }
  gltf::check_json_types(document);
  if (!document.contains("asset") || !document["asset"].contains("version")) fail("asset.version is missing");
  const std::string version = document["asset"]["version"].get<std::string>();
  if (version.rfind("2.", 0) != 0) fail("glTF version " + version + " is not supported (need 2.x)");
  for (const json& name : document.value("extensionsRequired", json::array()))
    if (!kSupportedRequiredExtensions.count(name.get<std::string>()))
      fail("required extension " + name.get<std::string>() + " is not supported");

  if (document.contains("nodes")) {
    const json& nodes = document["nodes"];
    for (size_t i = 0; i < nodes.size(); ++i) {  // tinygltf drops TRS silently when a matrix is present
      const json& node = nodes[i];
      if (node.contains("matrix") &&
          (node.contains("translation") || node.contains("rotation") || node.contains("scale")))
        fail("node " + std::to_string(i) + " has both a matrix and translation/rotation/scale");
    }
  }

  if (document.contains("extensions") && document["extensions"].contains("KHR_lights_punctual")) {
    const json& lights = document["extensions"]["KHR_lights_punctual"].value("lights", json::array());
    for (size_t i = 0; i < lights.size(); ++i) {
      if (!lights[i].contains("type")) fail("light " + std::to_string(i) + ": 'type' is missing");
      if (lights[i].value("type", "") == "spot" && !lights[i].contains("spot"))
        fail("light " + std::to_string(i) + ": a spot light needs a 'spot' object");
    }
  }
  check_buffers(document, contents, file);

  const tinygltf::Model model = parse_with_tinygltf(contents, file);
  check_model(model);
  const std::vector<int> parent = check_node_forest(model);

  if (model.scenes.empty()) fail("empty scene: the file has no scenes");
  const int scene_index = model.defaultScene >= 0 ? model.defaultScene : 0;
  check_index(scene_index, model.scenes.size(), "scene", "scene");
  const std::vector<NodeVisit> visits = walk_scene(model, model.scenes[size_t(scene_index)], parent);

  Scene scene;
  scene.source = file.string();

  // Materials: all of the file's, plus a default one if some primitive in use has none.
  for (size_t i = 0; i < model.materials.size(); ++i)
    scene.materials.push_back(convert_material(model.materials[i], document["materials"][i], i));
  uint32_t default_material = kNone;
  for (const NodeVisit& visit : visits) {
    const int m = model.nodes[visit.node].mesh;
    if (m < 0) continue;
    for (const auto& primitive : model.meshes[size_t(m)].primitives)
      if (primitive.material < 0 && default_material == kNone) {
        default_material = uint32_t(scene.materials.size());
        scene.materials.push_back(Material{.name = "default"});
      }
  }

  // Meshes (once per glTF mesh, in order of first use) and objects.
  std::map<size_t, uint32_t> mesh_of;  // glTF mesh -> scene mesh, kNone when it has no triangles
  std::map<std::string, int> names;
  std::map<size_t, size_t> objects_dropped;
  uint64_t refined_budget = kMaxRefinedTriangles;
  for (const NodeVisit& visit : visits) {
    const tinygltf::Node& node = model.nodes[visit.node];
    if (node.mesh < 0) continue;
    const size_t gltf_mesh = size_t(node.mesh);
    if (!mesh_of.count(gltf_mesh)) {
      BuiltMesh built = build_mesh(model, document, gltf_mesh, default_material, options, refined_budget);
      scene.repairs.insert(scene.repairs.end(), built.repairs.begin(), built.repairs.end());
      if (built.mesh.triangles.empty()) {
        mesh_of[gltf_mesh] = kNone;
      } else {
        mesh_of[gltf_mesh] = uint32_t(scene.meshes.size());
        scene.meshes.push_back(std::move(built.mesh));
      }
    }
    if (mesh_of[gltf_mesh] == kNone) {
      objects_dropped[gltf_mesh]++;
      continue;
    }
    const std::string& mesh_name = model.meshes[gltf_mesh].name;
    Object object;
    object.name = unique_name(!node.name.empty()   ? node.name
                              : !mesh_name.empty() ? mesh_name
                                                   : "node" + std::to_string(visit.node),
                              names);
    object.mesh = mesh_of[gltf_mesh];
    object.object_to_world = glm::mat4(visit.world);
    scene.objects.push_back(object);
  }
  for (const auto& [gltf_mesh, count] : objects_dropped) {
    const std::string& name = model.meshes[gltf_mesh].name;
    scene.repairs.push_back("mesh '" + (name.empty() ? "mesh" + std::to_string(gltf_mesh) : name) +
                            "': no triangles, " + std::to_string(count) + " object(s) using it left out");
  }
  if (scene.triangle_count() == 0) fail("empty scene: no triangles in scene " + std::to_string(scene_index));

  // Cameras and punctual lights on the walked nodes.
  const json& lights_json = document.contains("extensions") && document["extensions"].contains("KHR_lights_punctual")
                                ? document["extensions"]["KHR_lights_punctual"].value("lights", json::array())
                                : json::array();
  for (const NodeVisit& visit : visits) {
    const tinygltf::Node& node = model.nodes[visit.node];
    if (node.camera >= 0)
      scene.cameras.push_back(
          convert_camera(model.cameras[size_t(node.camera)], size_t(node.camera), node, visit.world, visit.node));
    const json& node_json = document["nodes"][visit.node];
    if (node_json.contains("extensions") && node_json["extensions"].contains("KHR_lights_punctual")) {
      const json& reference = node_json["extensions"]["KHR_lights_punctual"];
      if (!reference.contains("light"))
        fail("node " + std::to_string(visit.node) + ": KHR_lights_punctual without light");
      const int light = reference["light"].get<int>();
      check_index(light, lights_json.size(), "light", "node " + std::to_string(visit.node));
      scene.punctual_lights.push_back(
          convert_light(lights_json[size_t(light)], size_t(light), node, visit.world, visit.node));
    }
  }
  const Bounds bounds = scene.world_bounds();
  if (!finite(glm::dvec3(bounds.min)) || !finite(glm::dvec3(bounds.max))) fail("world bounds are not finite");
  if (scene.cameras.empty()) scene.cameras.push_back(default_camera(bounds));
  // The chosen scene's extras first, then the document's.
  const float path_znear = 0.001f * std::max(0.5f * glm::length(bounds.max - bounds.min), 1e-6f);
  const json& scene_json = document["scenes"][size_t(scene_index)];
  scene.camera_path = has_camera_path(scene_json)
                          ? read_camera_path(scene_json, "scenes[" + std::to_string(scene_index) + "].", path_znear)
                          : read_camera_path(document, "", path_znear);

  bool any_emissive = false;
  for (const Material& material : scene.materials) any_emissive |= material.emissive();
  if (any_emissive) scene.area_lights = build_area_lights(scene);
  return scene;
}

}  // namespace

Scene load_scene(const std::filesystem::path& file, const LoadOptions& options) {
  try {
    return load(file, options);
  } catch (const std::exception& e) {
    throw SceneLoadError(one_line(file.string() + ": " + e.what()));
  }
}

}  // namespace epi

// Writes small glTF files for the tests: JSON built with nlohmann, one binary buffer,
// saved as .gltf with an external .bin, as .gltf with a data: URI, or as .glb.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace epi::test {

using nlohmann::json;

// A fresh folder per test, removed at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("epi_gltf_" + std::to_string(getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

class GltfBuilder {
 public:
  json doc = {{"asset", {{"version", "2.0"}}}};
  std::vector<unsigned char> bin;

  // Appends raw bytes (4-byte aligned) as a buffer view; returns its index.
  int add_view(const void* data, size_t bytes, size_t stride = 0) {
    while (bin.size() % 4 != 0) bin.push_back(0);
    json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (stride != 0) view["byteStride"] = stride;
    const auto* p = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), p, p + bytes);
    doc["bufferViews"].push_back(view);
    return int(doc["bufferViews"].size()) - 1;
  }

  int add_accessor(int view, int component_type, size_t count, const char* type) {
    doc["accessors"].push_back({{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}});
    return int(doc["accessors"].size()) - 1;
  }

  int add_vec3(const std::vector<glm::vec3>& values) {
    const int view = add_view(values.data(), values.size() * sizeof(glm::vec3));
    return add_accessor(view, 5126, values.size(), "VEC3");
  }

  // Indices stored with the given component type (5121 ubyte, 5123 ushort, 5125 uint).
  int add_indices(const std::vector<uint32_t>& indices, int component_type = 5125) {
    std::vector<unsigned char> bytes;
    const size_t size = component_type == 5121 ? 1 : component_type == 5123 ? 2 : 4;
    for (uint32_t i : indices) {
      unsigned char b[4];
      std::memcpy(b, &i, 4);
      bytes.insert(bytes.end(), b, b + size);
    }
    const int view = add_view(bytes.data(), bytes.size());
    return add_accessor(view, component_type, indices.size(), "SCALAR");
  }

  // A one-primitive mesh; returns its index.
  int add_mesh(const std::string& name, const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices,
               int material = -1, const std::vector<glm::vec3>& normals = {}) {
    json mesh = {{"primitives", json::array({make_primitive(positions, indices, material, normals)})}};
    if (!name.empty()) mesh["name"] = name;
    doc["meshes"].push_back(mesh);
    return int(doc["meshes"].size()) - 1;
  }

  json make_primitive(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices, int material = -1,
                      const std::vector<glm::vec3>& normals = {}) {
    json primitive = {{"attributes", {{"POSITION", add_vec3(positions)}}}};
    if (!normals.empty()) primitive["attributes"]["NORMAL"] = add_vec3(normals);
    if (!indices.empty()) primitive["indices"] = add_indices(indices);
    if (material >= 0) primitive["material"] = material;
    return primitive;
  }

  int add_node(json node) {
    doc["nodes"].push_back(node);
    return int(doc["nodes"].size()) - 1;
  }

  int add_material(json material) {
    doc["materials"].push_back(material);
    return int(doc["materials"].size()) - 1;
  }

  void set_scene(const std::vector<int>& roots) {
    doc["scenes"] = json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  // .gltf with the buffer in `<stem>.bin` beside it.
  std::filesystem::path write_gltf(const std::filesystem::path& file) {
    json out = doc;
    if (!bin.empty()) {
      const std::string bin_name = file.stem().string() + ".bin";
      write_bytes(file.parent_path() / bin_name, bin);
      out["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", bin_name}}});
    }
    write_text(file, out.dump(1));
    return file;
  }

  // .gltf with the buffer as a base64 data: URI.
  std::filesystem::path write_embedded(const std::filesystem::path& file) {
    json out = doc;
    if (!bin.empty())
      out["buffers"] = json::array(
          {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
    write_text(file, out.dump());
    return file;
  }

  std::filesystem::path write_glb(const std::filesystem::path& file) {
    json out = doc;
    if (!bin.empty()) out["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string text = out.dump();
    while (text.size() % 4 != 0) text += ' ';
    std::vector<unsigned char> body = bin;
    while (body.size() % 4 != 0) body.push_back(0);
    std::vector<unsigned char> glb;
    auto u32 = [&](uint32_t v) {
      unsigned char b[4];
      std::memcpy(b, &v, 4);
      glb.insert(glb.end(), b, b + 4);
    };
    const uint32_t total = uint32_t(12 + 8 + text.size() + (body.empty() ? 0 : 8 + body.size()));
    glb.insert(glb.end(), {'g', 'l', 'T', 'F'});
    u32(2);
    u32(total);
    u32(uint32_t(text.size()));
    u32(0x4E4F534Au);
    glb.insert(glb.end(), text.begin(), text.end());
    if (!body.empty()) {
      u32(uint32_t(body.size()));
      u32(0x004E4942u);
      glb.insert(glb.end(), body.begin(), body.end());
    }
    write_bytes(file, glb);
    return file;
  }

  static void write_text(const std::filesystem::path& file, const std::string& text) {
    std::ofstream(file, std::ios::binary) << text;
  }
  static void write_bytes(const std::filesystem::path& file, const std::vector<unsigned char>& bytes) {
    std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), long(bytes.size()));
  }
  static std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
      uint32_t v = uint32_t(bytes[i]) << 16;
      if (i + 1 < bytes.size()) v |= uint32_t(bytes[i + 1]) << 8;
      if (i + 2 < bytes.size()) v |= bytes[i + 2];
      out += table[(v >> 18) & 63];
      out += table[(v >> 12) & 63];
      out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
      out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
  }
};

// Shapes used by several tests.
inline std::vector<glm::vec3> unit_quad_positions() {  // in the z = 0 plane, facing +Z
  return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
}
inline std::vector<uint32_t> unit_quad_indices() { return {0, 1, 2, 0, 2, 3}; }

// A unit cube [-0.5, 0.5]^3 as 24 vertices (4 per face, split at the seams as exporters do)
// and 12 triangles ordered as quad pairs (a,b,c),(a,c,d), counter-clockwise seen from outside.
inline void unit_cube(std::vector<glm::vec3>& positions, std::vector<uint32_t>& indices) {
  const glm::vec3 axes[6][3] = {// normal, u, v with u x v = normal
                                {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                                {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
                                {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}}};
  positions.clear();
  indices.clear();
  for (const auto& face : axes) {
    const uint32_t base = uint32_t(positions.size());
    const glm::vec3 c = 0.5f * face[0], u = 0.5f * face[1], v = 0.5f * face[2];
    positions.insert(positions.end(), {c - u - v, c + u - v, c + u + v, c - u + v});
    indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
}

}  // namespace epi::test

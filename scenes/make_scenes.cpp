// make_scenes OUTPUT_DIR: writes the bundled glTF 2.0 scenes (see README.md), deterministically.
// Each scene is one .gltf file with its buffer embedded as a base64 data: URI. Curved objects are
// stored as coarse subdivision cages (mesh extras.epi.subdivision); objects that rest on or touch
// each other are placed from their limit surfaces, computed here with epi::subdivide.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "scene/subdivide.h"

namespace {

using json = nlohmann::ordered_json;
using glm::mat4;
using glm::uvec3;
using glm::vec3;
using glm::vec4;
constexpr float kPi = std::numbers::pi_v<float>;

float radians(float degrees) { return degrees * kPi / 180.0f; }

// The shortest decimal that reads back as the same float, so the files stay readable and exact.
json number(float value) {
  if (value == 0.0f) return 0.0;
  char text[32];
  for (int digits = 1; digits <= 9; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, double(value));
    if (std::strtof(text, nullptr) == value) break;
  }
  return std::strtod(text, nullptr);
}
json numbers(const vec3& v) { return json::array({number(v.x), number(v.y), number(v.z)}); }

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t b0 = bytes[i], b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0, b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const uint32_t triple = b0 << 16 | b1 << 8 | b2;
    out += alphabet[triple >> 18 & 63];
    out += alphabet[triple >> 12 & 63];
    out += i + 1 < bytes.size() ? alphabet[triple >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? alphabet[triple & 63] : '=';
  }
  return out;
}

// Pretty-printed JSON with every array of plain numbers on one line: [1, 2, 3].
std::string inline_number_arrays(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '[') {
      const size_t close = text.find_first_of("[]{}\"", i + 1);
      if (close != std::string::npos && text[close] == ']') {
        std::string inside;
        for (size_t k = i + 1; k < close; ++k)
          if (text[k] != ' ' && text[k] != '\n') inside += text[k] == ',' ? std::string(", ") : std::string(1, text[k]);
        out += "[" + inside + "]";
        i = close;
        continue;
      }
    }
    out += text[i];
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Geometry: polygon meshes in object space.

struct Polygons {
  std::vector<vec3> positions;
  std::vector<std::vector<uint32_t>> faces;  // counter-clockwise seen from outside
  std::vector<epi::Crease> creases;

  uint32_t vertex(const vec3& p) {
    positions.push_back(p);
    return uint32_t(positions.size() - 1);
  }
  // Appends `other` transformed; a mirroring transform reverses the faces to keep them outward.
  void append(const Polygons& other, const mat4& transform = mat4(1.0f)) {
    const uint32_t base = uint32_t(positions.size());
    const bool mirrored = glm::determinant(glm::mat3(transform)) < 0.0f;
    for (const vec3& p : other.positions) positions.push_back(vec3(transform * glm::vec4(p, 1.0f)));
    for (auto face : other.faces) {
      for (uint32_t& v : face) v += base;
      if (mirrored) std::reverse(face.begin(), face.end());
      faces.push_back(face);
    }
    for (epi::Crease c : other.creases) creases.push_back({c.v0 + base, c.v1 + base, c.sharpness});
  }
  bool all_quads() const {
    for (const auto& f : faces)
      if (f.size() != 4) return false;
    return true;
  }
  epi::ControlMesh cage() const {
    epi::ControlMesh cage;
    cage.positions = positions;
    for (const auto& f : faces) {
      cage.face_sizes.push_back(uint32_t(f.size()));
      cage.face_indices.insert(cage.face_indices.end(), f.begin(), f.end());
    }
    cage.creases = creases;
    return cage;
  }
};

// Axis-aligned box, outward faces.
Polygons box(const vec3& lo, const vec3& hi) {
  Polygons b;
  for (int i = 0; i < 8; ++i) b.vertex({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  b.faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  return b;
}

// A closed solid from a 2D grid of cells (u breaks x v breaks, `filled` picks the cells) extruded
// from w0 to w1: walls with doorways, rings of walls. Manifold as long as filled cells never meet
// only at a corner; outward faces.
template <class Filled>
Polygons extrude_cells(const std::vector<float>& us, const std::vector<float>& vs, float w0, float w1, Filled filled) {
  Polygons p;
  const int nu = int(us.size()), nv = int(vs.size());
  std::vector<int> ids(size_t(nu * nv * 2), -1);
  auto vertex = [&](int i, int j, int side) {
    int& id = ids[size_t((i * nv + j) * 2 + side)];
    if (id < 0) id = int(p.vertex({us[size_t(i)], vs[size_t(j)], side ? w1 : w0}));
    return uint32_t(id);
  };
  auto cell = [&](int i, int j) { return i >= 0 && j >= 0 && i + 1 < nu && j + 1 < nv && filled(i, j); };
  for (int i = 0; i + 1 < nu; ++i)
    for (int j = 0; j + 1 < nv; ++j) {
      if (!cell(i, j)) continue;
      const int corner[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};  // counter-clockwise in (u, v)
      const int across[4][2] = {{i, j - 1}, {i + 1, j}, {i, j + 1}, {i - 1, j}};  // the cell beyond each side
      p.faces.push_back({vertex(i, j, 1), vertex(i + 1, j, 1), vertex(i + 1, j + 1, 1), vertex(i, j + 1, 1)});
      p.faces.push_back({vertex(i, j, 0), vertex(i, j + 1, 0), vertex(i + 1, j + 1, 0), vertex(i + 1, j, 0)});
      for (int e = 0; e < 4; ++e) {
        if (cell(across[e][0], across[e][1])) continue;
        const int* a = corner[e];
        const int* b = corner[(e + 1) % 4];
        p.faces.push_back({vertex(b[0], b[1], 1), vertex(a[0], a[1], 1), vertex(a[0], a[1], 0), vertex(b[0], b[1], 0)});
      }
    }
  return p;
}

// A quad facing towards `toward` (the winding is chosen so).
Polygons quad(const vec3& a, const vec3& b, const vec3& c, const vec3& d, const vec3& toward) {
  Polygons q;
  q.positions = {a, b, c, d};
  const vec3 normal = glm::cross(b - a, c - a);
  const vec3 centre = (a + b + c + d) * 0.25f;
  q.faces = {glm::dot(normal, toward - centre) > 0.0f ? std::vector<uint32_t>{0, 1, 2, 3} : std::vector<uint32_t>{3, 2, 1, 0}};
  return q;
}

// Horizontal floor square at y = 0 facing up.
Polygons floor_square(float half) {
  return quad({-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}, {0, 1, 0});
}

// Torus cage: ring in the xy plane around the z axis, stretched along x; quads outward.
Polygons torus(int major_steps, int minor_steps, float major_radius, float minor_radius, float stretch_x = 1.0f) {
  Polygons t;
  for (int i = 0; i < major_steps; ++i)
    for (int j = 0; j < minor_steps; ++j) {
      const float phi = 2.0f * kPi * float(i) / float(major_steps), theta = 2.0f * kPi * float(j) / float(minor_steps);
      const float ring = major_radius + minor_radius * std::cos(theta);
      t.vertex({stretch_x * ring * std::cos(phi), ring * std::sin(phi), minor_radius * std::sin(theta)});
    }
  auto id = [&](int i, int j) { return uint32_t((i % major_steps) * minor_steps + j % minor_steps); };
  for (int i = 0; i < major_steps; ++i)
    for (int j = 0; j < minor_steps; ++j) t.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return t;
}

// Capsule cage along x, all quads: rings of `around` vertices (one on top), closed by a pole at each end.
Polygons capsule(int around, float half_length, float radius) {
  Polygons c;
  const float xs[] = {-half_length - 0.8f * radius, -half_length, -0.5f * half_length, 0.0f,
                      0.5f * half_length, half_length, half_length + 0.8f * radius};
  const float rs[] = {0.75f * radius, radius, radius, radius, radius, radius, 0.75f * radius};
  const int rings = 7;
  for (int k = 0; k < rings; ++k)
    for (int j = 0; j < around; ++j) {
      const float a = 2.0f * kPi * float(j) / float(around);
      c.vertex({xs[k], rs[k] * std::sin(a), rs[k] * std::cos(a)});  // j = around/4: the top
    }
  auto id = [&](int k, int j) { return uint32_t(k * around + j % around); };
  for (int k = 0; k + 1 < rings; ++k)
    for (int j = 0; j < around; ++j) c.faces.push_back({id(k, j), id(k + 1, j), id(k + 1, j + 1), id(k, j + 1)});
  // Each end: a pole vertex and around/2 quads fanning around it (around must be even).
  const uint32_t first_pole = c.vertex({xs[0] - 0.3f * radius, 0, 0});
  const uint32_t last_pole = c.vertex({xs[rings - 1] + 0.3f * radius, 0, 0});
  for (int j = 0; j < around; j += 2) {
    c.faces.push_back({first_pole, id(0, j), id(0, j + 1), id(0, j + 2)});
    c.faces.push_back({last_pole, id(rings - 1, j + 2), id(rings - 1, j + 1), id(rings - 1, j)});
  }
  return c;
}

// Cube-sphere cage with `n` quads along each cube edge, displaced radially by `shape`.
template <class Shape>
Polygons blob(int n, Shape shape) {
  Polygons b;
  std::vector<int> id_of((n + 1) * (n + 1) * (n + 1), -1);
  auto vertex = [&](int i, int j, int k) {
    int& id = id_of[(i * (n + 1) + j) * (n + 1) + k];
    if (id < 0) {
      const vec3 cube = vec3(float(i), float(j), float(k)) * (2.0f / float(n)) - 1.0f;
      id = int(b.vertex(shape(glm::normalize(cube))));
    }
    return uint32_t(id);
  };
  // Each cube face as an (n x n) grid: a fixed axis at 0 or n, two running axes, outward winding.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) {
          auto corner = [&](int du, int dv) {
            int c[3];
            c[axis] = side * n;
            c[u_axis] = u + du;
            c[v_axis] = v + dv;
            return vertex(c[0], c[1], c[2]);
          };
          if (side == 1)
            b.faces.push_back({corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)});
          else
            b.faces.push_back({corner(0, 0), corner(0, 1), corner(1, 1), corner(1, 0)});
        }
    }
  return b;
}

// Octahedron (for Loop subdivision), outward triangles.
Polygons octahedron(float radius) {
  Polygons o;
  o.positions = {{radius, 0, 0}, {-radius, 0, 0}, {0, radius, 0}, {0, -radius, 0}, {0, 0, radius}, {0, 0, -radius}};
  o.faces = {{0, 2, 4}, {4, 2, 1}, {1, 2, 5}, {5, 2, 0}, {4, 3, 0}, {1, 3, 4}, {5, 3, 1}, {0, 3, 5}};
  return o;
}

// Limit surface bounds of a cage, for placing objects in contact.
struct Extent {
  vec3 min{1e30f}, max{-1e30f};
};
Extent limit_extent(const Polygons& p, epi::SubdivisionScheme scheme, int level, const mat4& transform = mat4(1.0f)) {
  const epi::SubdividedMesh refined = epi::subdivide(p.cage(), scheme, level);
  Extent e;
  for (const vec3& v : refined.positions) {
    const vec3 w = vec3(transform * glm::vec4(v, 1.0f));
    e.min = glm::min(e.min, w);
    e.max = glm::max(e.max, w);
  }
  return e;
}

// ---------------------------------------------------------------------------------------------
// glTF writer.

struct Subdivision {
  epi::SubdivisionScheme scheme = epi::SubdivisionScheme::catmull_clark;
  int level = 0;
};

struct Material {
  std::string name;
  vec3 base_color{0.8f};
  float metallic = 0.0f, roughness = 1.0f;
  vec3 emission{0.0f};  // linear radiance; stored as emissiveFactor (max 1) times emissive strength
};

struct CameraKey {
  vec3 eye, target, up{0, 1, 0};
  float yfov_degrees = 45.0f;
};

// Node placement looking from `eye` to `target`: the node's -z axis points at the target.
mat4 look_from(const vec3& eye, const vec3& target, const vec3& up = {0, 1, 0}) {
  return glm::inverse(glm::lookAt(eye, target, up));
}

class Gltf {
 public:
  explicit Gltf(std::string name) : name_(std::move(name)) {}

  int material(const Material& m) {
    json j = {{"name", m.name},
              {"pbrMetallicRoughness",
               {{"baseColorFactor", {number(m.base_color.r), number(m.base_color.g), number(m.base_color.b), 1.0}},
                {"metallicFactor", number(m.metallic)},
                {"roughnessFactor", number(m.roughness)}}}};
    const float peak = std::max({m.emission.r, m.emission.g, m.emission.b});
    if (peak > 0.0f) {
      j["emissiveFactor"] = numbers(m.emission / std::max(peak, 1.0f));
      if (peak > 1.0f) {
        j["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", number(peak)}}}};
        use_extension("KHR_materials_emissive_strength");
      }
    }
    materials_.push_back(j);
    return int(materials_.size() - 1);
  }

  // A mesh with one primitive per (polygons, material) part. Subdivided meshes have one part;
  // their quads are stored as triangle pairs (a,b,c),(a,c,d) and flagged "quads": true.
  int mesh(const std::string& name, const std::vector<std::pair<Polygons, int>>& parts,
           const Subdivision* subdivision = nullptr, float sharp_angle = 85.0f) {
    json primitives = json::array();
    for (const auto& [polygons, material] : parts) {
      std::vector<uint32_t> indices;
      for (const auto& f : polygons.faces)
        for (size_t i = 1; i + 1 < f.size(); ++i) indices.insert(indices.end(), {f[0], f[i], f[i + 1]});
      primitives.push_back({{"attributes", {{"POSITION", positions(polygons.positions)}}},
                            {"indices", index_accessor(indices, uint32_t(polygons.positions.size()))},
                            {"material", material},
                            {"mode", 4}});
    }
    json epi = {{"sharp_angle", number(sharp_angle)}};
    if (subdivision) {
      const Polygons& cage = parts.front().first;
      json creases = json::array();
      for (const epi::Crease& c : cage.creases) creases.push_back({c.v0, c.v1, number(c.sharpness)});
      const bool loop = subdivision->scheme == epi::SubdivisionScheme::loop;
      epi["subdivision"] = {{"scheme", loop ? "loop" : "catmull-clark"},
                            {"level", subdivision->level},
                            {"quads", !loop && cage.all_quads()},
                            {"creases", creases}};
      if (parts.size() != 1) fail("subdivided mesh " + name + " must have one primitive");
      if (!loop && !cage.all_quads()) fail("subdivided mesh " + name + " must be all quads");
      refined_triangles_.push_back(epi::subdivide(cage.cage(), subdivision->scheme, subdivision->level).triangles.size());
    } else {
      size_t triangles = 0;
      for (const auto& part : parts)
        for (const auto& f : part.first.faces) triangles += f.size() - 2;
      refined_triangles_.push_back(triangles);
    }
    meshes_.push_back({{"name", name}, {"primitives", primitives}, {"extras", {{"epi", epi}}}});
    return int(meshes_.size() - 1);
  }

  void object(const std::string& name, int mesh, const mat4& transform = mat4(1.0f)) {
    json node = {{"name", name}, {"mesh", mesh}};
    if (transform != mat4(1.0f)) node["matrix"] = matrix(transform);
    scene_triangles_ += refined_triangles_[size_t(mesh)];
    add_node(node);
  }

  void camera(const std::string& name, const CameraKey& key) {
    cameras_.push_back({{"name", name},
                        {"type", "perspective"},
                        {"perspective", {{"yfov", number(radians(key.yfov_degrees))}, {"znear", 0.01}}}});
    add_node({{"name", name}, {"camera", int(cameras_.size() - 1)}, {"matrix", matrix(look_from(key.eye, key.target, key.up))}});
  }

  void point_light(const std::string& name, const vec3& position, const vec3& color, float candela) {
    light(name, {{"type", "point"}}, color, candela, glm::translate(mat4(1.0f), position));
  }
  void spot_light(const std::string& name, const vec3& position, const vec3& target, const vec3& color, float candela,
                  float inner_degrees, float outer_degrees) {
    light(name,
          {{"type", "spot"},
           {"spot", {{"innerConeAngle", number(radians(inner_degrees))}, {"outerConeAngle", number(radians(outer_degrees))}}}},
          color, candela, look_from(position, target, std::abs(glm::normalize(target - position).y) > 0.99f ? vec3(1, 0, 0) : vec3(0, 1, 0)));
  }

  void camera_path(std::vector<CameraKey> keys) { camera_path_ = std::move(keys); }

  size_t triangles_after_subdivision() const { return scene_triangles_; }

  std::string text() const {
    json doc;
    doc["asset"] = {{"version", "2.0"}, {"generator", "epi make_scenes"}};
    if (!extensions_.empty()) doc["extensionsUsed"] = extensions_;
    json path = json::array();
    for (const CameraKey& k : camera_path_)
      path.push_back({{"eye", numbers(k.eye)}, {"target", numbers(k.target)}, {"up", numbers(k.up)}, {"yfov", number(k.yfov_degrees)}});
    doc["scene"] = 0;
    json scene = {{"name", name_}, {"nodes", roots_}};
    scene["extras"]["epi"]["camera_path"] = path;
    doc["scenes"] = json::array({scene});
    doc["nodes"] = nodes_;
    doc["meshes"] = meshes_;
    doc["materials"] = materials_;
    doc["cameras"] = cameras_;
    if (!lights_.empty()) doc["extensions"] = {{"KHR_lights_punctual", {{"lights", lights_}}}};
    doc["accessors"] = accessors_;
    doc["bufferViews"] = views_;
    doc["buffers"] = json::array(
        {{{"byteLength", bytes_.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes_)}}});
    return inline_number_arrays(doc.dump(1)) + "\n";
  }

  [[noreturn]] static void fail(const std::string& message) { throw std::runtime_error(message); }

 private:
  void use_extension(const std::string& name) {
    if (std::find(extensions_.begin(), extensions_.end(), name) == extensions_.end()) extensions_.push_back(name);
  }
  void add_node(const json& node) {
    nodes_.push_back(node);
    roots_.push_back(int(nodes_.size() - 1));
  }
  void light(const std::string& name, json light, const vec3& color, float intensity, const mat4& transform) {
    light["name"] = name;
    light["color"] = numbers(color);
    light["intensity"] = number(intensity);
    lights_.push_back(light);
    use_extension("KHR_lights_punctual");
    add_node({{"name", name}, {"matrix", matrix(transform)}, {"extensions", {{"KHR_lights_punctual", {{"light", int(lights_.size() - 1)}}}}}});
  }
  static json matrix(const mat4& m) {
    json out = json::array();
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) out.push_back(number(m[c][r]));
    return out;
  }
  int view(const void* data, size_t size, int target) {
    while (bytes_.size() % 4) bytes_.push_back(0);
    views_.push_back({{"buffer", 0}, {"byteOffset", bytes_.size()}, {"byteLength", size}, {"target", target}});
    const auto* p = static_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + size);
    return int(views_.size() - 1);
  }
  int positions(const std::vector<vec3>& p) {
    vec3 lo(1e30f), hi(-1e30f);
    for (const vec3& v : p) lo = glm::min(lo, v), hi = glm::max(hi, v);
    std::vector<float> flat;
    for (const vec3& v : p) flat.insert(flat.end(), {v.x, v.y, v.z});
    accessors_.push_back({{"bufferView", view(flat.data(), flat.size() * 4, 34962)},
                          {"componentType", 5126},
                          {"count", p.size()},
                          {"type", "VEC3"},
                          {"min", numbers(lo)},
                          {"max", numbers(hi)}});
    return int(accessors_.size() - 1);
  }
  int index_accessor(const std::vector<uint32_t>& indices, uint32_t vertex_count) {
    uint32_t lo = ~0u, hi = 0;
    for (uint32_t i : indices) {
      if (i >= vertex_count) fail("index out of range");
      lo = std::min(lo, i), hi = std::max(hi, i);
    }
    accessors_.push_back({{"bufferView", view(indices.data(), indices.size() * 4, 34963)},
                          {"componentType", 5125},
                          {"count", indices.size()},
                          {"type", "SCALAR"},
                          {"min", json::array({lo})},
                          {"max", json::array({hi})}});
    return int(accessors_.size() - 1);
  }

  std::string name_;
  std::vector<uint8_t> bytes_;
  json views_ = json::array(), accessors_ = json::array(), meshes_ = json::array(), materials_ = json::array();
  json nodes_ = json::array(), roots_ = json::array(), cameras_ = json::array(), lights_ = json::array();
  std::vector<std::string> extensions_;
  std::vector<CameraKey> camera_path_;
  std::vector<size_t> refined_triangles_;
  size_t scene_triangles_ = 0;
};

// A closed orbit around `target`: `keys` evenly spaced positions, gently bobbing in height.
std::vector<CameraKey> orbit(const vec3& target, float radius, float height, float bob, float yfov, int keys = 60,
                             float start_degrees = 0.0f, float sweep_degrees = 360.0f) {
  std::vector<CameraKey> path;
  for (int k = 0; k < keys; ++k) {
    const float t = float(k) / float(keys);
    const float a = radians(start_degrees) + (sweep_degrees == 360.0f ? 2.0f * kPi * t : radians(sweep_degrees) * std::sin(2.0f * kPi * t));
    path.push_back({target + vec3(radius * std::sin(a), height + bob * std::sin(4.0f * kPi * t), radius * std::cos(a)), target, {0, 1, 0}, yfov});
  }
  return path;
}

// ---------------------------------------------------------------------------------------------
// The scenes.

const vec3 kWhiteLight{1.0f, 1.0f, 1.0f};
const vec3 kWarmLight{1.0f, 0.85f, 0.7f};
const vec3 kCoolLight{0.75f, 0.85f, 1.0f};

// Cornell box, from the measured data (millimetres -> metres): the camera looks along +z,
// red wall at x = 0.55 on the left, green at x = 0 on the right, light just under the ceiling.
Gltf cornell_box() {
  Gltf g("cornell_box");
  const int white = g.material({"white", {0.73f, 0.73f, 0.73f}});
  const int red = g.material({"red", {0.63f, 0.065f, 0.05f}});
  const int green = g.material({"green", {0.14f, 0.45f, 0.091f}});
  const int light = g.material({"light", {0.0f, 0.0f, 0.0f}, 0.0f, 1.0f, {17.0f, 12.0f, 4.0f}});
  auto mm = [](float x, float y, float z) { return vec3(x, y, z) / 1000.0f; };
  const vec3 inside = mm(278, 274, 280);

  Polygons shell;  // floor, ceiling, back wall, facing in
  shell.append(quad(mm(552.8f, 0, 0), mm(0, 0, 0), mm(0, 0, 559.2f), mm(549.6f, 0, 559.2f), inside));
  shell.append(quad(mm(556, 548.8f, 0), mm(556, 548.8f, 559.2f), mm(0, 548.8f, 559.2f), mm(0, 548.8f, 0), inside));
  shell.append(quad(mm(549.6f, 0, 559.2f), mm(0, 0, 559.2f), mm(0, 548.8f, 559.2f), mm(556, 548.8f, 559.2f), inside));
  g.object("white_walls", g.mesh("white_walls", {{shell, white}}));
  g.object("red_wall", g.mesh("red_wall", {{quad(mm(552.8f, 0, 0), mm(549.6f, 0, 559.2f), mm(556, 548.8f, 559.2f),
                                                   mm(556, 548.8f, 0), inside), red}}));
  g.object("green_wall", g.mesh("green_wall", {{quad(mm(0, 0, 559.2f), mm(0, 0, 0), mm(0, 548.8f, 0),
                                                       mm(0, 548.8f, 559.2f), inside), green}}));

  // The blocks: their top quads from the data, extruded down to the floor; faces outward.
  auto block = [&](std::array<vec3, 4> top) {
    Polygons b;
    vec3 centre(0.0f);
    for (const vec3& t : top) centre += t * 0.25f;
    centre.y *= 0.5f;
    for (int i = 0; i < 4; ++i) {
      const vec3 a = top[i], c = top[(i + 1) % 4], mid = 0.5f * (a + c);
      const vec3 outside(2.0f * mid.x - centre.x, centre.y, 2.0f * mid.z - centre.z);
      b.append(quad(vec3(a.x, 0, a.z), vec3(c.x, 0, c.z), c, a, outside));
    }
    b.append(quad(top[0], top[1], top[2], top[3], centre + vec3(0, 1, 0)));
    b.append(quad(vec3(top[0].x, 0, top[0].z), vec3(top[1].x, 0, top[1].z), vec3(top[2].x, 0, top[2].z),
                  vec3(top[3].x, 0, top[3].z), centre - vec3(0, 1, 0)));
    return b;
  };
  g.object("short_block", g.mesh("short_block", {{block({mm(130, 165, 65), mm(82, 165, 225), mm(240, 165, 272), mm(290, 165, 114)}), white}}));
  g.object("tall_block", g.mesh("tall_block", {{block({mm(423, 330, 247), mm(265, 330, 296), mm(314, 330, 456), mm(472, 330, 406)}), white}}));
  g.object("ceiling_light", g.mesh("ceiling_light", {{quad(mm(343, 547.8f, 227), mm(343, 547.8f, 332), mm(213, 547.8f, 332),
                                                             mm(213, 547.8f, 227), inside), light}}));

  const float yfov = 2.0f * std::atan(12.5f / 35.0f) * 180.0f / kPi;  // 35 mm lens, 25 mm film
  g.camera("camera", {mm(278, 273, -800), mm(278, 273, 0), {0, 1, 0}, yfov});
  // Benchmark path: swing +-12 degrees around the box's centre (staying in front of the opening).
  std::vector<CameraKey> path;
  for (int k = 0; k < 60; ++k) {
    const float t = float(k) / 60.0f, a = radians(12.0f) * std::sin(2.0f * kPi * t);
    const vec3 centre = mm(278, 273, 280);
    path.push_back({centre + vec3(-1.08f * std::sin(a), 0.04f * std::sin(4.0f * kPi * t), -1.08f * std::cos(a)), centre, {0, 1, 0}, yfov});
  }
  g.camera_path(path);
  return g;
}

// Chains of interlocked tori (Catmull-Clark, 8x6 cages, level 3): 12 links, 73,728 triangles as in
// the paper's Chains scene; a point light and a spot light.
Gltf chains() {
  Gltf g("chains");
  const int floor_material = g.material({"floor", {0.55f, 0.55f, 0.52f}, 0.0f, 0.8f});
  const int steel = g.material({"steel", {0.8f, 0.8f, 0.82f}, 1.0f, 0.25f});
  const int gold = g.material({"gold", {1.0f, 0.78f, 0.34f}, 1.0f, 0.35f});
  const int red = g.material({"red_glossy", {0.6f, 0.05f, 0.05f}, 0.0f, 0.2f});
  g.object("floor", g.mesh("floor", {{floor_square(2.5f), floor_material}}));

  const float stretch = 1.4f;
  const Polygons link = torus(8, 6, 0.09f, 0.025f, stretch);
  const Subdivision smooth{epi::SubdivisionScheme::catmull_clark, 3};
  // Pitch between links: the one that keeps links k, k+1 (interlocked) and k, k+2 (end to end)
  // farthest apart, searched over points of the limit surface.
  const std::vector<vec3> surface = epi::subdivide(link.cage(), smooth.scheme, 2).positions;  // limit points, sparser
  float half_length = 0.0f;
  for (const vec3& p : surface) half_length = std::max(half_length, p.x);
  auto clearance = [&](float pitch) {
    const mat4 next = glm::rotate(glm::translate(mat4(1.0f), vec3(pitch, 0, 0)), 0.5f * kPi, vec3(1, 0, 0));
    float closest = 1e30f;
    for (size_t i = 0; i < surface.size(); i += 4)
      for (const vec3& q : surface) {
        closest = std::min(closest, glm::length(vec3(next * glm::vec4(surface[i], 1.0f)) - q));
        closest = std::min(closest, glm::length(surface[i] + vec3(2.0f * pitch, 0, 0) - q));
      }
    return closest;
  };
  float spacing = half_length, best = 0.0f;
  for (float pitch = 0.5f * half_length; pitch <= 1.5f * half_length; pitch += 0.02f * half_length)
    if (const float c = clearance(pitch); c > best) best = c, spacing = pitch;
  auto chain = [&](const std::string& name, int material, const mat4& placement, int links) {
    const int mesh = g.mesh(name + "_link", {{link, material}}, &smooth);
    for (int k = 0; k < links; ++k) {
      mat4 m = glm::translate(placement, vec3(spacing * float(k), 0, 0));
      if (k % 2) m = glm::rotate(m, 0.5f * kPi, vec3(1, 0, 0));
      g.object(name + "_" + std::to_string(k), mesh, m);
    }
  };
  // A horizontal chain, a chain sagging on a slant, and one hanging down through the scene.
  chain("steel_chain", steel, glm::rotate(glm::translate(mat4(1.0f), vec3(-0.45f, 0.16f, 0.25f)), radians(-12.0f), vec3(0, 1, 0)), 4);
  chain("gold_chain", gold,
        glm::rotate(glm::rotate(glm::translate(mat4(1.0f), vec3(-0.45f, 0.42f, -0.05f)), radians(10.0f), vec3(0, 1, 0)),
                    radians(-15.0f), vec3(0, 0, 1)),
        4);
  chain("red_chain", red,
        glm::rotate(glm::rotate(glm::translate(mat4(1.0f), vec3(0.3f, 0.9f, -0.45f)), radians(-90.0f), vec3(0, 0, 1)),
                    radians(20.0f), vec3(1, 0, 0)),
        4);

  g.point_light("point", {0.9f, 1.9f, 0.7f}, kWarmLight, 6.0f);
  g.spot_light("spot", {-1.3f, 1.6f, -0.9f}, {0.0f, 0.3f, 0.0f}, kCoolLight, 8.0f, 18.0f, 28.0f);
  g.camera("camera", {{1.15f, 0.8f, 1.3f}, {0.0f, 0.4f, 0.0f}, {0, 1, 0}, 40.0f});
  g.camera_path(orbit({0.0f, 0.4f, 0.0f}, 1.75f, 0.45f, 0.15f, 40.0f, 60, 40.0f));
  return g;
}

// A torus lying on a capsule that lies on the floor, under a square area light (Figure 9): the
// torus touches the capsule's top, so the soft shadow hardens towards the contact.
Gltf torus_capsule() {
  Gltf g("torus_capsule");
  const int floor_material = g.material({"floor", {0.7f, 0.7f, 0.7f}, 0.0f, 0.9f});
  const int orange = g.material({"orange", {0.8f, 0.35f, 0.1f}, 0.0f, 0.45f});
  const int blue = g.material({"blue", {0.2f, 0.4f, 0.8f}, 0.0f, 0.6f});
  const int light = g.material({"light", {0.0f, 0.0f, 0.0f}, 0.0f, 1.0f, {10.0f, 10.0f, 10.0f}});
  g.object("floor", g.mesh("floor", {{floor_square(2.0f), floor_material}}));

  const Subdivision smooth{epi::SubdivisionScheme::catmull_clark, 4}, coarser{epi::SubdivisionScheme::catmull_clark, 3};
  const float half_length = 0.42f;
  const Polygons capsule_cage = capsule(8, half_length, 0.15f);
  const Polygons torus_cage = torus(8, 6, 0.19f, 0.05f);
  // Capsule on the floor; the torus flat (its ring horizontal) across the capsule's straight part,
  // its lowest circle touching the capsule's top line.
  const Extent capsule_extent = limit_extent(capsule_cage, smooth.scheme, smooth.level);
  const mat4 capsule_placement = glm::translate(mat4(1.0f), vec3(0, -capsule_extent.min.y, 0));
  const float capsule_top = capsule_extent.max.y - capsule_extent.min.y;
  const mat4 flat = glm::rotate(mat4(1.0f), 0.5f * kPi, vec3(1, 0, 0));
  const Extent torus_extent = limit_extent(torus_cage, smooth.scheme, smooth.level, flat);
  // The capsule's top is level where all four control rings of a B-spline span are full-size: |x| < h/2.
  const float ring_radius = torus_extent.max.x - 0.5f * (torus_extent.max.y - torus_extent.min.y);
  if (ring_radius > 0.5f * half_length) Gltf::fail("torus_capsule: the torus would not rest on the level part of the capsule");
  const mat4 torus_placement = glm::translate(mat4(1.0f), vec3(0, capsule_top - torus_extent.min.y, 0)) * flat;
  g.object("capsule", g.mesh("capsule", {{capsule_cage, blue}}, &coarser), capsule_placement);
  g.object("torus", g.mesh("torus", {{torus_cage, orange}}, &smooth), torus_placement);

  const float h = 1.5f, s = 0.25f;
  g.object("area_light", g.mesh("area_light", {{quad({-s, h, -s}, {s, h, -s}, {s, h, s}, {-s, h, s}, {0, 0, 0}), light}}),
           glm::translate(mat4(1.0f), vec3(-0.25f, 0, 0.15f)));
  g.camera("camera", {{0.85f, 0.62f, 1.1f}, {0.0f, 0.2f, 0.0f}, {0, 1, 0}, 40.0f});
  g.camera_path(orbit({0.0f, 0.2f, 0.0f}, 1.35f, 0.45f, 0.1f, 40.0f, 60, 38.0f));
  return g;
}

// A smooth blob (Catmull-Clark level 4 of a deformed 17x17-per-side cube sphere: 887,808 triangles,
// standing in for the paper's 871k-polygon dragon) under a lattice of thin sharp bars that a spot
// light shines through; an area light fills in from the side.
Gltf grid_dragon() {
  Gltf g("grid_dragon");
  const int floor_material = g.material({"floor", {0.6f, 0.6f, 0.58f}, 0.0f, 0.9f});
  const int jade = g.material({"jade", {0.25f, 0.6f, 0.4f}, 0.0f, 0.35f});
  const int iron = g.material({"iron", {0.35f, 0.35f, 0.37f}, 1.0f, 0.5f});
  const int light = g.material({"light", {0.0f, 0.0f, 0.0f}, 0.0f, 1.0f, {8.0f, 7.5f, 7.0f}});
  g.object("floor", g.mesh("floor", {{floor_square(3.0f), floor_material}}));

  // An organic body: a stretched sphere with lumps along it, a raised "head" at +x.
  auto shape = [](vec3 d) {
    const float lumps = 0.10f * std::sin(5.0f * d.x + 1.3f) * std::sin(4.0f * d.y - 0.7f) * std::cos(3.0f * d.z + 0.4f) +
                        0.06f * std::sin(9.0f * d.x) * std::cos(7.0f * d.z + 2.0f) +
                        0.08f * std::max(0.0f, d.y) * std::pow(std::abs(std::sin(12.0f * d.x)), 3.0f);  // ridges on the back
    vec3 p = d * (1.0f + lumps);
    p *= vec3(0.75f, 0.42f, 0.38f);
    p.y += 0.12f * std::max(0.0f, d.x) * std::max(0.0f, d.x);  // the head rises
    p.z += 0.06f * std::sin(3.0f * d.x);                          // a slight S curve
    return p;
  };
  const Polygons body = blob(17, shape);
  const Subdivision smooth{epi::SubdivisionScheme::catmull_clark, 4};
  const Extent e = limit_extent(body, smooth.scheme, smooth.level);
  g.object("dragon", g.mesh("dragon", {{body, jade}}, &smooth), glm::translate(mat4(1.0f), vec3(0, -e.min.y, 0)));

  // The grid: bars along x below bars along z, stacked so that they touch without intersecting.
  Polygons grid;
  const int bars = 9;
  const float half = 0.8f, pitch = 2.0f * half / float(bars - 1), w = 0.012f, height = 1.25f;
  for (int i = 0; i < bars; ++i) {
    const float c = -half + pitch * float(i);
    grid.append(box({-half - w, height - 2 * w, c - w}, {half + w, height, c + w}));
    grid.append(box({c - w, height, -half - w}, {c + w, height + 2 * w, half + w}));
  }
  g.object("grid", g.mesh("grid", {{grid, iron}}), glm::rotate(mat4(1.0f), radians(20.0f), vec3(0, 1, 0)));

  g.spot_light("spot", {0.25f, 3.2f, 0.45f}, {0.0f, 0.3f, 0.0f}, kWhiteLight, 22.0f, 14.0f, 22.0f);
  const float s = 0.3f;
  g.object("area_light",
           g.mesh("area_light", {{quad({-s, -s, 0}, {s, -s, 0}, {s, s, 0}, {-s, s, 0}, {0, 0, 1}), light}}),
           look_from({-1.8f, 1.6f, 1.4f}, {0.0f, 0.3f, 0.0f}) * glm::rotate(mat4(1.0f), kPi, vec3(0, 1, 0)));
  g.camera("camera", {{2.3f, 1.9f, 2.6f}, {0.0f, 0.55f, 0.0f}, {0, 1, 0}, 40.0f});
  g.camera_path(orbit({0.0f, 0.55f, 0.0f}, 3.4f, 1.3f, 0.2f, 40.0f, 60, 42.0f));
  return g;
}

// Four rooms (2 x 2, 4 m square, 2.6 m high) joined by doorways in a loop, furnished with boxes and a
// few subdivided pieces, lit by seven lights: two ceiling panels (area), three point, two spot.
Gltf rooms() {
  Gltf g("rooms");
  const int wall = g.material({"wall", {0.78f, 0.76f, 0.72f}, 0.0f, 0.9f});
  const int floor_material = g.material({"floor", {0.45f, 0.32f, 0.2f}, 0.0f, 0.6f});
  const int ceiling = g.material({"ceiling", {0.85f, 0.85f, 0.85f}});
  const int wood = g.material({"wood", {0.5f, 0.33f, 0.18f}, 0.0f, 0.5f});
  const int metal = g.material({"metal", {0.7f, 0.7f, 0.72f}, 1.0f, 0.3f});
  const int fabric_blue = g.material({"fabric_blue", {0.15f, 0.25f, 0.55f}});
  const int fabric_red = g.material({"fabric_red", {0.6f, 0.15f, 0.12f}});
  const int ceramic = g.material({"ceramic", {0.9f, 0.9f, 0.85f}, 0.0f, 0.15f});
  const int panel = g.material({"ceiling_panel", {0.0f, 0.0f, 0.0f}, 0.0f, 1.0f, {5.0f, 4.8f, 4.5f}});

  const float size = 8.0f, height = 2.6f, t = 0.1f, door_width = 1.0f, door_height = 2.1f;
  Polygons walls;
  // Outer walls: a ring in plan (u = x, v = -z), extruded upwards (w = y).
  const mat4 plan_to_world(vec4(1, 0, 0, 0), vec4(0, 0, -1, 0), vec4(0, 1, 0, 0), vec4(0, 0, 0, 1));
  walls.append(extrude_cells({-t, 0, size, size + t}, {-size - t, -size, 0, t}, 0, height,
                             [](int i, int j) { return !(i == 1 && j == 1); }),
               plan_to_world);
  // Interior walls: a wall along x at z = 4 across the whole house, and two walls along z at x = 4
  // that end against it; each room-side stretch has a doorway in its middle.
  auto wall_solid = [&](float from, float to, std::vector<float> door_centres) {
    std::vector<float> us = {from};
    for (float c : door_centres) us.insert(us.end(), {c - 0.5f * door_width, c + 0.5f * door_width});
    us.push_back(to);
    return extrude_cells(us, {0, door_height, height}, -0.5f * t, 0.5f * t,
                         [](int i, int j) { return !(j == 0 && i % 2 == 1); });  // odd columns are doorways
  };
  walls.append(wall_solid(0, size, {2.0f, 6.0f}), glm::translate(mat4(1.0f), vec3(0, 0, 4.0f)));
  const mat4 along_z(vec4(0, 0, 1, 0), vec4(0, 1, 0, 0), vec4(1, 0, 0, 0), vec4(4.0f, 0, 0, 1));  // mirrors: append re-orients
  walls.append(wall_solid(0, 4.0f - 0.5f * t, {2.0f}), along_z);
  walls.append(wall_solid(4.0f + 0.5f * t, size, {6.0f}), along_z);
  g.object("walls", g.mesh("walls", {{walls, wall}}));
  g.object("floor", g.mesh("floor", {{quad({0, 0, 0}, {size, 0, 0}, {size, 0, size}, {0, 0, size}, {4, 1, 4}), floor_material}}));
  g.object("ceiling", g.mesh("ceiling", {{quad({0, height, 0}, {size, height, 0}, {size, height, size}, {0, height, size}, {4, 0, 4}), ceiling}}));

  // Furniture. A table: wooden top and metal legs, two primitives of one mesh.
  Polygons top = box({-0.7f, 0.72f, -0.45f}, {0.7f, 0.76f, 0.45f}), legs;
  for (float x : {-0.62f, 0.62f})
    for (float z : {-0.37f, 0.37f}) legs.append(box({x - 0.03f, 0, z - 0.03f}, {x + 0.03f, 0.72f, z + 0.03f}));
  const int table = g.mesh("table", {{top, wood}, {legs, metal}});
  g.object("table_a", table, glm::translate(mat4(1.0f), vec3(2.0f, 0, 1.4f)));
  g.object("table_b", table, glm::rotate(glm::translate(mat4(1.0f), vec3(6.2f, 0, 6.0f)), 0.5f * kPi, vec3(0, 1, 0)));
  g.object("bed", g.mesh("bed", {{box({5.0f, 0, 0.2f}, {7.8f, 0.5f, 1.8f}), fabric_red}}));
  g.object("headboard", g.mesh("headboard", {{box({7.7f, 0, 0.2f}, {7.8f, 1.1f, 1.8f}), wood}}));
  g.object("shelf", g.mesh("shelf", {{box({0.2f, 0, 7.4f}, {2.2f, 1.9f, 7.8f}), wood}}));
  Polygons sofa = box({0.3f, 0, 4.35f}, {0.9f, 0.45f, 6.25f});  // the seat shares no edge with the back
  sofa.append(box({0.1f, 0, 4.3f}, {0.3f, 0.9f, 6.3f}));
  g.object("sofa", g.mesh("sofa", {{sofa, fabric_blue}}));
  g.object("cabinet", g.mesh("cabinet", {{box({4.3f, 0, 7.3f}, {5.5f, 1.0f, 7.8f}), wood}}));

  // A pouf: a Catmull-Clark box with semi-sharp creases on its top and bottom rims.
  Polygons pouf = box({-0.3f, 0, -0.3f}, {0.3f, 0.4f, 0.3f});
  for (auto [a, b] : {std::pair{0u, 1u}, {1u, 5u}, {5u, 4u}, {4u, 0u}, {2u, 3u}, {3u, 7u}, {7u, 6u}, {6u, 2u}})
    pouf.creases.push_back({a, b, 2.0f});
  const Subdivision pouf_subdivision{epi::SubdivisionScheme::catmull_clark, 4};
  const Extent pouf_extent = limit_extent(pouf, pouf_subdivision.scheme, pouf_subdivision.level);
  g.object("pouf", g.mesh("pouf", {{pouf, fabric_red}}, &pouf_subdivision),
           glm::translate(mat4(1.0f), vec3(1.8f, -pouf_extent.min.y, 5.3f)));
  // A ball (Loop subdivision of an octahedron) on the floor, and a vase (Catmull-Clark) on a table.
  const Polygons ball = octahedron(0.25f);
  const Subdivision ball_subdivision{epi::SubdivisionScheme::loop, 4};
  const Extent ball_extent = limit_extent(ball, ball_subdivision.scheme, ball_subdivision.level);
  g.object("ball", g.mesh("ball", {{ball, ceramic}}, &ball_subdivision),
           glm::translate(mat4(1.0f), vec3(5.6f, -ball_extent.min.y, 2.9f)));
  Polygons vase = capsule(8, 0.12f, 0.09f);
  const Subdivision vase_subdivision{epi::SubdivisionScheme::catmull_clark, 3};
  const mat4 upright = glm::rotate(mat4(1.0f), 0.5f * kPi, vec3(0, 0, 1));
  const Extent vase_extent = limit_extent(vase, vase_subdivision.scheme, vase_subdivision.level, upright);
  g.object("vase", g.mesh("vase", {{vase, ceramic}}, &vase_subdivision),
           glm::translate(mat4(1.0f), vec3(2.2f, 0.76f - vase_extent.min.y, 1.3f)) * upright);

  // Lights: ceiling panels in rooms (0,0) and (0,1), point lights, spots on the table and the bed.
  const float p = 0.5f, y = height - 0.01f;
  const int ceiling_panel = g.mesh("ceiling_panel", {{quad({-p, 0, -p}, {p, 0, -p}, {p, 0, p}, {-p, 0, p}, {0, -1, 0}), panel}});
  g.object("panel_a", ceiling_panel, glm::translate(mat4(1.0f), vec3(2.0f, y, 2.0f)));
  g.object("panel_b", ceiling_panel, glm::translate(mat4(1.0f), vec3(2.0f, y, 6.0f)));
  g.point_light("bedroom_lamp", {6.0f, 2.2f, 2.0f}, kWarmLight, 4.0f);
  g.point_light("floor_lamp", {0.6f, 1.5f, 3.3f}, kWarmLight, 2.0f);
  g.point_light("hall_lamp", {6.0f, 2.3f, 6.0f}, kWhiteLight, 3.0f);
  g.spot_light("table_spot", {6.8f, 2.5f, 5.0f}, {6.2f, 0.76f, 6.0f}, kWhiteLight, 10.0f, 20.0f, 30.0f);
  g.spot_light("bed_spot", {4.3f, 2.5f, 3.6f}, {6.5f, 0.5f, 1.0f}, kCoolLight, 8.0f, 15.0f, 25.0f);

  g.camera("camera", {{3.6f, 1.6f, 0.4f}, {1.0f, 0.9f, 3.0f}, {0, 1, 0}, 60.0f});
  // Walk: a closed Catmull-Rom loop through the room centres and the four doorways, looking ahead.
  const std::vector<glm::vec2> stops = {{2, 2}, {4, 2}, {6, 2.6f}, {6, 4}, {6, 5.2f}, {4, 6}, {2, 6}, {2, 4}};
  auto along = [&](float u) {
    const int n = int(stops.size());
    const int i = int(std::floor(u)) % n;
    const float f = u - std::floor(u);
    const glm::vec2 p0 = stops[(i + n - 1) % n], p1 = stops[i], p2 = stops[(i + 1) % n], p3 = stops[(i + 2) % n];
    const glm::vec2 q = 0.5f * ((2.0f * p1) + (-p0 + p2) * f + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * f * f +
                                (-p0 + 3.0f * p1 - 3.0f * p2 + p3) * f * f * f);
    return q;
  };
  std::vector<CameraKey> path;
  for (int k = 0; k < 60; ++k) {
    const float u = float(stops.size()) * float(k) / 60.0f;
    const glm::vec2 eye = along(u), ahead = along(u + 0.5f);
    path.push_back({{eye.x, 1.6f, eye.y}, {ahead.x, 1.4f, ahead.y}, {0, 1, 0}, 60.0f});
  }
  g.camera_path(path);
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_scenes OUTPUT_DIR\n";
    return 2;
  }
  const std::filesystem::path out = argv[1];
  try {
    std::filesystem::create_directories(out);
    const std::pair<const char*, Gltf (*)()> scenes[] = {{"cornell_box", cornell_box}, {"chains", chains},
                                                         {"torus_capsule", torus_capsule}, {"grid_dragon", grid_dragon},
                                                         {"rooms", rooms}};
    for (const auto& [name, make] : scenes) {
      const Gltf scene = make();
      const std::string text = scene.text();
      const std::filesystem::path file = out / (std::string(name) + ".gltf"), temporary = file.string() + ".tmp";
      {
        std::ofstream stream(temporary, std::ios::binary);
        stream << text;
        if (!stream.flush()) throw std::runtime_error(temporary.string() + ": cannot write");
      }
      std::filesystem::rename(temporary, file);
      std::cout << file.string() << ": " << scene.triangles_after_subdivision() << " triangles after subdivision, "
                << text.size() << " bytes\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "make_scenes: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

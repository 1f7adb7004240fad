// The scene model: what a loaded scene holds once tessellated and validated.
// Knows nothing of file formats (io/gltf fills it) or of ray tracing (core/shade reads it).
// Geometry stays in object space with a transform per object, so that moving an object
// never touches its mesh (edge trees are built once per mesh; see docs/architecture.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace epi {

inline constexpr uint32_t kNone = 0xffffffffu;

// Metallic-roughness material (glTF 2.0 core), colours linear RGB.
struct Material {
  std::string name;
  glm::vec3 base_color{0.8f};
  float metallic = 0.0f;
  float roughness = 1.0f;
  glm::vec3 emission{0.0f};  // emissiveFactor * KHR_materials_emissive_strength, linear radiance
  bool emissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
};

// A run of consecutive triangles sharing one material.
struct MaterialRange {
  uint32_t first_triangle = 0;
  uint32_t triangle_count = 0;
  uint32_t material = 0;
};

enum class SubdivisionScheme { catmull_clark, loop };

// A crease: the edge between two control vertices, with OpenSubdiv's sharpness (0 smooth, 10 infinitely sharp).
struct Crease {
  uint32_t v0 = 0, v1 = 0;
  float sharpness = 0.0f;
};

// What the scene asked for; kept so `epi info` can report it.
struct SubdivisionInfo {
  SubdivisionScheme scheme = SubdivisionScheme::catmull_clark;
  int level = 0;
  uint32_t control_faces = 0;
  uint32_t crease_count = 0;
};

// A triangle mesh in object space, after tessellation, welding and repair.
struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;
  std::vector<glm::vec3> normals;        // per-vertex shading normals; empty means flat shading
  std::vector<MaterialRange> materials;  // cover all triangles, in order
  float sharp_angle_degrees = 85.0f;     // dihedral cutoff for sharp edges (extras.epi.sharp_angle)
  bool subdivided = false;
  SubdivisionInfo subdivision;           // meaningful when subdivided
  uint32_t degenerate_triangles_dropped = 0;

  uint32_t material_of(uint32_t triangle) const;
  size_t memory_bytes() const;
};

// An instance of a mesh in the world: one glTF node with a mesh.
struct Object {
  std::string name;  // the glTF node name (unique: the loader disambiguates repeats)
  uint32_t mesh = 0;
  glm::mat4 object_to_world{1.0f};
};

enum class LightType { point, spot, directional, area };

// KHR_lights_punctual, in world space. Radiometric conventions follow the extension:
// point and spot intensity in candela (W/sr here), directional in lux (W/m^2 here).
struct PunctualLight {
  std::string name;
  LightType type = LightType::point;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // where the light points (spot, directional)
  glm::vec3 intensity{1.0f};               // colour * intensity
  float range = 0.0f;                      // 0: infinite
  float inner_cone_cos = 1.0f, outer_cone_cos = 0.70710678f;  // spot only
};

// An emissive object taken as a polygonal area light. Sampling uses its world-space
// triangles; soft-shadow edges use its outline: the boundary loops of the emitting surface.
struct AreaLight {
  uint32_t object = 0;  // index into Scene::objects
  std::vector<glm::vec3> triangle_vertices;      // world space, 3 per triangle
  std::vector<uint32_t> triangle_materials;      // material per triangle (emission per triangle)
  std::vector<float> triangle_cdf;               // cumulative power fraction, last = 1
  std::vector<std::vector<glm::vec3>> outlines;  // world-space boundary loops; empty for closed meshes
  float area = 0.0f;
  float power = 0.0f;  // sum of luminance(emission) * area, for choosing among lights
  size_t memory_bytes() const;
};

// A pinhole camera. Field of view is vertical, in degrees.
struct Camera {
  std::string name;
  glm::vec3 eye{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float yfov_degrees = 45.0f;
  float znear = 0.01f;
};

// Why `camera` cannot be used, or "" when it can: a field of view outside (0, 180) degrees,
// a non-finite or non-positive znear, eye and target that are not finite or coincide, an up
// vector that is zero or parallel to the view direction. Lengths are computed in double, so
// large but finite coordinates (1e30, 3e38) are fine.
std::string camera_problem(const Camera& camera);

struct Bounds {
  glm::vec3 min{1e30f}, max{-1e30f};
  void extend(const glm::vec3& p) { min = glm::min(min, p); max = glm::max(max, p); }
  bool empty() const { return min.x > max.x; }
};

struct MemoryItem {
  std::string name;
  size_t bytes = 0;
};

struct Scene {
  std::string source;  // file it came from, for messages
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Object> objects;
  std::vector<PunctualLight> punctual_lights;
  std::vector<AreaLight> area_lights;  // built only when the scene has emissive meshes
  std::vector<Camera> cameras;         // cameras[0] is the default view
  std::vector<Camera> camera_path;     // benchmark path (extras.epi.camera_path); may be empty
  std::vector<std::string> repairs;    // safe repairs done while loading, one line each

  size_t triangle_count() const;
  Bounds world_bounds() const;
  std::vector<MemoryItem> memory() const;  // what was built, and its size
};

}  // namespace epi

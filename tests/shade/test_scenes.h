// Small scenes built in code for the shade tests: analytic set-ups with known answers.
#pragma once

#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/scene.h"
#include "shade/lights.h"

namespace epi::test {

inline uint32_t add_material(Scene& scene, glm::vec3 base, float metallic = 0.0f, float roughness = 1.0f,
                             glm::vec3 emission = glm::vec3(0.0f)) {
  Material m;
  m.name = "m";
  m.name += std::to_string(scene.materials.size());  // (not "m" + ...: GCC 12 warns falsely, bug 105651)
  m.base_color = base;
  m.metallic = metallic;
  m.roughness = roughness;
  m.emission = emission;
  scene.materials.push_back(m);
  return uint32_t(scene.materials.size() - 1);
}

inline void finish_mesh(Mesh& mesh, uint32_t material) {
  mesh.materials = {MaterialRange{0, uint32_t(mesh.triangles.size()), material}};
}

// A parallelogram corner, corner+u, corner+u+v, corner+v; its front faces along cross(u, v).
inline Mesh quad_mesh(glm::vec3 corner, glm::vec3 u, glm::vec3 v, uint32_t material) {
  Mesh mesh;
  mesh.name = "quad";
  mesh.positions = {corner, corner + u, corner + u + v, corner + v};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  finish_mesh(mesh, material);
  return mesh;
}

// The axis-aligned box [lo, hi] with faces pointing inwards (a room) or outwards.
inline Mesh box_mesh(glm::vec3 lo, glm::vec3 hi, uint32_t material, bool inwards) {
  Mesh mesh;
  mesh.name = "box";
  for (int i = 0; i < 8; ++i) mesh.positions.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  // Outward-facing quads (counter-clockwise seen from outside).
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    if (inwards) {
      mesh.triangles.push_back({uint32_t(f[0]), uint32_t(f[2]), uint32_t(f[1])});
      mesh.triangles.push_back({uint32_t(f[0]), uint32_t(f[3]), uint32_t(f[2])});
    } else {
      mesh.triangles.push_back({uint32_t(f[0]), uint32_t(f[1]), uint32_t(f[2])});
      mesh.triangles.push_back({uint32_t(f[0]), uint32_t(f[2]), uint32_t(f[3])});
    }
  }
  finish_mesh(mesh, material);
  return mesh;
}

// A UV sphere with smooth normals: 2 * rings * segments triangles (minus the pole slivers).
inline Mesh sphere_mesh(glm::vec3 centre, float radius, int rings, int segments, uint32_t material) {
  Mesh mesh;
  mesh.name = "sphere";
  for (int r = 0; r <= rings; ++r) {
    float theta = float(M_PI) * float(r) / float(rings);
    for (int s = 0; s <= segments; ++s) {
      float phi = 2.0f * float(M_PI) * float(s) / float(segments);
      glm::vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      mesh.positions.push_back(centre + radius * n);
      mesh.normals.push_back(n);
    }
  }
  auto index = [&](int r, int s) { return uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      if (r != 0) mesh.triangles.push_back({index(r, s), index(r + 1, s), index(r, s + 1)});
      if (r != rings - 1) mesh.triangles.push_back({index(r, s + 1), index(r + 1, s), index(r + 1, s + 1)});
    }
  finish_mesh(mesh, material);
  return mesh;
}

inline uint32_t add_object(Scene& scene, Mesh mesh, const std::string& name, glm::mat4 transform = glm::mat4(1.0f)) {
  mesh.name = name;
  scene.meshes.push_back(std::move(mesh));
  Object object;
  object.name = name;
  object.mesh = uint32_t(scene.meshes.size() - 1);
  object.object_to_world = transform;
  scene.objects.push_back(object);
  return uint32_t(scene.objects.size() - 1);
}

// Makes an object with an emissive material an area light, as the glTF loader does.
inline void add_area_light(Scene& scene, uint32_t object) {
  scene.area_lights.push_back(build_area_light(scene, object, scene.objects[object].object_to_world));
}

inline PunctualLight point_light(glm::vec3 position, glm::vec3 intensity) {
  PunctualLight l;
  l.name = "point";
  l.type = LightType::point;
  l.position = position;
  l.intensity = intensity;
  return l;
}

inline Camera look(glm::vec3 eye, glm::vec3 target, float yfov = 45.0f) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = glm::vec3(0.0f, 0.0f, 1.0f);
  c.yfov_degrees = yfov;
  return c;
}

// A ground quad with a red box on it, one point light ("lamp") and a camera looking at the box:
// the frame loop's and the moving-light tests' small scene.
inline Scene plane_and_box() {
  Scene scene;
  const uint32_t grey = add_material(scene, glm::vec3(0.7f));
  const uint32_t red = add_material(scene, glm::vec3(0.8f, 0.2f, 0.1f));
  add_object(scene, quad_mesh({-6, -6, 0}, {12, 0, 0}, {0, 12, 0}, grey), "ground");
  add_object(scene, box_mesh({-0.8f, -0.8f, 0.0f}, {0.8f, 0.8f, 1.6f}, red, false), "box");
  scene.punctual_lights.push_back(point_light({2.0f, -3.0f, 6.0f}, glm::vec3(40.0f)));
  scene.punctual_lights.back().name = "lamp";
  scene.cameras.push_back(look({3.0f, -6.0f, 4.0f}, {0.0f, 0.0f, 0.6f}, 45.0f));
  return scene;
}

}  // namespace epi::test

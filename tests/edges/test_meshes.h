// Meshes built in code for the edge finder's tests and benchmarks: smooth, sharp and hard ones.
#pragma once

#include <cmath>
#include <random>
#include <string>

#include "scene/scene.h"

namespace epi::edges::test {

inline Mesh finish(Mesh m, std::string name) {
  m.name = std::move(name);
  m.materials = {{0, uint32_t(m.triangles.size()), 0}};
  return m;
}

// A UV sphere; each quad split into two triangles, poles as fans. Vertices duplicated along the
// seam (as exporters do), so welding matters.
inline Mesh uv_sphere(int rings, int segments, float radius = 1.0f, glm::vec3 centre = glm::vec3(0.0f)) {
  Mesh m;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * (s % segments) / segments;
      glm::vec3 p(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      if (r == 0) p = {0, 1, 0};
      if (r == rings) p = {0, -1, 0};
      m.positions.push_back(centre + radius * p);
    }
  auto id = [&](int r, int s) { return uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = id(r, s), b = id(r, s + 1), c = id(r + 1, s), d = id(r + 1, s + 1);
      if (r != 0) m.triangles.push_back({a, b, c});
      if (r != rings - 1) m.triangles.push_back({b, d, c});
    }
  return finish(std::move(m), "sphere");
}

inline Mesh torus(int rings, int segments, float major = 1.0f, float minor = 0.35f) {
  Mesh m;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double u = 2 * M_PI * r / rings, v = 2 * M_PI * s / segments;
      m.positions.push_back(glm::vec3((major + minor * std::cos(v)) * std::cos(u), minor * std::sin(v),
                                      (major + minor * std::cos(v)) * std::sin(u)));
    }
  auto id = [&](int r, int s) { return uint32_t((r % rings) * segments + (s % segments)); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({id(r, s), id(r, s + 1), id(r + 1, s)});
      m.triangles.push_back({id(r, s + 1), id(r + 1, s + 1), id(r + 1, s)});
    }
  return finish(std::move(m), "torus");
}

// A torus as exporters write it: a (rings + 1) x (segments + 1) grid of vertices with UVs in
// mind, the last row and column repeating the first at angle 2 pi, so the seam copies come from
// cos/sin of 2 pi and of 0 and differ by about 1e-16 (or float rounding). 2 (rings + segments)
// border edges before welding with a tolerance.
inline Mesh exporter_torus(int rings, int segments, float major = 1.0f, float minor = 0.35f,
                           glm::vec3 centre = glm::vec3(0.0f)) {
  Mesh m;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const double u = 2 * M_PI * r / rings, v = 2 * M_PI * s / segments;
      m.positions.push_back(centre + glm::vec3((major + minor * std::cos(v)) * std::cos(u), minor * std::sin(v),
                                               (major + minor * std::cos(v)) * std::sin(u)));
    }
  auto id = [&](int r, int s) { return uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({id(r, s), id(r, s + 1), id(r + 1, s)});
      m.triangles.push_back({id(r, s + 1), id(r + 1, s + 1), id(r + 1, s)});
    }
  return finish(std::move(m), "exporter_torus");
}

// An axis-aligned box with 4 vertices per face (split at the sharp edges, as exporters write it).
inline Mesh box(glm::vec3 lo, glm::vec3 hi) {
  Mesh m;
  const glm::vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                          {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  for (const auto& q : quads) {
    const uint32_t base = uint32_t(m.positions.size());
    for (int k = 0; k < 4; ++k) m.positions.push_back(c[q[k]]);
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  }
  return finish(std::move(m), "box");
}

// A flat n x n grid of quads in the y = 0 plane, facing +y (coplanar neighbours, border edges).
inline Mesh grid(int n, float size = 2.0f) {
  Mesh m;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) m.positions.push_back({size * (float(j) / n - 0.5f), 0.0f, size * (float(i) / n - 0.5f)});
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const uint32_t a = i * (n + 1) + j, b = a + 1, c = a + (n + 1), d = c + 1;
      m.triangles.push_back({a, c, b});
      m.triangles.push_back({b, c, d});
    }
  return finish(std::move(m), "grid");
}

// A noisy sphere: random radial displacement, so normals vary a lot (a scanned-looking mesh).
inline Mesh bumpy_sphere(int rings, int segments, float noise, uint32_t seed) {
  Mesh m = uv_sphere(rings, segments);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> jitter(1.0f - noise, 1.0f + noise);
  // Displace welded positions consistently: same position, same factor.
  for (glm::vec3& p : m.positions) {
    std::seed_seq s{std::hash<float>{}(p.x), std::hash<float>{}(p.y), std::hash<float>{}(p.z), size_t(seed)};
    std::mt19937 local(s);
    p *= jitter(local);
  }
  (void)rng;
  m.name = "bumpy";
  return m;
}

// Non-manifold fins: triangles sharing one edge three and four times, plus slivers and a
// zero-area triangle.
inline Mesh hard_mesh() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0.2f}, {0.5f, 0, 1}, {0.5f, 0.1f, -1},
                 {2, 0, 0}, {1.5f, 1e-6f, 0}, {3, 0, 0}, {2.5f, 0, 0}, {2.5f, 1e-7f, 1e-7f}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5},  // four faces on edge 0-1
                 {1, 6, 7},                                   // sliver
                 {6, 8, 9},                                   // zero area (collinear)
                 {6, 9, 10}, {1, 7, 2}};
  return finish(std::move(m), "hard");
}

// Random triangle soup sharing vertices: arbitrary orientations, many non-manifold edges.
inline Mesh random_soup(int vertices, int triangles, uint32_t seed) {
  Mesh m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < vertices; ++i) m.positions.push_back({u(rng), u(rng), u(rng)});
  std::uniform_int_distribution<uint32_t> pick(0, vertices - 1);
  while (int(m.triangles.size()) < triangles) {
    const glm::uvec3 t{pick(rng), pick(rng), pick(rng)};
    if (t.x != t.y && t.y != t.z && t.x != t.z) m.triangles.push_back(t);
  }
  return finish(std::move(m), "soup");
}

inline Mesh transformed(Mesh m, float scale, glm::vec3 offset, const std::string& suffix) {
  for (glm::vec3& p : m.positions) p = p * scale + offset;
  m.name += suffix;
  return m;
}

inline glm::mat4 translation(glm::vec3 p) {
  glm::mat4 m(1.0f);
  m[3] = glm::vec4(p, 1.0f);
  return m;
}

// A scene of n unit boxes on a floor, spaced 3 apart on a square grid, under a point light high
// above and a slanted sun: shadows fall near their casters (issue 14's scaling tests and bench).
inline Scene boxes_on_a_floor(int n) {
  Scene scene;
  scene.meshes = {box({-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f})};
  const int side = int(std::ceil(std::sqrt(double(n))));
  scene.meshes.push_back(box({-1.5f * side - 2, -0.2f, -1.5f * side - 2}, {1.5f * side + 2, 0.0f, 1.5f * side + 2}));
  scene.objects.push_back({"floor", 1, glm::mat4(1.0f)});
  for (int i = 0; i < n; ++i)
    scene.objects.push_back({"box" + std::to_string(i), 0,
                             translation({3.0f * float(i % side) - 1.5f * side, 0.0f, 3.0f * float(i / side) - 1.5f * side})});
  PunctualLight lamp;
  lamp.position = {0.5f, 60.0f, 0.25f};
  scene.punctual_lights.push_back(lamp);
  PunctualLight sun;
  sun.type = LightType::directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  scene.punctual_lights.push_back(sun);
  return scene;
}

}  // namespace epi::edges::test

// Subdivision: face counts, limit-surface properties, topology and orientation kept, every error case.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "scene/subdivide.h"
#include "scene/topology.h"

namespace epi {
namespace {

// Cube [-1,1]^3, quads counter-clockwise seen from outside.
ControlMesh cube_cage() {
  ControlMesh cage;
  for (int i = 0; i < 8; ++i) cage.positions.emplace_back(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f);
  const uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    cage.face_sizes.push_back(4);
    cage.face_indices.insert(cage.face_indices.end(), f, f + 4);
  }
  return cage;
}

ControlMesh tetrahedron_cage() {
  ControlMesh cage;
  cage.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  const uint32_t faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  for (const auto& f : faces) {
    cage.face_sizes.push_back(3);
    cage.face_indices.insert(cage.face_indices.end(), f, f + 3);
  }
  return cage;
}

// Torus around the y axis, major radius 2, minor 0.5, outward quads.
ControlMesh torus_cage(int major_steps = 8, int minor_steps = 6) {
  ControlMesh cage;
  const float two_pi = 2.0f * std::numbers::pi_v<float>;
  for (int i = 0; i < major_steps; ++i)
    for (int j = 0; j < minor_steps; ++j) {
      const float phi = two_pi * i / major_steps, theta = two_pi * j / minor_steps;
      const float ring = 2.0f + 0.5f * std::cos(theta);
      cage.positions.emplace_back(ring * std::cos(phi), 0.5f * std::sin(theta), ring * std::sin(phi));
    }
  auto id = [&](int i, int j) { return uint32_t((i % major_steps) * minor_steps + j % minor_steps); };
  for (int i = 0; i < major_steps; ++i)
    for (int j = 0; j < minor_steps; ++j) {
      cage.face_sizes.push_back(4);
      for (uint32_t v : {id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)}) cage.face_indices.push_back(v);
    }
  return cage;
}

double signed_volume(const std::vector<glm::vec3>& p, const std::vector<glm::uvec3>& triangles) {
  double volume = 0.0;
  for (const glm::uvec3& t : triangles)
    volume += glm::dot(glm::dvec3(p[t.x]), glm::cross(glm::dvec3(p[t.y]), glm::dvec3(p[t.z]))) / 6.0;
  return volume;
}

long euler_characteristic(const SubdividedMesh& refined) {
  Mesh mesh;
  mesh.positions = refined.positions;
  mesh.triangles = refined.triangles;
  const EdgeTable table = build_edge_table(mesh);
  EXPECT_EQ(table.border_edges, 0u);
  EXPECT_EQ(table.non_manifold_edges, 0u);
  return long(table.weld.positions.size()) - long(table.edges.size()) + long(mesh.triangles.size());
}

void expect_valid_indices(const SubdividedMesh& m) {
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (const glm::uvec3& t : m.triangles) {
    ASSERT_LT(t.x, m.positions.size());
    ASSERT_LT(t.y, m.positions.size());
    ASSERT_LT(t.z, m.positions.size());
  }
}

TEST(Subdivide, CatmullClarkCubeFaceCounts) {
  for (int level = 0; level <= 5; ++level) {
    const SubdividedMesh m = subdivide(cube_cage(), SubdivisionScheme::catmull_clark, level);
    EXPECT_EQ(m.triangles.size(), 12u << (2 * level)) << "level " << level;
    // V = 6*4^N quads' worth: 8 corners + edges + faces; closed genus 0 with quads: V = F_quads + 2.
    EXPECT_EQ(m.positions.size(), (6u << (2 * level)) + 2) << "level " << level;
    expect_valid_indices(m);
  }
}

TEST(Subdivide, LoopTetrahedronFaceCounts) {
  for (int level = 0; level <= 6; ++level) {
    const SubdividedMesh m = subdivide(tetrahedron_cage(), SubdivisionScheme::loop, level);
    EXPECT_EQ(m.triangles.size(), 4u << (2 * level)) << "level " << level;
    EXPECT_EQ(m.positions.size(), (2u << (2 * level)) + 2) << "level " << level;
    expect_valid_indices(m);
  }
}

TEST(Subdivide, CatmullClarkCubeLimitInsideCageAndSymmetric) {
  const SubdividedMesh m = subdivide(cube_cage(), SubdivisionScheme::catmull_clark, 4);
  float min_radius = 1e9f, max_radius = 0.0f;
  for (const glm::vec3& p : m.positions) {
    EXPECT_LT(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 1.0f);
    min_radius = std::min(min_radius, glm::length(p));
    max_radius = std::max(max_radius, glm::length(p));
  }
  // Sphere-like: the limit surface of a cube is a rounded blob, far from the cage's corners (radius sqrt 3).
  EXPECT_GT(min_radius, 0.55f);
  EXPECT_LT(max_radius, 0.9f);
  EXPECT_GT(min_radius / max_radius, 0.8f);

  // The cube's symmetries map the point set onto itself: mirror x, and swap x with y.
  auto contains = [&](const glm::vec3& q) {
    return std::any_of(m.positions.begin(), m.positions.end(),
                       [&](const glm::vec3& p) { return glm::length(p - q) < 1e-5f; });
  };
  for (size_t v = 0; v < m.positions.size(); v += 7) {
    const glm::vec3 p = m.positions[v];
    EXPECT_TRUE(contains({-p.x, p.y, p.z})) << v;
    EXPECT_TRUE(contains({p.y, p.x, p.z})) << v;
    EXPECT_TRUE(contains({p.z, -p.y, p.x})) << v;
  }
}

TEST(Subdivide, LimitPositionsAgreeAcrossLevels) {
  // A vertex keeps its index when refined further, and its limit point is the same point of the
  // limit surface: positions at level N and N+1 agree on the shared vertices (convergence).
  for (SubdivisionScheme scheme : {SubdivisionScheme::catmull_clark, SubdivisionScheme::loop}) {
    const ControlMesh cage = scheme == SubdivisionScheme::loop ? tetrahedron_cage() : torus_cage();
    SubdividedMesh previous = subdivide(cage, scheme, 1);
    for (int level = 2; level <= 4; ++level) {
      const SubdividedMesh next = subdivide(cage, scheme, level);
      for (size_t v = 0; v < previous.positions.size(); ++v)
        ASSERT_LT(glm::length(next.positions[v] - previous.positions[v]), 2e-5f) << "level " << level << " vertex " << v;
      previous = next;
    }
  }
}

TEST(Subdivide, RefinedPointsApproachTheLimitSurface) {
  // Max distance between consecutive levels' limit points shrinks: the cube's limit radius at the
  // face centres and corners is fixed, so the extremes converge.
  float previous_gap = 1e9f;
  for (int level = 1; level <= 5; ++level) {
    const SubdividedMesh a = subdivide(cube_cage(), SubdivisionScheme::catmull_clark, level);
    float min_r = 1e9f, max_r = 0.0f;
    for (const glm::vec3& p : a.positions) {
      min_r = std::min(min_r, glm::length(p));
      max_r = std::max(max_r, glm::length(p));
    }
    EXPECT_LE(max_r - min_r, previous_gap + 1e-6f);
    previous_gap = max_r - min_r;
  }
}

TEST(Subdivide, InfinitelySharpCreasesKeepTheCube) {
  ControlMesh cage = cube_cage();
  for (size_t f = 0; f < 6; ++f)
    for (int i = 0; i < 4; ++i) {
      const uint32_t a = cage.face_indices[f * 4 + i], b = cage.face_indices[f * 4 + (i + 1) % 4];
      if (a < b) cage.creases.push_back({a, b, 10.0f});
    }
  ASSERT_EQ(cage.creases.size(), 12u);
  const SubdividedMesh m = subdivide(cage, SubdivisionScheme::catmull_clark, 3);
  for (uint32_t corner = 0; corner < 8; ++corner)
    EXPECT_LT(glm::length(m.positions[corner] - cage.positions[corner]), 1e-6f) << corner;
  for (const glm::vec3& p : m.positions)  // every point on the cube's surface
    EXPECT_NEAR(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 1.0f, 1e-5f);
  EXPECT_NEAR(signed_volume(m.positions, m.triangles), 8.0, 1e-4);
}

TEST(Subdivide, CreaseVertexOrderDoesNotMatter) {
  ControlMesh forward = cube_cage(), backward = cube_cage();
  forward.creases = {{0, 1, 3.0f}, {1, 5, 10.0f}};
  backward.creases = {{1, 0, 3.0f}, {5, 1, 10.0f}};
  const SubdividedMesh a = subdivide(forward, SubdivisionScheme::catmull_clark, 3);
  const SubdividedMesh b = subdivide(backward, SubdivisionScheme::catmull_clark, 3);
  EXPECT_EQ(a.positions, b.positions);
  const SubdividedMesh smooth = subdivide(cube_cage(), SubdivisionScheme::catmull_clark, 3);
  EXPECT_NE(a.positions, smooth.positions);  // the creases did something
}

TEST(Subdivide, SemiSharpCreasesLieBetweenSmoothAndSharp) {
  ControlMesh cage = cube_cage();
  const SubdividedMesh smooth = subdivide(cage, SubdivisionScheme::catmull_clark, 3);
  for (size_t f = 0; f < 6; ++f)
    for (int i = 0; i < 4; ++i) {
      const uint32_t a = cage.face_indices[f * 4 + i], b = cage.face_indices[f * 4 + (i + 1) % 4];
      if (a < b) cage.creases.push_back({a, b, 1.5f});
    }
  const SubdividedMesh creased = subdivide(cage, SubdivisionScheme::catmull_clark, 3);
  const float r_smooth = glm::length(smooth.positions[0]), r_creased = glm::length(creased.positions[0]);
  EXPECT_GT(r_creased, r_smooth + 0.05f);
  EXPECT_LT(r_creased, std::sqrt(3.0f) - 0.05f);
}

TEST(Subdivide, EulerCharacteristicPreserved) {
  EXPECT_EQ(euler_characteristic(subdivide(cube_cage(), SubdivisionScheme::catmull_clark, 3)), 2);
  EXPECT_EQ(euler_characteristic(subdivide(torus_cage(), SubdivisionScheme::catmull_clark, 3)), 0);
  EXPECT_EQ(euler_characteristic(subdivide(tetrahedron_cage(), SubdivisionScheme::loop, 4)), 2);
  EXPECT_EQ(euler_characteristic(subdivide(cube_cage(), SubdivisionScheme::catmull_clark, 0)), 2);
}

// Every interior edge is crossed in opposite directions by its two triangles.
void expect_consistently_oriented(const SubdividedMesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const glm::uvec3& t : m.triangles)
    for (int i = 0; i < 3; ++i) ++directed[{t[i], t[(i + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    ASSERT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " used twice in one direction";
    ASSERT_TRUE(directed.count({edge.second, edge.first})) << "closed mesh has a border edge";
  }
}

TEST(Subdivide, RandomlyPerturbedCagesKeepTopologyAndOrientation) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
  for (int trial = 0; trial < 12; ++trial) {
    const int kind = trial % 3;  // cube, torus, tetrahedron (Loop)
    const bool loop = kind == 2;
    ControlMesh cage = kind == 0 ? cube_cage() : kind == 1 ? torus_cage(5 + trial % 4, 4 + trial % 3) : tetrahedron_cage();
    for (glm::vec3& p : cage.positions) p += glm::vec3(jitter(rng), jitter(rng), jitter(rng));
    if (trial % 2) cage.creases.push_back({cage.face_indices[0], cage.face_indices[1], float(trial % 5) * 2.5f});
    const int level = 1 + trial % 3;
    const SubdividedMesh m = subdivide(cage, loop ? SubdivisionScheme::loop : SubdivisionScheme::catmull_clark, level);
    expect_consistently_oriented(m);
    EXPECT_EQ(euler_characteristic(m), kind == 1 ? 0 : 2) << "trial " << trial;
    EXPECT_GT(signed_volume(m.positions, m.triangles), 0.0) << "trial " << trial;
  }
}

TEST(Subdivide, OrientationAndNormalsPointOutward) {
  for (int level : {0, 1, 3}) {
    for (SubdivisionScheme scheme : {SubdivisionScheme::catmull_clark, SubdivisionScheme::loop}) {
      const ControlMesh cage = scheme == SubdivisionScheme::loop ? tetrahedron_cage() : cube_cage();
      const SubdividedMesh m = subdivide(cage, scheme, level);
      EXPECT_GT(signed_volume(m.positions, m.triangles), 0.01) << "level " << level;
      for (size_t v = 0; v < m.positions.size(); ++v) {
        EXPECT_NEAR(glm::length(m.normals[v]), 1.0f, 1e-4f);
        // Convex, centred at the origin: the outward normal has a positive radial component.
        EXPECT_GT(glm::dot(m.normals[v], glm::normalize(m.positions[v])), 0.5f) << "level " << level << " vertex " << v;
      }
    }
  }
  // The same cage turned inside out gives a negative volume and inward normals.
  ControlMesh inverted = cube_cage();
  for (size_t f = 0; f < 6; ++f) std::reverse(inverted.face_indices.begin() + 4 * f, inverted.face_indices.begin() + 4 * f + 4);
  const SubdividedMesh m = subdivide(inverted, SubdivisionScheme::catmull_clark, 2);
  EXPECT_LT(signed_volume(m.positions, m.triangles), -0.1);
  EXPECT_LT(glm::dot(m.normals[0], m.positions[0]), 0.0f);
}

TEST(Subdivide, LimitNormalsMatchTheSurface) {
  // On a smooth surface the limit normal agrees with the normals of the refined triangles around it.
  const SubdividedMesh m = subdivide(torus_cage(), SubdivisionScheme::catmull_clark, 4);
  std::vector<glm::vec3> face_sum(m.positions.size(), glm::vec3(0.0f));
  for (const glm::uvec3& t : m.triangles) {
    const glm::vec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    face_sum[t.x] += n;
    face_sum[t.y] += n;
    face_sum[t.z] += n;
  }
  for (size_t v = 0; v < m.positions.size(); ++v)
    EXPECT_GT(glm::dot(m.normals[v], glm::normalize(face_sum[v])), 0.99f) << v;
}

TEST(Subdivide, LimitNormalsAreNormalToTheLimitSurface) {
  // A vertex keeps its index across levels, so its neighbours at a deep level trace the limit
  // surface around it: chords to them are perpendicular to the limit normal computed at level 1
  // (face-averaged normals of the coarse level 1 mesh would be off by several degrees).
  const ControlMesh cage = torus_cage(5, 4);
  const SubdividedMesh coarse = subdivide(cage, SubdivisionScheme::catmull_clark, 1);
  const SubdividedMesh fine = subdivide(cage, SubdivisionScheme::catmull_clark, 6);
  std::vector<float> worst(coarse.positions.size(), 0.0f);
  for (const glm::uvec3& t : fine.triangles)
    for (int i = 0; i < 3; ++i) {
      const uint32_t v = t[i], w = t[(i + 1) % 3];
      if (v >= coarse.positions.size()) continue;
      const glm::vec3 chord = glm::normalize(fine.positions[w] - fine.positions[v]);
      worst[v] = std::max(worst[v], std::abs(glm::dot(chord, coarse.normals[v])));
    }
  for (size_t v = 0; v < worst.size(); ++v) EXPECT_LT(worst[v], 0.03f) << v;
}

TEST(Subdivide, OpenSurfaceKeepsBoundaryAndCorners) {
  // A 2x2 grid of quads in the xz plane, facing +y.
  ControlMesh cage;
  for (int z = 0; z < 3; ++z)
    for (int x = 0; x < 3; ++x) cage.positions.emplace_back(float(x), 0.0f, float(z));
  for (uint32_t z = 0; z < 2; ++z)
    for (uint32_t x = 0; x < 2; ++x) {
      cage.face_sizes.push_back(4);
      for (uint32_t v : {z * 3 + x, (z + 1) * 3 + x, (z + 1) * 3 + x + 1, z * 3 + x + 1}) cage.face_indices.push_back(v);
    }
  const int level = 3;
  const SubdividedMesh m = subdivide(cage, SubdivisionScheme::catmull_clark, level);
  Mesh mesh;
  mesh.positions = m.positions;
  mesh.triangles = m.triangles;
  const EdgeTable table = build_edge_table(mesh);
  EXPECT_EQ(table.border_edges, 8u << level);
  for (uint32_t corner : {0u, 2u, 6u, 8u}) EXPECT_EQ(m.positions[corner], cage.positions[corner]);
  for (const glm::vec3& n : m.normals) EXPECT_NEAR(n.y, 1.0f, 1e-5f);
}

TEST(Subdivide, LevelZeroPolygonsAreFanTriangulated) {
  // A pentagonal prism: two pentagons and five quads; level 0 keeps the cage points.
  ControlMesh cage;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 5; ++i) {
      const float a = 2.0f * std::numbers::pi_v<float> * i / 5;
      cage.positions.emplace_back(std::cos(a), k ? 1.0f : -1.0f, -std::sin(a));
    }
  auto face = [&](std::initializer_list<uint32_t> f) {
    cage.face_sizes.push_back(uint32_t(f.size()));
    cage.face_indices.insert(cage.face_indices.end(), f);
  };
  face({4, 3, 2, 1, 0});  // bottom, facing -y
  face({5, 6, 7, 8, 9});  // top, facing +y
  for (uint32_t i = 0; i < 5; ++i) face({i, (i + 1) % 5, (i + 1) % 5 + 5, i + 5});
  const SubdividedMesh flat = subdivide(cage, SubdivisionScheme::catmull_clark, 0);
  EXPECT_EQ(flat.triangles.size(), 3u + 3u + 10u);
  EXPECT_EQ(flat.positions, cage.positions);
  const double volume = signed_volume(flat.positions, flat.triangles);
  const SubdividedMesh smooth = subdivide(cage, SubdivisionScheme::catmull_clark, 2);
  EXPECT_EQ(smooth.triangles.size(), (2u * 30u) << 2);  // 30 quads at level 1
  EXPECT_GT(volume, 0.0);
  EXPECT_GT(signed_volume(smooth.positions, smooth.triangles), 0.0);
  EXPECT_EQ(euler_characteristic(smooth), 2);
}

TEST(Subdivide, LoopWithSharpEdgesKeepsTheTetrahedron) {
  ControlMesh cage = tetrahedron_cage();
  for (uint32_t a = 0; a < 4; ++a)
    for (uint32_t b = a + 1; b < 4; ++b) cage.creases.push_back({a, b, 10.0f});
  const SubdividedMesh m = subdivide(cage, SubdivisionScheme::loop, 3);
  for (uint32_t corner = 0; corner < 4; ++corner)
    EXPECT_LT(glm::length(m.positions[corner] - cage.positions[corner]), 1e-6f);
  EXPECT_NEAR(signed_volume(m.positions, m.triangles), 8.0 / 3.0, 1e-4);
}

TEST(Subdivide, AcceptsManifoldOddities) {
  // Two quads sharing only a vertex (a non-manifold vertex), and two triangles whose windings
  // disagree across their shared edge: OpenSubdiv handles both; the output stays well formed.
  ControlMesh bowtie;
  bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 0, 0}, {-1, -1, 0}, {0, -1, 0}};
  bowtie.face_sizes = {4, 4};
  bowtie.face_indices = {0, 1, 2, 3, 0, 4, 5, 6};
  const SubdividedMesh a = subdivide(bowtie, SubdivisionScheme::catmull_clark, 2);
  EXPECT_EQ(a.triangles.size(), 2u * 2u * 16u);
  expect_valid_indices(a);
  ControlMesh flipped;
  flipped.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  flipped.face_sizes = {3, 3};
  flipped.face_indices = {0, 1, 2, 1, 2, 3};  // edge (1,2) traversed the same way twice
  const SubdividedMesh b = subdivide(flipped, SubdivisionScheme::loop, 2);
  EXPECT_EQ(b.triangles.size(), 2u * 16u);
  expect_valid_indices(b);
  for (const glm::vec3& p : b.positions) EXPECT_TRUE(std::isfinite(p.x + p.y + p.z));
}

TEST(Subdivide, RandomCagesFailCleanlyOrGiveValidMeshes) {
  // Random polygon soups over few vertices (repeated edges, fans, bowties, bad indices): each one
  // either throws SubdivisionError or yields in-range indices and finite points, never crashes.
  std::mt19937 rng(5);
  int accepted = 0, rejected = 0;
  for (int trial = 0; trial < 400; ++trial) {
    ControlMesh cage;
    const uint32_t vertex_count = 3 + rng() % 8;
    for (uint32_t v = 0; v < vertex_count; ++v)
      cage.positions.emplace_back(float(rng() % 5), float(rng() % 5), float(rng() % 5));
    const SubdivisionScheme scheme = rng() % 2 ? SubdivisionScheme::loop : SubdivisionScheme::catmull_clark;
    const uint32_t faces = 1 + rng() % 6;
    for (uint32_t f = 0; f < faces; ++f) {
      const uint32_t size = scheme == SubdivisionScheme::loop ? 3 : 3 + rng() % 3;
      cage.face_sizes.push_back(size);
      for (uint32_t i = 0; i < size; ++i) cage.face_indices.push_back(rng() % (vertex_count + (trial % 10 == 0)));
    }
    if (rng() % 3 == 0) cage.creases.push_back({cage.face_indices[0], cage.face_indices[1], float(rng() % 11)});
    try {
      const SubdividedMesh m = subdivide(cage, scheme, 1 + trial % 3);
      ++accepted;
      expect_valid_indices(m);
      for (const glm::vec3& p : m.positions) ASSERT_TRUE(std::isfinite(p.x + p.y + p.z)) << "trial " << trial;
      for (const glm::vec3& n : m.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f) << "trial " << trial;
    } catch (const SubdivisionError&) {
      ++rejected;
    }
  }
  EXPECT_GT(accepted, 50);
  EXPECT_GT(rejected, 50);
}

void expect_error(const ControlMesh& cage, SubdivisionScheme scheme, int level, const std::string& words) {
  try {
    subdivide(cage, scheme, level);
    ADD_FAILURE() << "no error; expected one mentioning '" << words << "'";
  } catch (const SubdivisionError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(words), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(SubdivideErrors, Level) {
  expect_error(cube_cage(), SubdivisionScheme::catmull_clark, -1, "level -1 is outside 0..8");
  expect_error(cube_cage(), SubdivisionScheme::catmull_clark, 9, "level 9 is outside 0..8");
  EXPECT_NO_THROW(subdivide(cube_cage(), SubdivisionScheme::catmull_clark, 8));
}

TEST(SubdivideErrors, NonManifoldEdge) {
  ControlMesh cage;
  cage.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  cage.face_sizes = {3, 3, 3};
  cage.face_indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};  // three triangles on edge (0,1)
  expect_error(cage, SubdivisionScheme::loop, 2, "edge (0, 1) is shared by 3 faces (non-manifold)");
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "non-manifold");
}

TEST(SubdivideErrors, BadFaces) {
  ControlMesh cage = cube_cage();
  cage.face_indices[5] = 8;
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "face 1 uses vertex 8 but the cage has 8");
  cage = cube_cage();
  cage.face_indices[2] = cage.face_indices[0];
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "face 0 repeats vertex 0");
  cage = tetrahedron_cage();
  cage.face_sizes = {3, 3, 2, 4};
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "face 2 has 2 vertices (at least 3 needed)");
  cage = tetrahedron_cage();
  cage.face_sizes = {3, 3, 3, 2, 1};
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "face 3 has 2 vertices");
  cage = tetrahedron_cage();
  cage.face_sizes.push_back(3);
  expect_error(cage, SubdivisionScheme::loop, 1, "face sizes add up to 15 indices but 12 are given");
  expect_error(ControlMesh{}, SubdivisionScheme::loop, 1, "the cage has no faces");
  cage = cube_cage();
  cage.positions[3].y = std::numeric_limits<float>::quiet_NaN();
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "vertex 3 has a non-finite position");
}

TEST(SubdivideErrors, LoopNeedsTriangles) {
  expect_error(cube_cage(), SubdivisionScheme::loop, 1, "face 0 has 4 vertices: Loop subdivision needs triangles");
}

TEST(SubdivideErrors, Creases) {
  ControlMesh cage = cube_cage();
  cage.creases = {{0, 7, 10.0f}};  // a diagonal of the cube, not an edge
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "crease 0 (0, 7) is not an edge of the cage");
  cage.creases = {{0, 1, 2.0f}, {0, 99, 2.0f}};
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "crease 1 (0, 99) is not an edge of the cage");
  cage.creases = {{0, 0, 2.0f}};
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "is not an edge");
  cage.creases = {{1, 0, -1.0f}};
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "sharpness");
  cage.creases = {{1, 0, std::numeric_limits<float>::infinity()}};
  expect_error(cage, SubdivisionScheme::catmull_clark, 1, "sharpness");
  cage.creases = {{1, 0, 3.0f}};  // either orientation names the edge
  EXPECT_NO_THROW(subdivide(cage, SubdivisionScheme::catmull_clark, 1));
}

TEST(SubdivideErrors, TooManyTriangles) {
  ControlMesh cage = torus_cage(64, 32);  // 2048 quads: 2048 * 2 * 4^8 triangles at level 8
  expect_error(cage, SubdivisionScheme::catmull_clark, 8, "level 8 would make 268435456 triangles");
}

}  // namespace
}  // namespace epi

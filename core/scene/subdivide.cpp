// Subdivision through OpenSubdiv Far: validate the cage, refine uniformly, project to the limit.
// Conventions: boundaries are interpolated with their corners kept (VTX_BOUNDARY_EDGE_AND_CORNER),
// uniform creasing, cage vertex i stays vertex i at every level (OpenSubdiv's default ordering),
// refined faces are fan-triangulated from their first vertex, which keeps their orientation.
#include "scene/subdivide.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <string>

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

namespace epi {
namespace {

using namespace OpenSubdiv;

constexpr int kMaxLevel = 8;
constexpr uint64_t kMaxTriangles = uint64_t{1} << 26;  // ~67M triangles, ~1.6 GB of output

[[noreturn]] void fail(const std::string& message) { throw SubdivisionError("subdivision: " + message); }

uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t{a} << 32) | b : (uint64_t{b} << 32) | a;
}

// The checks OpenSubdiv does not do (or crashes on). Returns the sorted unique cage edges.
std::vector<uint64_t> validate(const ControlMesh& cage, SubdivisionScheme scheme, int level) {
  if (level < 0 || level > kMaxLevel)
    fail("level " + std::to_string(level) + " is outside 0.." + std::to_string(kMaxLevel));
  if (cage.face_sizes.empty()) fail("the cage has no faces");
  const size_t vertex_count = cage.positions.size();
  if (vertex_count >= size_t{1} << 31) fail("the cage has too many vertices");
  for (size_t v = 0; v < vertex_count; ++v) {
    const glm::vec3& p = cage.positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail("vertex " + std::to_string(v) + " has a non-finite position");
  }

  uint64_t corner_count = 0;
  for (size_t f = 0; f < cage.face_sizes.size(); ++f) {
    const uint32_t size = cage.face_sizes[f];
    if (size < 3) fail("face " + std::to_string(f) + " has " + std::to_string(size) + " vertices (at least 3 needed)");
    if (scheme == SubdivisionScheme::loop && size != 3)
      fail("face " + std::to_string(f) + " has " + std::to_string(size) + " vertices: Loop subdivision needs triangles");
    corner_count += size;
  }
  if (corner_count != cage.face_indices.size())
    fail("face sizes add up to " + std::to_string(corner_count) + " indices but " +
         std::to_string(cage.face_indices.size()) + " are given");

  // Per face: indices in range and distinct; collect (edge, face) pairs.
  std::vector<uint64_t> face_edges;
  face_edges.reserve(corner_count);
  size_t first = 0;
  for (size_t f = 0; f < cage.face_sizes.size(); ++f) {
    const uint32_t size = cage.face_sizes[f];
    const uint32_t* face = cage.face_indices.data() + first;
    for (uint32_t i = 0; i < size; ++i) {
      if (face[i] >= vertex_count)
        fail("face " + std::to_string(f) + " uses vertex " + std::to_string(face[i]) + " but the cage has " +
             std::to_string(vertex_count));
      for (uint32_t j = 0; j < i; ++j)
        if (face[j] == face[i]) fail("face " + std::to_string(f) + " repeats vertex " + std::to_string(face[i]));
      face_edges.push_back(edge_key(face[i], face[(i + 1) % size]));
    }
    first += size;
  }

  // More than two faces on an edge: non-manifold, which OpenSubdiv may crash on.
  std::sort(face_edges.begin(), face_edges.end());
  std::vector<uint64_t> edges;
  for (size_t i = 0; i < face_edges.size();) {
    size_t j = i;
    while (j < face_edges.size() && face_edges[j] == face_edges[i]) ++j;
    if (j - i > 2)
      fail("edge (" + std::to_string(face_edges[i] >> 32) + ", " + std::to_string(face_edges[i] & 0xffffffffu) +
           ") is shared by " + std::to_string(j - i) + " faces (non-manifold)");
    edges.push_back(face_edges[i]);
    i = j;
  }

  for (size_t c = 0; c < cage.creases.size(); ++c) {
    const Crease& crease = cage.creases[c];
    const std::string name = "crease " + std::to_string(c) + " (" + std::to_string(crease.v0) + ", " +
                             std::to_string(crease.v1) + ")";
    if (!std::isfinite(crease.sharpness) || crease.sharpness < 0.0f)
      fail(name + " has sharpness " + std::to_string(crease.sharpness) + " (needs a finite value >= 0)");
    if (!std::binary_search(edges.begin(), edges.end(), edge_key(crease.v0, crease.v1)))
      fail(name + " is not an edge of the cage");
  }

  // Refined triangle count, to refuse requests that cannot fit in memory.
  uint64_t triangles = 0;
  if (scheme == SubdivisionScheme::loop) {
    triangles = cage.face_sizes.size() << (2 * level);
  } else if (level == 0) {
    triangles = corner_count - 2 * cage.face_sizes.size();
  } else {
    triangles = (2 * corner_count) << (2 * (level - 1));
  }
  if (triangles > kMaxTriangles)
    fail("level " + std::to_string(level) + " would make " + std::to_string(triangles) + " triangles (limit " +
         std::to_string(kMaxTriangles) + ")");
  return edges;
}

// A primvar for Far::PrimvarRefiner.
struct Point {
  glm::vec3 p{0.0f};
  void Clear(void* = nullptr) { p = glm::vec3(0.0f); }
  void AddWithWeight(const Point& src, float weight) { p += weight * src.p; }
};

// Lets OpenSubdiv write limit positions straight into the output array.
struct PointRef {
  glm::vec3& p;
  void Clear(void* = nullptr) { p = glm::vec3(0.0f); }
  void AddWithWeight(const Point& src, float weight) { p += weight * src.p; }
};
struct PositionsAsPoints {
  glm::vec3* data;
  PointRef operator[](int i) const { return {data[i]}; }
};

thread_local std::string osd_error;
void record_osd_error(Far::ErrorType, const char* message) {
  if (osd_error.empty()) osd_error = message;
}

// Area-weighted vertex normals of a triangle mesh: the fallback where limit tangents degenerate.
std::vector<glm::vec3> face_weighted_normals(const std::vector<glm::vec3>& positions,
                                             const std::vector<glm::uvec3>& triangles) {
  std::vector<glm::vec3> normals(positions.size(), glm::vec3(0.0f));
  for (const glm::uvec3& t : triangles) {
    const glm::vec3 n = glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]);
    normals[t.x] += n;
    normals[t.y] += n;
    normals[t.z] += n;
  }
  return normals;
}

glm::vec3 normalized_or_zero(const glm::vec3& v) {
  const float length = glm::length(v);
  return length > 0.0f && std::isfinite(length) ? v / length : glm::vec3(0.0f);
}

}  // namespace

SubdividedMesh subdivide(const ControlMesh& cage, SubdivisionScheme scheme, int level) {
  validate(cage, scheme, level);

  // Topology: faces and creases as OpenSubdiv sees them.
  std::vector<int> face_sizes(cage.face_sizes.begin(), cage.face_sizes.end());
  std::vector<int> face_indices(cage.face_indices.begin(), cage.face_indices.end());
  std::vector<int> crease_pairs;
  std::vector<float> crease_weights;
  for (const Crease& c : cage.creases) {
    crease_pairs.push_back(static_cast<int>(c.v0));
    crease_pairs.push_back(static_cast<int>(c.v1));
    crease_weights.push_back(c.sharpness);
  }
  Far::TopologyDescriptor descriptor;
  descriptor.numVertices = static_cast<int>(cage.positions.size());
  descriptor.numFaces = static_cast<int>(face_sizes.size());
  descriptor.numVertsPerFace = face_sizes.data();
  descriptor.vertIndicesPerFace = face_indices.data();
  descriptor.numCreases = static_cast<int>(crease_weights.size());
  descriptor.creaseVertexIndexPairs = crease_pairs.data();
  descriptor.creaseWeights = crease_weights.data();

  Sdc::Options sdc_options;
  sdc_options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  const Sdc::SchemeType sdc_scheme = scheme == SubdivisionScheme::loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;

  osd_error.clear();
  Far::SetErrorCallback(record_osd_error);
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(descriptor, Factory::Options(sdc_scheme, sdc_options)));
  if (!refiner) fail("OpenSubdiv rejected the cage: " + (osd_error.empty() ? std::string("unknown error") : osd_error));

  Far::TopologyRefiner::UniformOptions uniform(level);
  uniform.fullTopologyInLastLevel = true;  // the limit projection needs edges and faces of the last level
  refiner->RefineUniform(uniform);

  // Refine positions level by level.
  std::vector<Point> current(cage.positions.size());
  for (size_t v = 0; v < cage.positions.size(); ++v) current[v].p = cage.positions[v];
  Far::PrimvarRefiner primvars(*refiner);
  for (int l = 1; l <= level; ++l) {
    std::vector<Point> next(refiner->GetLevel(l).GetNumVertices());
    primvars.Interpolate(l, current, next);
    current.swap(next);
  }

  // Faces of the last level, triangulated as fans (refined Catmull-Clark faces are quads: (a,b,c),(a,c,d)).
  SubdividedMesh out;
  const Far::TopologyLevel& last = refiner->GetLevel(level);
  bool all_quads_or_triangles = true;
  out.triangles.reserve(static_cast<size_t>(last.GetNumFaces()) * 2);
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    const Far::ConstIndexArray face = last.GetFaceVertices(f);
    const int expected = scheme == SubdivisionScheme::loop ? 3 : 4;
    if (face.size() != expected) all_quads_or_triangles = false;
    for (int i = 1; i + 1 < face.size(); ++i)
      out.triangles.emplace_back(static_cast<uint32_t>(face[0]), static_cast<uint32_t>(face[i]),
                                 static_cast<uint32_t>(face[i + 1]));
  }

  // Project to the limit surface. OpenSubdiv's limit masks assume quads (Catmull-Clark) or triangles (Loop)
  // around each vertex, which holds after one refinement; a level-0 cage with other faces keeps its points.
  const size_t vertex_count = current.size();
  out.positions.resize(vertex_count);
  std::vector<Point> du, dv;  // limit tangents
  if (all_quads_or_triangles) {
    du.resize(vertex_count);
    dv.resize(vertex_count);
    PositionsAsPoints limit{out.positions.data()};
    primvars.Limit(current, limit, du, dv);
  } else {
    for (size_t v = 0; v < vertex_count; ++v) out.positions[v] = current[v].p;
  }
  if (!osd_error.empty()) fail("OpenSubdiv failed: " + osd_error);
  std::vector<Point>().swap(current);
  refiner.reset();  // the refined topology is no longer needed

  // Normals: the limit normal (cross product of the tangents) where it is well defined and agrees with
  // the faces around the vertex; else (sharp corners, level-0 n-gons) the area-weighted face normal;
  // +z where even that vanishes (a vertex whose faces all have zero area).
  out.normals = face_weighted_normals(out.positions, out.triangles);
  for (size_t v = 0; v < vertex_count; ++v) {
    const glm::vec3 face_normal = normalized_or_zero(out.normals[v]);
    out.normals[v] = face_normal == glm::vec3(0.0f) ? glm::vec3(0.0f, 0.0f, 1.0f) : face_normal;  // always unit
    if (du.empty()) continue;
    const glm::vec3 n = glm::cross(normalized_or_zero(du[v].p), normalized_or_zero(dv[v].p));
    if (glm::length(n) > 1e-3f && glm::dot(n, face_normal) > 0.0f) out.normals[v] = glm::normalize(n);
  }
  return out;
}

}  // namespace epi

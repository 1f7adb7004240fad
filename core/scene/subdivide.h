// Subdivision surfaces through OpenSubdiv: a control mesh in, a triangle mesh out.
#pragma once

#include <stdexcept>
#include <vector>

#include "scene/scene.h"

namespace epi {

// A polygonal control cage. Vertices are shared between faces (welded).
struct ControlMesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> face_sizes;    // vertices per face (3 or more)
  std::vector<uint32_t> face_indices;  // concatenated, counter-clockwise seen from outside
  std::vector<Crease> creases;         // edges between control vertices, OpenSubdiv sharpness
};

struct SubdividedMesh {
  std::vector<glm::vec3> positions;     // refined vertices at `level`, projected to the limit surface
  std::vector<glm::uvec3> triangles;    // refined faces, triangulated, orientation kept
  std::vector<glm::vec3> normals;       // limit-surface normals per vertex
};

// Thrown with a one-line description of what is wrong with the cage (non-manifold, bad index...).
struct SubdivisionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Uniform refinement to `level` (0..8). Loop requires triangles.
SubdividedMesh subdivide(const ControlMesh& cage, SubdivisionScheme scheme, int level);

}  // namespace epi

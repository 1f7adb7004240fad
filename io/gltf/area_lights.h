// Emissive objects as polygonal area lights: world-space triangles, a power CDF for sampling,
// and the outline (boundary loops) that soft-shadow edges are cast from.
#pragma once

#include <vector>

#include "scene/scene.h"

namespace epi {

// Luminance of linear Rec.709 RGB.
float luminance(const glm::vec3& rgb);

// One AreaLight per Object whose mesh has triangles with an emissive material (in object order).
// Objects whose transform mirrors (negative determinant) get their triangles and outlines
// reversed, so that world-space winding is counter-clockwise seen from the emitting side.
std::vector<AreaLight> build_area_lights(const Scene& scene);

// The boundary loops of `mesh` (welded by position), each a closed loop of welded-vertex
// positions ordered along the triangles' winding: counter-clockwise seen from the side the
// triangles face. Empty for a closed (watertight) mesh.
std::vector<std::vector<glm::vec3>> boundary_loops(const Mesh& mesh);

}  // namespace epi

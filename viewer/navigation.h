// Camera navigation as in the tools people know (Embree's tutorials, OSPRay Studio, Blender):
// orbit about a target, pan, dolly, fly (look and move), frame the scene. Pure math on a Camera,
// no window: the viewer feeds it mouse and key deltas, tests call it directly.
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace epi::viewer {

// Degrees of orbit per pixel of mouse motion; dolly factor per wheel step.
inline constexpr float kOrbitDegreesPerPixel = 0.3f;
inline constexpr float kDollyPerStep = 0.9f;

// Rotates the eye about the target: dx turns about the camera's up axis (yaw), dy tilts about
// its right axis (pitch), stopping short of the up axis.
void orbit(Camera& camera, float dx_pixels, float dy_pixels);
// Moves eye and target together in the view plane so the point at the target's depth follows
// the mouse (dx, dy in pixels of a view `height` pixels tall).
void pan(Camera& camera, float dx_pixels, float dy_pixels, int height);
// Moves the eye towards the target (steps > 0) or away, by kDollyPerStep per step; never
// onto the target.
void dolly(Camera& camera, float steps);
// Fly mode: turns the view direction about the eye (the target moves).
void look(Camera& camera, float dx_pixels, float dy_pixels);
// Fly mode: moves eye and target by `local` = (right, up, forward) in world units.
void fly(Camera& camera, const glm::vec3& local);
// Looks at the bounds' centre from the current direction, at a distance that fits them.
void frame_bounds(Camera& camera, const Bounds& bounds);

// The camera basis: forward (unit, towards the target), right and true up.
struct Basis {
  glm::vec3 forward, right, up;
};
Basis basis(const Camera& camera);

}  // namespace epi::viewer

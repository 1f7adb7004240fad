// Shadow edges: a shadow event intersected with the receivers' faces, then clipped in one
// dimension along the event so that only the parts nearest the light remain (a nearer receiver,
// the blocker included, keeps the event from reaching farther ones). World space. See docs/edges.md.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "edges/receiver_tree.h"
#include "edges/shadow_events.h"

namespace epi::edges {

struct ReceiverView {
  const EdgeMesh* mesh = nullptr;
  const ReceiverTree* tree = nullptr;
  glm::dmat4 object_to_world{1.0}, world_to_object{1.0};
  uint32_t object = kNone;
  // A world-space bounding sphere of the receiver; receivers whose sphere misses an event's plane
  // are skipped without searching their faces. Infinite radius: always searched.
  glm::dvec3 bound_centre{0.0};
  double bound_radius = INFINITY;
};

struct ShadowEdge {
  glm::dvec3 a{0.0}, b{0.0};  // world space
  uint32_t receiver = kNone, face = kNone;  // receiver object and its face
  uint32_t blocker = kNone, light = kNone;
  EventKind kind = EventKind::hard;
  uint32_t event = kNone;  // index of the event it came from (in the caller's list)
};

// Appends the visible shadow edges of one event over the given receivers. Returns how many
// receivers had their faces searched (the others' bounding spheres miss the event's plane).
size_t shadow_edges_of_event(const ShadowEvent& event, uint32_t event_index, std::span<const ReceiverView> receivers,
                           std::vector<ShadowEdge>& out);

// The event's ray parameter u of a world point in (or near) its plane, and the distance parameter
// t along D(u): point = B(u) + t D(u). Exposed for tests.
glm::dvec2 event_coordinates(const ShadowEvent& event, const glm::dvec3& point);

}  // namespace epi::edges

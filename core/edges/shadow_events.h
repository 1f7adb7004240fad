// Shadow events (section 6.3, Appendix A): the planar wedges, in world space, that bound a
// blocker's shadow. Point, spot and directional lights give one hard event per silhouette edge of
// the blocker seen from the light; polygonal area lights give umbral and penumbral VE events
// (light vertex, blocker edge) and EV events (light edge, blocker vertex). See docs/edges.md.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "edges/edge_mesh.h"
#include "edges/edge_tree.h"

namespace epi::edges {

enum class EventKind : uint8_t { hard, umbral, penumbral };

// The wedge is { B(u) + t D(u) : 0 <= u <= 1, t >= 0 }:
//   vertex_edge: B(u) = blocker0 + u (blocker1 - blocker0), D(u) = B(u) - source0 (a light point)
//   edge_vertex: B(u) = blocker0 (a blocker vertex),         D(u) = blocker0 - S(u), S on source0..source1
//   parallel:    B(u) as vertex_edge,                         D(u) = source0 (the way the light travels)
enum class EventShape : uint8_t { vertex_edge, edge_vertex, parallel };

struct ShadowEvent {
  EventShape shape = EventShape::vertex_edge;
  EventKind kind = EventKind::hard;
  glm::dvec3 source0{0.0}, source1{0.0};
  glm::dvec3 blocker0{0.0}, blocker1{0.0};
  uint32_t light = kNone, blocker = kNone;  // scene light index, blocker object
  uint32_t blocker_v0 = kNone, blocker_v1 = kNone;  // welded blocker vertices (v1 = v0 for edge_vertex)

  glm::dvec3 base(double u) const;       // B(u)
  glm::dvec3 direction(double u) const;  // D(u)
  glm::dvec3 normal() const;             // of the event plane, not normalized
};

// A blocker as the event finders see it. `tree` may be null: brute force then.
struct BlockerView {
  const EdgeMesh* mesh = nullptr;
  const EdgeTree* tree = nullptr;
  glm::dmat4 object_to_world{1.0};
  uint32_t object = kNone;
};

// A light as the edge finder sees it, in world space.
struct EdgeLight {
  enum class Type { point, directional, area } type = Type::point;
  glm::dvec3 position{0.0};               // point and spot
  glm::dvec3 direction{0.0, 0.0, -1.0};   // directional: the way the light travels; spot: where it points
  double cone_cos = -2.0;                 // spot: cosine of the outer cone angle; below -1: no cone
  std::vector<std::vector<glm::dvec3>> outlines;  // area: polygon loops
  uint32_t object = kNone;                // area: the emitting object (never a blocker of itself)
};

// Appends the events of one light and one blocker. `light_index` is stored in each event.
void find_shadow_events(const BlockerView& blocker, const EdgeLight& light, uint32_t light_index,
                        std::vector<ShadowEvent>& out);

}  // namespace epi::edges

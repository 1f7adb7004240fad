// The edge finder over a whole scene: per-mesh edge data and trees (object space, shared by every
// object using the mesh), the edges seen from a viewpoint (silhouette, sharp, border), the
// light-blocker-receiver triples when no shader reports them, and shadow edges kept per
// (light, blocker) pair until the light, the blocker or one of its receivers moves.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "edges/edge_tree.h"
#include "edges/receiver_tree.h"
#include "edges/shadow_edges.h"
#include "edges/shadow_events.h"
#include "scene/scene.h"

namespace epi::edges {

enum class EdgeKind : uint8_t { silhouette, sharp, border, umbral, penumbral, shadow };
const char* to_string(EdgeKind kind);
inline constexpr int kEdgeKindCount = 6;

struct SceneEdge {
  EdgeKind kind = EdgeKind::silhouette;
  uint32_t object = kNone;  // the receiver for shadow edges
  glm::dvec3 a{0.0}, b{0.0};  // world space
  uint32_t blocker = kNone, light = kNone;  // shadow edges only
};

struct LightBlockerReceiver {
  uint32_t light = 0, blocker = 0, receiver = 0;
  auto operator<=>(const LightBlockerReceiver&) const = default;
};

// The per-object choice between the tree and brute force: a cost model whose constants were
// measured by bench/edges (docs/edges.md): the tree's cost is estimated from its work over a few
// fixed viewpoints around the mesh, brute force's from the face and edge counts.
struct FinderCost {
  double ns_per_node = 60.0, ns_per_tree_edge = 1.0, ns_per_tree_silhouette = 40.0;   // tree: traversal, leaf tests, sorted output
  double ns_per_face = 0.33, ns_per_brute_edge = 0.33, ns_per_brute_silhouette = 10.0;  // brute force
  bool operator==(const FinderCost&) const = default;
};

struct SceneEdgeSettings {
  EdgeTreeSettings tree;
  FinderCost cost;
  int force = 0;  // 0: choose by cost; 1: always the tree; -1: always brute force
  // A mesh sent to brute force keeps no tree (the tree is built to estimate its cost, then freed:
  // model only what the scene requires). true: keep every tree (`epi edges` times both finders).
  bool keep_unchosen_trees = false;
  // Receiver trees (the faces shadow edges are searched on) for every mesh; false: none, and
  // shadow_edges() must not be called (the frame loop with shadow edges off).
  bool receiver_trees = true;
  bool operator==(const SceneEdgeSettings&) const = default;
};

struct FinderChoice {
  bool tree = false;
  double tree_ns = 0.0, brute_ns = 0.0;  // the model's estimates
};

class SceneEdgeFinder {
 public:
  explicit SceneEdgeFinder(const Scene& scene, const SceneEdgeSettings& settings = {});

  // Lights in the scene's order: punctual lights, then area lights.
  const std::vector<EdgeLight>& lights() const { return lights_; }
  const std::vector<std::string>& light_names() const { return light_names_; }
  const FinderChoice& choice(uint32_t mesh) const { return meshes_[mesh].choice; }
  const EdgeMesh& edge_mesh(uint32_t mesh) const { return meshes_[mesh].edges; }
  // Empty (no nodes) for a mesh sent to brute force unless SceneEdgeSettings::keep_unchosen_trees.
  const EdgeTree& edge_tree(uint32_t mesh) const { return meshes_[mesh].tree; }
  const ReceiverTree& receiver_tree(uint32_t mesh) const { return meshes_[mesh].receivers; }
  double build_ms() const { return build_ms_; }
  const SceneEdgeSettings& settings() const { return settings_; }
  size_t memory_bytes() const;

  // Silhouette, sharp and border edges from a world-space eye point.
  void view_edges(const Scene& scene, const glm::dvec3& eye, std::vector<SceneEdge>& out) const;

  // Every (light, blocker, receiver) whose receiver may meet the blocker's shadow volume
  // (bounding spheres against the light's shadow cone); a blocker is always its own receiver.
  std::vector<LightBlockerReceiver> find_triples(const Scene& scene) const;

  // Shadow edges of the triples' (light, blocker) pairs over their receivers. A pair's edges are
  // reused while its light, blocker and receivers keep their transforms. Throws std::logic_error
  // for a finder built without receiver trees.
  void shadow_edges(const Scene& scene, std::span<const LightBlockerReceiver> triples, std::vector<SceneEdge>& out);
  size_t pairs_recomputed() const { return pairs_recomputed_; }
  // Work counters (docs/reliability.md): sphere tests of the last find_triples; receivers whose
  // faces were searched for an event, over all shadow_edges calls (the rest were culled by their
  // bounding sphere against the event's plane).
  uint64_t triple_tests() const { return triple_tests_; }
  uint64_t receiver_searches() const { return receiver_searches_; }

 private:
  struct MeshData {
    EdgeMesh edges;
    EdgeTree tree;
    ReceiverTree receivers;
    FinderChoice choice;
  };
  struct PairState {
    EdgeLight light;
    glm::dmat4 blocker_transform{1.0};
    std::vector<std::pair<uint32_t, glm::dmat4>> receivers;
    std::vector<ShadowEdge> edges;
  };
  BlockerView blocker_view(const Scene& scene, uint32_t object) const;
  static std::vector<EdgeLight> scene_lights(const Scene& scene, std::vector<std::string>* names);

  SceneEdgeSettings settings_;
  std::vector<MeshData> meshes_;
  std::vector<EdgeLight> lights_;
  std::vector<std::string> light_names_;
  std::map<std::pair<uint32_t, uint32_t>, PairState> pairs_;
  size_t pairs_recomputed_ = 0;
  mutable uint64_t triple_tests_ = 0;
  uint64_t receiver_searches_ = 0;
  double build_ms_ = 0.0;
};

}  // namespace epi::edges

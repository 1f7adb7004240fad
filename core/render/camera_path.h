// Camera paths for the frame loop: keys per frame for the camera and for object and punctual
// light offsets, read
// from a small text file (format: docs/camera-path.md) or taken from the scene's own path.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace epi::render {

struct CameraKey {
  double frame = 0;
  Camera camera;
};

struct ObjectKey {
  double frame = 0;
  uint32_t object = 0;
  glm::vec3 translate{0.0f};  // world-space offset added to the object's scene placement
};

struct LightKey {
  double frame = 0;
  uint32_t light = 0;         // index into Scene::punctual_lights (a point or spot light)
  glm::vec3 translate{0.0f};  // world-space offset added to the light's scene position
};

struct CameraPath {
  std::vector<CameraKey> cameras;  // sorted by frame
  std::vector<ObjectKey> objects;  // sorted by object, then frame
  std::vector<LightKey> lights;    // sorted by light, then frame

  // The camera at a frame: linear between keys, held before the first and after the last.
  Camera camera_at(double frame) const;
  // Every object's transform at a frame: the scene's, translated by its keys (linear, held).
  std::vector<glm::mat4> object_transforms_at(const Scene& scene, double frame) const;
  bool moves_objects() const { return !objects.empty(); }
  // Every punctual light's position at a frame: the scene's, translated by its keys (linear,
  // held); directional lights keep theirs (unused).
  std::vector<glm::vec3> light_positions_at(const Scene& scene, double frame) const;
  bool moves_lights() const { return !lights.empty(); }
  // The frame of the path's last key (camera, object or light); 0 for a path without keys.
  double last_frame() const;
};

// Where along a path each rendered frame is (docs/render.md, "The path on the clock"). Without a
// rate, frame f is path frame f. With one, the path advances by the loop's clock: each frame shows
// the clock's position (rate path frames a second, less the time paused), except that the first
// frame whose clock reaches one of the `exact` keys is drawn exactly at it, each in turn, so that
// it can be compared with a reference of that key; the last frame is exactly at the path's end.
// Positions never decrease. The caller reads the clock (milliseconds since the loop started).
class PathClock {
 public:
  PathClock(double rate, int last_frame, std::vector<int> exact);  // exact: sorted, each in [0, last_frame]
  double next(double clock_ms);  // the next frame's path position
  // Whether the last position is a key of `exact` (without a rate and without keys: every frame).
  bool exact() const { return exact_now_; }
  bool done() const;  // the path's end was drawn (and every exact key)
  void pause(double ms) { paused_ms_ += ms; }  // time the loop's clock should not count (writing files)
  int frames() const { return frames_; }

 private:
  double rate_;
  int last_;
  std::vector<int> exact_;
  size_t next_exact_ = 0;
  double paused_ms_ = 0.0, position_ = -1.0;
  bool exact_now_ = false;
  int frames_ = 0;
};

// Parses the text of a path file; errors are std::runtime_error("<source>:<line>: <problem>").
CameraPath parse_camera_path(std::string_view text, const std::string& source, const Scene& scene);
CameraPath read_camera_path(const std::filesystem::path& file, const Scene& scene);

// The scene's own path (Scene::camera_path) spread evenly over `frames` frames; without one, the
// default camera held still.
CameraPath scene_camera_path(const Scene& scene, int frames);

}  // namespace epi::render

namespace epi::render {

// One line of a path file (docs/camera-path.md), the inverse of the parser: numbers printed so
// that parsing gives back the same floats. Used by the viewer to print and record cameras.
std::string format_camera_key(double frame, const Camera& camera);
std::string format_object_key(double frame, const std::string& object, const glm::vec3& translate);
std::string format_light_key(double frame, const std::string& light, const glm::vec3& translate);

}  // namespace epi::render

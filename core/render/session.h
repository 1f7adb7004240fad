// An interactive rendering session: the narrow interface between a window (the viewer) and the
// frame loop. The session owns the ray scene, the shader and a FrameRenderer and runs frames on
// a thread of its own; the window thread only posts input (camera, object and light placement,
// settings, the hovered pixel, picks) and takes the newest finished frame. Neither ever waits for
// the other, and the shader stays asynchronous (docs/viewer.md, "Threads").
//
// Modes: epi and rendercache run the FrameRenderer; raytrace shades every pixel once per pass
// (the first pass at the pixel centres, later ones jittered) and accumulates the passes while
// nothing moves; reference renders --spp stratified samples per pixel once per view (as
// `epi render --mode reference`). Stage views show the frame loop's intermediate images.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>
#include <tbb/global_control.h>

#include "render/camera_path.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "shade/shader.h"

namespace epi::render {

enum class SessionMode { epi, rendercache, raytrace, reference };
enum class StageView { final, points, edges, classes, reachability, priority, depth };
inline constexpr int kStageViewCount = 7;
const char* to_string(SessionMode mode);
const char* to_string(StageView view);
// "epi", "rendercache", "raytrace", "reference"; throws std::invalid_argument otherwise.
SessionMode session_mode(const std::string& name);

struct SessionSettings {
  SessionMode mode = SessionMode::epi;
  FrameSettings frame;    // size, budget, sync, seed, anti-aliasing, edges, shader threads (epi, rendercache)
  ShaderSettings shader;  // kind, sample counts, seed
  int reference_spp = 16;
  int threads = 0;        // TBB worker limit for the whole process (0: all cores)
  StageView stage = StageView::final;
  double max_fps = 0.0;   // frame loop cap (0: as fast as it goes)
  uint64_t frame_limit = 0;  // stop after this many frames (0: never); the last one stays published
  // Changing any of these rebuilds the renderer (and the shader when `shader` changes): the point
  // cache starts empty. Changing stage, max_fps or frame_limit does not.
  bool needs_rebuild(const SessionSettings& other) const;
};

// What the window sets; the frame thread renders each frame from the newest post.
struct SessionInput {
  Camera camera;
  std::vector<glm::mat4> objects;  // object_to_world per scene object (empty: as loaded)
  std::vector<glm::vec3> lights;   // position per punctual light (empty: as loaded)
  SessionSettings settings;
  glm::ivec2 probe{-1, -1};        // the hovered pixel (reachability view), -1: none
  int highlight_object = -1;       // outlined in the image (-1: none)
  // A camera path played frame by frame on the frame thread: frame number n (counted from 1)
  // shows path frame n - 1 - path_start, as `epi render --camera-path` shows frame n - 1; camera,
  // objects and lights come from the path where it has keys for them (the fields above otherwise).
  std::shared_ptr<const CameraPath> path;
  uint64_t path_start = 0;
  // With path_rate > 0 the path runs on the wall clock instead, as `epi render --path-rate` runs
  // it on the loop's: a frame shows path frame min(last key, path_rate x seconds since
  // path_clock_start), however many frames the loop managed (docs/viewer.md, "Paths on the clock").
  double path_rate = 0.0;
  std::chrono::steady_clock::time_point path_clock_start;
  uint64_t sequence = 0;           // set by post(): the number of this input
  std::chrono::steady_clock::time_point time;  // set by post(): when it was posted
};

// A pick request: which object, and which world point, is seen at a pixel.
struct PickRequest {
  uint64_t id = 0;
  glm::ivec2 pixel{0};
};
struct PickResult {
  uint64_t id = 0;            // the request answered (0: none yet)
  int object = -1;            // -1: background or nothing known there
  glm::vec3 world{0.0f};      // the surface point seen there (valid when object >= 0)
};

// The 5x5 neighbourhood of the probed pixel after classification (the reachability view).
struct PixelProbe {
  glm::ivec2 pixel{-1, -1};   // -1: no probe
  uint32_t reach = 0;         // bits per reach_bit(dx, dy) (core/epi/reachability.h)
  int types[5][5] = {};       // pixel type per neighbour, [dy+2][dx+2] (-1 outside the image)
  bool samples[5][5] = {};    // the neighbour holds a usable sample
};

struct SessionFrame {
  uint64_t number = 0;          // frames rendered since the session started (0: none yet)
  int width = 0, height = 0;    // of image and display
  uint64_t input_sequence = 0;  // the newest input this frame reflects
  std::chrono::steady_clock::time_point input_time, done_time;
  Camera camera;
  double path_frame = -1.0;     // the path frame shown (SessionInput::path; -1: none)
  SessionSettings settings;     // as rendered
  RgbImage image;               // linear RGB of the chosen stage view
  std::vector<uint32_t> display;  // RGBA8 of `image` (made by the display function; empty without one)
  int64_t display_tag = -1;     // the display function's tag when it kept the pixels itself
  FrameStats stats;             // epi and rendercache
  double frame_ms = 0.0;        // the whole frame on the frame thread (stage view and display included)
  double mrays_per_second = 0.0;  // the shader's rays over the last second of wall time
  size_t cache_points = 0, cache_capacity = 0;
  int passes = 0;               // raytrace: passes accumulated; reference: 1 when done
  PixelProbe probe;
  std::vector<PickResult> picks;  // the last 16 picks answered, oldest first
  std::string error;            // a failure of the frame thread (e.g. an unusable camera); empty: none
};

class Session {
 public:
  // Converts a linear image into RGBA8 for display (run on the frame thread; may be empty): into
  // `rgba`, or into storage of its own (e.g. a mapped pixel buffer), then returning a tag for it
  // that the frame carries (SessionFrame::display_tag); -1: the pixels are in `rgba`.
  using DisplayFunction = std::function<int64_t(const RgbImage& image, std::vector<uint32_t>& rgba)>;
  // The scene must outlive the session. The first frame is rendered from `input`. Throws what
  // the renderer and shader throw for bad settings (before the thread starts).
  Session(const Scene& scene, const SessionInput& input, DisplayFunction display = {});
  ~Session();  // stops the frame thread (the shader's work in flight finishes first)
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Posts the newest input; returns its sequence number. Never waits for a frame.
  uint64_t post(SessionInput input);
  // Asks which object is seen at a pixel; the answer comes with a later frame (PickResult::id).
  uint64_t pick(glm::ivec2 pixel);
  // The newest finished frame, if newer than `have` (a frame number); copies under a short lock.
  bool take_frame(uint64_t have, SessionFrame& out) const;
  // The same without the pixels (out.image and out.display are left empty): the RGBA8 pixels go
  // straight to display_target(width, height) (e.g. a mapped pixel buffer; nullptr: skipped).
  using DisplayTarget = std::function<uint32_t*(int width, int height)>;
  bool take_frame(uint64_t have, SessionFrame& out, const DisplayTarget& display_target) const;
  // The newest frame's linear image (screenshots); returns its number (0: none yet).
  uint64_t copy_image(RgbImage& out) const;
  uint64_t frames() const { return frames_.load(); }
  // How many times the edge finder (the scene's edge trees) was built: once per scene and edge
  // settings, not once per rebuild of the frame loop.
  uint64_t edge_finder_builds() const { return edge_finder_builds_.load(); }
  // Blocks until a frame numbered >= n is published or the timeout passes (tests, --frames).
  bool wait_for_frame(uint64_t n, std::chrono::milliseconds timeout) const;

  const Scene& scene() const { return scene_; }
  // reference mode: the fraction of the image in progress done (1 when none is in progress).
  double reference_progress() const { return reference_progress_.load(); }

 private:
  void run();
  void rebuild(const SessionSettings& settings);
  void render_frame(const SessionInput& input, SessionFrame& frame);
  void render_raytrace_pass(const SessionInput& input, bool restart);
  void stage_image(const SessionInput& input, const RgbImage& final_image, SessionFrame& frame);
  void answer_pick(const PickRequest& request, const SessionInput& input, PickResult& out);
  void place_directly(const SessionInput& input);

  const Scene& scene_;
  DisplayFunction display_;
  std::unique_ptr<RayScene> ray_scene_;
  std::shared_ptr<edges::SceneEdgeFinder> edge_finder_;  // kept across rebuilds while its settings hold
  std::atomic<uint64_t> edge_finder_builds_{0};
  std::unique_ptr<Shader> shader_;
  std::unique_ptr<FrameRenderer> renderer_;
  std::unique_ptr<tbb::global_control> thread_limit_;
  SessionSettings built_;  // the settings the renderer and shader were made with

  // raytrace and reference accumulation (frame thread only)
  RgbImage accumulated_, averaged_;
  std::vector<int32_t> ray_objects_;   // object per pixel of the last raytrace pass
  int passes_ = 0;
  uint64_t accumulated_for_ = 0;  // a hash of what the accumulation was made for
  bool reference_done_ = false;
  RgbImage stage_;                // scratch for stage views
  std::vector<float> scratch_;

  // rays per second over the last second
  uint64_t rays_mark_ = 0;
  std::chrono::steady_clock::time_point rays_mark_time_;
  double mrays_per_second_ = 0.0;

  mutable std::mutex input_mutex_;
  std::condition_variable input_changed_;
  SessionInput input_;
  uint64_t next_sequence_ = 0;
  std::vector<PickRequest> picks_;
  uint64_t next_pick_ = 0;
  std::vector<PickResult> picks_answered_;  // frame thread only

  mutable std::mutex frame_mutex_;
  mutable std::condition_variable frame_ready_;
  mutable SessionFrame front_;  // the newest published frame (its pixels lent out in take_frame)
  SessionFrame back_;   // being filled by the frame thread
  std::atomic<uint64_t> frames_{0};
  std::atomic<double> reference_progress_{1.0};

  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace epi::render

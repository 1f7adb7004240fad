#include "app.h"

#define GL_GLEXT_PROTOTYPES
#define GLFW_INCLUDE_GLEXT
#include <GLFW/glfw3.h>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/parallel_for.h>

#include "epi/reachability.h"
#include "image_io.h"
#include "load_scene.h"
#include "display.h"
#include "navigation.h"
#include "overlay_layout.h"
#include "output.h"
#include "render/camera_path.h"
#include "render/session.h"
#include "script.h"

namespace epi::viewer {

namespace {

using Clock = std::chrono::steady_clock;
using render::SessionFrame;
using render::SessionInput;
using render::SessionMode;
using render::StageView;

// The renderer's extent for a framebuffer extent at a render scale (--render-scale): at least a pixel.
int render_extent(int framebuffer, double scale) { return std::max(1, int(std::lround(double(framebuffer) * scale))); }

double ms_between(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }

std::string glfw_error_text;
void on_glfw_error(int, const char* description) { glfw_error_text = description ? description : "unknown error"; }

// The shader hold of --test-hold-shader: the shading thread waits while this is set.
std::atomic<bool> shader_held{false};

// Statistics of a series (the --benchmark output).
struct Summary {
  double min = 0, median = 0, mean = 0, max = 0, p90 = 0, sigma = 0;
  size_t n = 0;
};
Summary summarize(std::vector<double> v) {
  Summary s;
  s.n = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front(), s.max = v.back(), s.median = v[v.size() / 2], s.p90 = v[std::min(v.size() - 1, v.size() * 9 / 10)];
  for (double x : v) s.mean += x;
  s.mean /= double(v.size());
  for (double x : v) s.sigma += (x - s.mean) * (x - s.mean);
  s.sigma = std::sqrt(s.sigma / double(v.size()));
  return s;
}

const char* const kModeNames[] = {"epi", "rendercache", "raytrace", "reference"};
const char* const kShaderNames[] = {"direct", "glossy", "gi"};
const char* const kStageNames[] = {"final", "points (age)", "edges (kind)", "pixel classes", "reachability (hover)", "priority", "depth"};
// One colour per loop stage of render::kFrameStages (shading is not the loop's time).
const ImU32 kStageTimeColors[] = {IM_COL32(255, 210, 40, 255), IM_COL32(255, 140, 0, 255), IM_COL32(80, 200, 80, 255),
                                  IM_COL32(60, 160, 255, 255), IM_COL32(160, 100, 255, 255), IM_COL32(255, 90, 170, 255),
                                  IM_COL32(200, 200, 200, 255), IM_COL32(255, 60, 60, 255), IM_COL32(170, 120, 60, 255),
                                  IM_COL32(120, 255, 230, 255)};
constexpr int kStageTimeCount = int(std::size(kStageTimeColors));
static_assert(kStageTimeCount == int(render::FrameStage::shade) && render::kFrameStages[kStageTimeCount - 1].loop &&
              !render::kFrameStages[kStageTimeCount].loop, "a colour per loop stage (the loop stages come first)");

const char* const kKeyHelp[][2] = {
    {"left drag", "orbit (on the selected object: move it)"},
    {"Ctrl+left drag", "move the selected object on the ground"},
    {"middle or Shift+left drag", "pan"},
    {"wheel", "dolly"},
    {"right drag", "fly: look around"},
    {"W A S D, Q E", "fly: move (Shift: faster)"},
    {"click", "select an object or a light marker"},
    {"F / R", "frame the scene / reset all"},
    {"C", "print the camera (path syntax)"},
    {"Ctrl+1..9 / 1..9", "store / recall a bookmark"},
    {"K", "record to --record FILE (again: stop)"},
    {"L", "play the --camera-path file"},
    {"F1..F7", "stage view (final ... depth)"},
    {"M", "next mode"},
    {"P", "screenshot (PNG and EXR)"},
    {"Tab / H / Escape", "panel and overlay / help / quit"},
};

struct Drag {
  enum class Kind { none, orbit, pan, look, object, light, pending } kind = Kind::none;
  int button = -1;
  double x = 0, y = 0;          // last pointer position (window coordinates)
  double start_x = 0, start_y = 0;
  double moved = 0;             // pointer travel since the press (pixels)
  uint64_t pick = 0;            // pending: the pick asked for
  bool ground = false;          // object or light: move on the ground plane (Ctrl)
  int index = -1;               // the object or light dragged
  glm::vec3 grab{0.0f};         // the world point grabbed
  glm::mat4 start_transform{1.0f};
  glm::vec3 start_position{0.0f};
  double pending_dx = 0, pending_dy = 0;  // pending: pointer motion before the pick's answer
};

class Viewer {
 public:
  Viewer(const ViewerOptions& options, const Scene& scene, const Camera& camera, std::optional<render::CameraPath> path,
         std::vector<ScriptCommand> script)
      : options_(options), scene_(scene), script_(std::move(script)) {
    if (path) path_ = std::make_shared<const render::CameraPath>(std::move(*path));
    initial_camera_ = camera;
    input_.camera = camera;
    for (const Object& o : scene.objects) input_.objects.push_back(o.object_to_world), loaded_objects_.push_back(o.object_to_world);
    for (const PunctualLight& l : scene.punctual_lights) input_.lights.push_back(l.position), loaded_lights_.push_back(l.position);
    SessionSettings& s = input_.settings;
    s.mode = render::session_mode(options.render.mode);
    s.frame.width = options.render.width, s.frame.height = options.render.height;
    s.frame.sample_budget = options.render.sample_budget;
    s.frame.sync = options.render.sync;
    s.frame.seed = options.render.seed;
    s.frame.soft_shadow_edges = options.render.soft_shadow_edges;
    s.frame.sparse_blend = options.render.sparse_blend;
    s.frame.sparse_effort = options.render.sparse_effort;
    if (!options.render.punctual_highlights) s.frame.cache.punctual_highlight_share = render::PointCacheSettings::kNoPunctualHighlights;
    s.frame.trace_ahead = options.render.trace_ahead;
    s.frame.rest_sample_budget = options.render.rest_sample_budget;
    s.frame.motion_sample_budget = options.render.motion_sample_budget;
    s.frame.motion_frame_ms = 1000.0 / options.ui_fps;  // frames faster than the window's are not seen
    if (options.render.sparse_occlusion_radius) s.frame.cache.sparse_occlusion_radius = *options.render.sparse_occlusion_radius;
    if (options.render.new_occluder_radius) s.frame.cache.new_occluder_radius = *options.render.new_occluder_radius;
    s.shader = cli::shader_settings(options.render);
    s.reference_spp = options.render.spp;
    s.threads = options.render.threads;
    s.max_fps = options.max_fps;
    s.frame_limit = uint64_t(options.frames);
    if (options.hold_shader) {
      shader_held = true;
      s.frame.before_shading_slice = [] {
        while (shader_held.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      };
    }
    encoder_.set_exposure(options.render.exposure);
    render_scale_ = options.render_scale;
    scene_radius_ = scene.world_bounds().empty() ? 1.0f : 0.5f * glm::length(scene.world_bounds().max - scene.world_bounds().min);
    if (path_) play_path(0);
  }

  int run();

 private:
  using SessionSettings = render::SessionSettings;

  void open_window();
  // Starts the --camera-path playing from its first key: frame by frame after frame `after`, or on
  // the clock from now (--path-rate).
  void play_path(uint64_t after) {
    playing_ = true, input_.path = path_, input_.path_start = after;
    input_.path_rate = options_.render.path_rate, input_.path_clock_start = std::chrono::steady_clock::now();
  }
  void close_window();
  void frame_input(double dt);
  void run_script();
  bool script_done() const { return script_at_ >= script_.size() && !script_hold_ && !script_drag_; }
  void mouse_button(int button, bool press, int mods, double x, double y);
  void cursor(double x, double y);
  // A drag under way that moves the camera or an object (not a light: its marker follows the pointer).
  bool moves_the_view() const { return drag_.kind != Drag::Kind::none && drag_.kind != Drag::Kind::light; }
  void scroll(double dy);
  void key(int key, bool press, int mods);
  void post_if_changed();
  void take_newest_frame();
  void draw_ui();
  void draw_panel();
  void draw_overlay();
  void draw_help();
  void draw_light_markers();
  void save_image(const std::string& file);
  void save_window(const std::string& file);
  void print_camera();
  void toggle_recording();
  void reset();
  glm::vec2 to_pixel(double x, double y) const;  // window coordinates -> image pixel
  Ray pointer_ray(double x, double y) const;
  std::optional<glm::vec3> on_plane(double x, double y, const glm::vec3& point, const glm::vec3& normal) const;
  std::optional<glm::vec2> project(const glm::vec3& world) const;
  void changed_by_user() {
    user_change_ = true;
    if (playing_) playing_ = false, input_.path = nullptr;  // the user takes over from the path
  }

  static void on_mouse_button(GLFWwindow* w, int button, int action, int mods);
  static void on_cursor(GLFWwindow* w, double x, double y);
  static void on_scroll(GLFWwindow* w, double dx, double dy);
  static void on_key(GLFWwindow* w, int key, int scancode, int action, int mods);

  const ViewerOptions& options_;
  const Scene& scene_;
  std::shared_ptr<const render::CameraPath> path_;
  std::vector<ScriptCommand> script_;
  size_t script_at_ = 0;
  int script_wait_ = 0;
  std::optional<ScriptCommand> script_hold_, script_drag_;
  int script_step_ = 0;

  GLFWwindow* window_ = nullptr;
  std::unique_ptr<FrameTexture> texture_;
  std::unique_ptr<PixelRing> ring_;  // must outlive session_ (its display function writes there)
  DisplayEncoder encoder_;
  std::unique_ptr<render::Session> session_;
  SessionInput input_, posted_;
  bool posted_once_ = false, user_change_ = false;
  uint64_t posted_sequence_ = 0;
  std::deque<std::pair<uint64_t, Clock::time_point>> pending_inputs_;  // user changes not yet on screen
  SessionFrame frame_;  // the newest frame taken
  std::string last_error_;  // the frame thread's last error, printed once
  // The last input that changes what the window draws other than through a new frame (the panel,
  // a hover, a click, a key; not a camera or object drag, a dolly or a held key: docs/viewer.md,
  // "Redraws"); the last redraw.
  Clock::time_point last_activity_{}, last_draw_{};
  size_t redraws_ = 0;  // window redraws, for --benchmark
  std::vector<uint32_t> staging_;
  Camera initial_camera_;
  std::vector<glm::mat4> loaded_objects_;
  std::vector<glm::vec3> loaded_lights_;
  float scene_radius_ = 1.0f;

  Drag drag_;
  std::optional<uint64_t> click_pick_;  // a click waiting for its pick's answer
  uint64_t last_pick_id_ = 0;
  int last_pick_object_ = -1;
  std::vector<std::string> window_shots_;  // window screenshots asked for this frame
  double pointer_x_ = -1, pointer_y_ = -1;
  std::set<int> held_keys_;
  int mods_ = 0;
  int selected_object_ = -1, selected_light_ = -1;
  std::array<std::optional<Camera>, 9> bookmarks_;
  bool show_panel_ = true, show_help_ = false;
  Rect panel_rect_;                               // the panel as last drawn
  bool panel_fold_decided_ = false;               // whether the panel starts folded was decided
  ImVec2 overlay_full_{0, 0}, overlay_compact_{0, 0};  // the overlay's two forms as last drawn
  bool quit_ = false;
  int window_width_ = 0, window_height_ = 0, fb_width_ = 0, fb_height_ = 0;
  Clock::time_point resized_at_{};
  bool resize_pending_ = false;
  double render_scale_ = 1.0;  // the renderer's size over the framebuffer's (--render-scale, the panel)

  // path playing and recording
  bool playing_ = false;
  bool recording_ = false;
  uint64_t record_start_ = 0;
  std::vector<std::string> recorded_;
  int screenshot_count_ = 0;

  // statistics
  struct StatPoint {
    Clock::time_point time;
    render::StageTimes ms;
    size_t samples;
  };
  std::deque<StatPoint> history_;
  std::deque<Clock::time_point> ui_frames_, render_frames_;
  std::vector<double> upload_ms_, upload_finish_ms_, latency_ms_, ui_frame_ms_, render_frame_ms_;
  double last_upload_ms_ = 0.0, last_latency_ms_ = 0.0;
  uint64_t ring_frames_ = 0, copied_frames_ = 0;  // new frames shown from the frame thread's pixel buffers / copied
  uint64_t frames_shown_ = 0;
};

Viewer* viewer_of(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

void Viewer::on_mouse_button(GLFWwindow* w, int button, int action, int mods) {
  viewer_of(w)->last_activity_ = Clock::now();
  if (ImGui::GetIO().WantCaptureMouse && action == GLFW_PRESS) return;
  double x, y;
  glfwGetCursorPos(w, &x, &y);
  viewer_of(w)->mouse_button(button, action == GLFW_PRESS, mods, x, y);
}
void Viewer::on_cursor(GLFWwindow* w, double x, double y) {
  Viewer& v = *viewer_of(w);
  // A drag that moves the camera or an object shows only through the frames it causes.
  if (!v.moves_the_view()) v.last_activity_ = Clock::now();
  v.cursor(x, y);
}
void Viewer::on_scroll(GLFWwindow* w, double, double dy) {
  if (ImGui::GetIO().WantCaptureMouse) {
    viewer_of(w)->last_activity_ = Clock::now();
    return;
  }
  viewer_of(w)->scroll(dy);  // a dolly: shows through the frames it causes
}
void Viewer::on_key(GLFWwindow* w, int key, int, int action, int mods) {
  if (action == GLFW_REPEAT) return;
  viewer_of(w)->last_activity_ = Clock::now();
  if (ImGui::GetIO().WantCaptureKeyboard && action != GLFW_RELEASE) return;
  viewer_of(w)->key(key, action == GLFW_PRESS, mods);
}

void Viewer::open_window() {
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit())
    throw std::runtime_error("cannot open a window: " + (glfw_error_text.empty() ? std::string("no display") : glfw_error_text) +
                             " (epi-viewer needs an X display; without one, run it under xvfb-run -a)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);  // HiDPI: the window grows, the renderer follows the framebuffer
  const std::string title = "epi-viewer: " + options_.render.scene;
  window_ = glfwCreateWindow(options_.render.width, options_.render.height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw std::runtime_error("cannot open a window: " + glfw_error_text);
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(1);
  glfwSetWindowUserPointer(window_, this);
  glfwSetMouseButtonCallback(window_, on_mouse_button);
  glfwSetCursorPosCallback(window_, on_cursor);
  glfwSetScrollCallback(window_, on_scroll);
  glfwSetKeyCallback(window_, on_key);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the user's files
  ImGui::StyleColorsDark();
  float scale_x = 1.0f, scale_y = 1.0f;  // HiDPI: the panel grows with the monitor's scale
  glfwGetWindowContentScale(window_, &scale_x, &scale_y);
  if (scale_x > 1.0f) ImGui::GetStyle().ScaleAllSizes(scale_x), ImGui::GetIO().FontGlobalScale = scale_x;
  ImGui_ImplGlfw_InitForOpenGL(window_, true);  // chains to the callbacks above
  ImGui_ImplOpenGL3_Init("#version 330");
  texture_ = std::make_unique<FrameTexture>();
  ring_ = std::make_unique<PixelRing>(glfwExtensionSupported("GL_ARB_buffer_storage"));
  glfwGetWindowSize(window_, &window_width_, &window_height_);
  glfwGetFramebufferSize(window_, &fb_width_, &fb_height_);
  input_.settings.frame.width = render_extent(fb_width_, render_scale_);
  input_.settings.frame.height = render_extent(fb_height_, render_scale_);
}

void Viewer::close_window() {
  texture_.reset();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window_);
  glfwTerminate();
}

glm::vec2 Viewer::to_pixel(double x, double y) const {
  const float sx = window_width_ > 0 ? float(input_.settings.frame.width) / float(window_width_) : 1.0f;
  const float sy = window_height_ > 0 ? float(input_.settings.frame.height) / float(window_height_) : 1.0f;
  return {float(x) * sx, float(y) * sy};
}

Ray Viewer::pointer_ray(double x, double y) const {
  View v;
  v.camera = input_.camera, v.width = input_.settings.frame.width, v.height = input_.settings.frame.height;
  const glm::vec2 p = to_pixel(x, y);
  return ViewFrame(v).ray(p.x, p.y);
}

std::optional<glm::vec3> Viewer::on_plane(double x, double y, const glm::vec3& point, const glm::vec3& normal) const {
  const Ray ray = pointer_ray(x, y);
  const float denom = glm::dot(ray.direction, normal);
  if (std::abs(denom) < 1e-6f) return std::nullopt;
  const float t = glm::dot(point - ray.origin, normal) / denom;
  if (!(t > 0.0f) || !std::isfinite(t)) return std::nullopt;
  return ray.origin + ray.direction * t;
}

std::optional<glm::vec2> Viewer::project(const glm::vec3& world) const {
  View v;
  v.camera = input_.camera, v.width = input_.settings.frame.width, v.height = input_.settings.frame.height;
  const Projection p = ViewFrame(v).project(world);
  if (!p.in_front()) return std::nullopt;
  const float sx = float(window_width_) / float(v.width), sy = float(window_height_) / float(v.height);
  return glm::vec2(p.pixel.x * sx, p.pixel.y * sy);
}

void Viewer::mouse_button(int button, bool press, int mods, double x, double y) {
  mods_ = mods;
  if (press) {
    if (drag_.kind != Drag::Kind::none) return;
    drag_ = Drag{};
    drag_.button = button, drag_.x = drag_.start_x = x, drag_.y = drag_.start_y = y;
    const bool shift = mods & GLFW_MOD_SHIFT;
    if (button == GLFW_MOUSE_BUTTON_MIDDLE || (button == GLFW_MOUSE_BUTTON_LEFT && shift)) {
      drag_.kind = Drag::Kind::pan;
    } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
      drag_.kind = Drag::Kind::look;
    } else if (button == GLFW_MOUSE_BUTTON_LEFT) {
      drag_.ground = mods & GLFW_MOD_CONTROL;
      // A light marker under the pointer takes the drag at once (the window knows where they are).
      for (size_t l = 0; l < input_.lights.size(); ++l) {
        if (scene_.punctual_lights[l].type == LightType::directional) continue;
        const auto p = project(input_.lights[l]);
        if (p && glm::distance(*p, glm::vec2(x, y)) <= 10.0f) {
          selected_light_ = int(l), selected_object_ = -1;
          drag_.kind = Drag::Kind::light, drag_.index = int(l), drag_.grab = input_.lights[l], drag_.start_position = input_.lights[l];
          return;
        }
      }
      // Otherwise ask the session what is under the pointer; orbit or move once it answers.
      const glm::vec2 p = to_pixel(x, y);
      drag_.kind = Drag::Kind::pending;
      drag_.pick = session_->pick(glm::ivec2(int(p.x), int(p.y)));
    }
    return;
  }
  if (button != drag_.button) return;
  // A click selects what its pick found (or, still unanswered, what it will find).
  if (drag_.kind == Drag::Kind::pending) {
    click_pick_ = drag_.pick;
  } else if (drag_.moved < 3.0 && (drag_.kind == Drag::Kind::orbit || drag_.kind == Drag::Kind::object)) {
    selected_object_ = last_pick_object_, selected_light_ = -1;
  }
  drag_ = Drag{};
}

void Viewer::cursor(double x, double y) {
  pointer_x_ = x, pointer_y_ = y;
  if (drag_.kind == Drag::Kind::none) return;
  const double dx = x - drag_.x, dy = y - drag_.y;
  drag_.moved += std::abs(dx) + std::abs(dy);
  drag_.x = x, drag_.y = y;
  const float scale = float(input_.settings.frame.height) / float(std::max(1, window_height_));
  switch (drag_.kind) {
    case Drag::Kind::none: break;
    case Drag::Kind::pending: drag_.pending_dx += dx, drag_.pending_dy += dy; break;
    case Drag::Kind::orbit: orbit(input_.camera, float(dx), float(dy)), changed_by_user(); break;
    case Drag::Kind::pan: pan(input_.camera, float(dx) * scale, float(dy) * scale, input_.settings.frame.height), changed_by_user(); break;
    case Drag::Kind::look: look(input_.camera, float(dx), float(dy)), changed_by_user(); break;
    case Drag::Kind::object:
    case Drag::Kind::light: {
      const glm::vec3 normal = drag_.ground ? glm::normalize(input_.camera.up) : basis(input_.camera).forward;
      const auto hit = on_plane(x, y, drag_.grab, normal);
      if (!hit) break;
      const glm::vec3 delta = *hit - drag_.grab;
      if (drag_.kind == Drag::Kind::object)
        input_.objects[size_t(drag_.index)] = glm::translate(glm::mat4(1.0f), delta) * drag_.start_transform;
      else
        input_.lights[size_t(drag_.index)] = drag_.start_position + delta;
      changed_by_user();
      break;
    }
  }
}

void Viewer::scroll(double dy) {
  dolly(input_.camera, float(dy));
  changed_by_user();
}

void Viewer::key(int key, bool press, int mods) {
  mods_ = mods;
  if (!press) {
    held_keys_.erase(key);
    return;
  }
  held_keys_.insert(key);
  const bool ctrl = mods & GLFW_MOD_CONTROL;
  if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) {
    auto& mark = bookmarks_[size_t(key - GLFW_KEY_1)];
    if (ctrl) {
      mark = input_.camera;
      std::printf("bookmark %d: %s\n", key - GLFW_KEY_0, render::format_camera_key(0, input_.camera).c_str());
    } else if (mark) {
      input_.camera = *mark, changed_by_user();
    }
  } else if (key >= GLFW_KEY_F1 && key < GLFW_KEY_F1 + render::kStageViewCount) {
    input_.settings.stage = StageView(key - GLFW_KEY_F1);
  }
  switch (key) {
    case GLFW_KEY_F: frame_bounds(input_.camera, scene_.world_bounds()), changed_by_user(); break;
    case GLFW_KEY_R: reset(); break;
    case GLFW_KEY_C: print_camera(); break;
    case GLFW_KEY_H: show_help_ = !show_help_; break;
    case GLFW_KEY_TAB: show_panel_ = !show_panel_; break;
    case GLFW_KEY_M: input_.settings.mode = SessionMode((int(input_.settings.mode) + 1) % 4); break;
    case GLFW_KEY_K: toggle_recording(); break;
    case GLFW_KEY_L:
      if (path_) play_path(frame_.number);
      break;
    case GLFW_KEY_P: {
      const std::string base = "epi-screenshot-" + std::to_string(++screenshot_count_);
      save_image(base + ".png");
      save_image(base + ".exr");
      break;
    }
    case GLFW_KEY_ESCAPE: quit_ = true; break;
    default: break;
  }
}

void Viewer::reset() {
  changed_by_user();  // stops a path playing
  input_.camera = initial_camera_;
  input_.objects = loaded_objects_;
  input_.lights = loaded_lights_;
}

void Viewer::print_camera() {
  // The camera, then keys for what was moved (paste them into a path file), then where each
  // point and spot light is (world, and its marker in the window).
  std::printf("%s\n", render::format_camera_key(0, input_.camera).c_str());
  for (size_t o = 0; o < input_.objects.size(); ++o)
    if (input_.objects[o] != loaded_objects_[o])
      std::printf("%s\n", render::format_object_key(0, scene_.objects[o].name, glm::vec3(input_.objects[o][3]) - glm::vec3(loaded_objects_[o][3])).c_str());
  for (size_t l = 0; l < input_.lights.size(); ++l) {
    if (scene_.punctual_lights[l].type == LightType::directional) continue;
    if (input_.lights[l] != loaded_lights_[l])
      std::printf("%s\n", render::format_light_key(0, scene_.punctual_lights[l].name, input_.lights[l] - loaded_lights_[l]).c_str());
    const glm::vec3 p = input_.lights[l];
    const auto marker = project(p);
    std::printf("# light '%s' at %g %g %g, marker at window pixel %.0f %.0f\n", scene_.punctual_lights[l].name.c_str(), p.x, p.y, p.z,
                marker ? marker->x : -1.0f, marker ? marker->y : -1.0f);
  }
  std::fflush(stdout);
}

void Viewer::toggle_recording() {
  if (!recording_) {
    if (options_.record.empty()) {
      std::fprintf(stderr, "epi-viewer: K records to --record FILE, and none was given\n");
      return;
    }
    recording_ = true, record_start_ = frame_.number, recorded_.clear();
    return;
  }
  recording_ = false;
  std::string text = "# recorded by epi-viewer from " + options_.render.scene + "\n";
  for (const std::string& line : recorded_) text += line + "\n";
  cli::StagedOutputs out;
  out.add_text(options_.record, text);
  out.commit();
  std::printf("recorded %zu keys to %s\n", recorded_.size(), options_.record.c_str());
}

void Viewer::save_image(const std::string& file) {
  if (frame_.number == 0) {
    std::fprintf(stderr, "epi-viewer: %s: no frame has been rendered yet\n", file.c_str());
    return;
  }
  ImageWriteOptions o;
  o.exposure = encoder_.exposure();
  RgbImage image;
  session_->copy_image(image);
  write_image(file, image, o);
}

void Viewer::save_window(const std::string& file) {
  std::vector<uint8_t> rgb(size_t(fb_width_) * size_t(fb_height_) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, fb_width_, fb_height_, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  // The screen's bytes, as linear values whose tone map gives them back: write_image (8-bit)
  // then writes the same bytes.
  RgbImage image(fb_width_, fb_height_);
  const auto& lut = srgb8_to_linear();
  for (int y = 0; y < fb_height_; ++y)
    for (int x = 0; x < fb_width_; ++x) {
      float display[3];
      for (int c = 0; c < 3; ++c) display[c] = lut[rgb[(size_t(fb_height_ - 1 - y) * size_t(fb_width_) + size_t(x)) * 3 + size_t(c)]];
      inverse_tone_map(display, image.at(x, y));
    }
  write_image(file, image);
}

void Viewer::frame_input(double dt) {
  // Fly: held keys move the camera, at half the scene per second (Shift: four times as fast).
  glm::vec3 move(0.0f);
  auto held = [&](int k) { return held_keys_.count(k) > 0; };
  if (held(GLFW_KEY_W)) move.z += 1;
  if (held(GLFW_KEY_S)) move.z -= 1;
  if (held(GLFW_KEY_D)) move.x += 1;
  if (held(GLFW_KEY_A)) move.x -= 1;
  if (held(GLFW_KEY_E)) move.y += 1;
  if (held(GLFW_KEY_Q)) move.y -= 1;
  if (move != glm::vec3(0.0f)) {
    const float speed = scene_radius_ * 0.5f * (held(GLFW_KEY_LEFT_SHIFT) || held(GLFW_KEY_RIGHT_SHIFT) ? 4.0f : 1.0f);
    fly(input_.camera, move * float(dt) * speed);
    changed_by_user();
  }
  // A path plays on the frame thread, frame by frame or on the clock (--path-rate); the window
  // follows what it shows.
  if (playing_ && frame_.number > input_.path_start && frame_.path_frame >= 0.0) {
    const double f = frame_.path_frame;
    if (!path_->cameras.empty()) input_.camera = frame_.camera;
    if (path_->moves_objects()) input_.objects = path_->object_transforms_at(scene_, f);
    if (path_->moves_lights()) input_.lights = path_->light_positions_at(scene_, f);
  }
  // The hovered pixel for the reachability view.
  if (pointer_x_ >= 0 && pointer_y_ >= 0) {
    const glm::vec2 p = to_pixel(pointer_x_, pointer_y_);
    input_.probe = glm::ivec2(int(p.x), int(p.y));
  }
  input_.highlight_object = selected_object_;
}

void Viewer::run_script() {
  if (script_wait_ > 0) {
    --script_wait_;
    return;
  }
  if (script_hold_) {
    if (--script_step_ <= 0) key(script_hold_->key, false, 0), script_hold_.reset();
    return;
  }
  if (script_drag_) {
    if (drag_.kind == Drag::Kind::pending) return;  // the pick decides between orbit and move
    const ScriptCommand& c = *script_drag_;
    ++script_step_;
    const double t = double(script_step_) / double(c.frames);
    cursor(c.x0 + (c.x1 - c.x0) * t, c.y0 + (c.y1 - c.y0) * t);
    if (script_step_ >= c.frames) {
      const int button = c.button == Button::left ? GLFW_MOUSE_BUTTON_LEFT : c.button == Button::middle ? GLFW_MOUSE_BUTTON_MIDDLE : GLFW_MOUSE_BUTTON_RIGHT;
      mouse_button(button, false, mods_, c.x1, c.y1);
      script_drag_.reset();
    }
    return;
  }
  // Pending picks are answered by the frame loop: the script waits for them (a click or a drag
  // on an object needs the answer to know what it touched).
  if (drag_.kind == Drag::Kind::pending || click_pick_) return;
  while (script_at_ < script_.size()) {
    const ScriptCommand& c = script_[script_at_++];
    const int button = c.button == Button::left ? GLFW_MOUSE_BUTTON_LEFT : c.button == Button::middle ? GLFW_MOUSE_BUTTON_MIDDLE : GLFW_MOUSE_BUTTON_RIGHT;
    using K = ScriptCommand::Kind;
    switch (c.kind) {
      case K::wait: script_wait_ = c.frames; return;
      case K::key:
        key(c.key, true, c.mods);
        key(c.key, false, c.mods);
        break;
      case K::hold: key(c.key, true, 0), script_hold_ = c, script_step_ = c.frames; return;
      case K::click:
        cursor(c.x0, c.y0);
        mouse_button(button, true, mods_, c.x0, c.y0);
        mouse_button(button, false, mods_, c.x0, c.y0);
        return;
      case K::drag:
        cursor(c.x0, c.y0);
        mouse_button(button, true, mods_, c.x0, c.y0);
        script_drag_ = c, script_step_ = 0;
        return;
      case K::move: cursor(c.x0, c.y0); break;
      case K::scroll: scroll(c.scroll); break;
      case K::screenshot:
        // The image of what the script has done so far: wait for a frame that reflects it.
        frame_input(0.0);
        post_if_changed();
        if (frame_.number == 0 || frame_.input_sequence < posted_sequence_) {
          --script_at_;
          return;
        }
        save_image(c.file);
        break;
      case K::window_screenshot:
        frame_input(0.0);
        post_if_changed();
        if (frame_.number == 0 || frame_.input_sequence < posted_sequence_) {
          --script_at_;
          return;
        }
        window_shots_.push_back(c.file);
        return;  // taken at the end of this window frame
      case K::resize: glfwSetWindowSize(window_, int(c.x0), int(c.y0)); return;
      case K::quit: quit_ = true; return;
    }
  }
  if (script_done() && !options_.script.empty()) quit_ = true;
}

void Viewer::post_if_changed() {
  const bool changed = !posted_once_ || user_change_ || input_.camera.eye != posted_.camera.eye ||
                       input_.camera.target != posted_.camera.target || input_.camera.up != posted_.camera.up ||
                       input_.camera.yfov_degrees != posted_.camera.yfov_degrees || input_.objects != posted_.objects ||
                       input_.lights != posted_.lights || input_.probe != posted_.probe ||
                       input_.highlight_object != posted_.highlight_object || input_.settings.stage != posted_.settings.stage ||
                       input_.settings.needs_rebuild(posted_.settings) || input_.settings.max_fps != posted_.settings.max_fps ||
                       input_.path != posted_.path || input_.path_start != posted_.path_start;
  if (!changed) return;
  const uint64_t sequence = session_->post(input_);
  posted_sequence_ = sequence;
  if (user_change_) pending_inputs_.push_back({sequence, Clock::now()});
  posted_ = input_;
  posted_once_ = true;
  user_change_ = false;
}

void Viewer::take_newest_frame() {
  // The display cost: the frame's RGBA8 copied from the session straight into a mapped PBO, and
  // the texture upload issued.
  const auto start = Clock::now();
  bool mapped = false;
  const bool taken = session_->take_frame(frame_.number, frame_, [&](int w, int h) {
    uint32_t* target = texture_->begin_upload(w, h);
    mapped = target != nullptr;
    return target;
  });
  if (!taken) return;
  if (mapped) {
    texture_->finish_upload();
    ++copied_frames_;
  } else if (frame_.display_tag >= 0) {
    mapped = ring_->upload(frame_.display_tag, *texture_, frame_.width, frame_.height);
    ring_frames_ += mapped;
  }
  const auto now = Clock::now();
  ++frames_shown_;
  if (frame_.error != last_error_ && !frame_.error.empty()) std::fprintf(stderr, "epi-viewer: %s\n", frame_.error.c_str());
  last_error_ = frame_.error;
  if (mapped) {
    last_upload_ms_ = ms_between(start, now);
    upload_ms_.push_back(last_upload_ms_);
    if (options_.benchmark > 0) {  // the upload's full cost, the driver's copy included
      const auto t = Clock::now();
      glFinish();
      upload_finish_ms_.push_back(last_upload_ms_ + ms_between(t, Clock::now()));
    }
  }
  render_frames_.push_back(now);
  render_frame_ms_.push_back(frame_.frame_ms);
  history_.push_back({now, frame_.stats.ms, frame_.stats.samples});
  while (!history_.empty() && ms_between(history_.front().time, now) > 5000.0) history_.pop_front();
  // Input-to-screen latency: the first frame that reflects each user change.
  while (!pending_inputs_.empty() && pending_inputs_.front().first <= frame_.input_sequence) {
    last_latency_ms_ = ms_between(pending_inputs_.front().second, now);
    latency_ms_.push_back(last_latency_ms_);
    pending_inputs_.pop_front();
  }
  // Picks: a drag waiting for one starts now; a click selects.
  for (const render::PickResult& pick : frame_.picks) {
    if (pick.id <= last_pick_id_) continue;
    last_pick_id_ = pick.id, last_pick_object_ = pick.object;
    if (drag_.kind == Drag::Kind::pending && drag_.pick == pick.id) {
      if (pick.object >= 0 && pick.object == selected_object_) {
        drag_.kind = Drag::Kind::object, drag_.index = pick.object, drag_.grab = pick.world;
        drag_.start_transform = input_.objects[size_t(pick.object)];
        const double x = drag_.x, y = drag_.y;
        cursor(x, y);
      } else {
        drag_.kind = Drag::Kind::orbit;
        orbit(input_.camera, float(drag_.pending_dx), float(drag_.pending_dy));
        if (drag_.pending_dx != 0 || drag_.pending_dy != 0) changed_by_user();
      }
    }
    if (click_pick_ && *click_pick_ == pick.id) {
      selected_object_ = pick.object, selected_light_ = -1;
      click_pick_.reset();
    }
  }
  // Recording: one key per renderer frame shown.
  if (recording_) {
    const double f = double(frame_.number - record_start_);
    recorded_.push_back(render::format_camera_key(f, frame_.camera));
    for (size_t o = 0; o < input_.objects.size(); ++o)
      if (input_.objects[o] != loaded_objects_[o])
        recorded_.push_back(render::format_object_key(f, scene_.objects[o].name,
                                                      glm::vec3(input_.objects[o][3]) - glm::vec3(loaded_objects_[o][3])));
    for (size_t l = 0; l < input_.lights.size(); ++l)
      if (input_.lights[l] != loaded_lights_[l])
        recorded_.push_back(render::format_light_key(f, scene_.punctual_lights[l].name, input_.lights[l] - loaded_lights_[l]));
  }
}

void Viewer::draw_light_markers() {
  ImDrawList* draw = ImGui::GetBackgroundDrawList();
  for (size_t l = 0; l < input_.lights.size(); ++l) {
    if (scene_.punctual_lights[l].type == LightType::directional) continue;
    const auto p = project(input_.lights[l]);
    if (!p) continue;
    const bool selected = int(l) == selected_light_;
    draw->AddCircle(ImVec2(p->x, p->y), 8.0f, selected ? IM_COL32(255, 140, 0, 255) : IM_COL32(255, 255, 120, 220), 16, 2.0f);
    draw->AddCircleFilled(ImVec2(p->x, p->y), 2.5f, IM_COL32(255, 255, 120, 255));
    draw->AddText(ImVec2(p->x + 10, p->y - 7), IM_COL32(255, 255, 160, 255), scene_.punctual_lights[l].name.c_str());
  }
}

void Viewer::draw_overlay() {
  const auto now = Clock::now();
  while (!ui_frames_.empty() && ms_between(ui_frames_.front(), now) > 1000.0) ui_frames_.pop_front();
  while (!render_frames_.empty() && ms_between(render_frames_.front(), now) > 1000.0) render_frames_.pop_front();
  // Beside the panel, never over it (overlay_layout.h); each form is its own ImGui window so each
  // keeps its own measured size.
  const OverlayPlacement at = place_overlay(panel_rect_, overlay_full_.x, overlay_full_.y, overlay_compact_.x,
                                            overlay_compact_.y, float(window_width_), float(window_height_));
  ImGui::SetNextWindowPos(ImVec2(at.x, at.y), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin(at.compact ? "overlay (compact)" : "overlay", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs);
  ImGui::Text("window %zu fps | frames %zu fps (%.1f ms)", ui_frames_.size(), render_frames_.size(), frame_.frame_ms);
  if (at.compact) {
    ImGui::Text("%s, %dx%d, %s shader | %zu samples/frame", render::to_string(frame_.settings.mode), frame_.width,
                frame_.height, kShaderNames[int(frame_.settings.shader.kind)], frame_.stats.samples);
    if (!frame_.error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.3f, 0.3f, 1.0f), "%s", frame_.error.c_str());
    overlay_compact_ = ImGui::GetWindowSize();
    ImGui::End();
    return;
  }
  ImGui::Text("%s, %dx%d%s, %s shader", render::to_string(frame_.settings.mode), frame_.width, frame_.height,
              frame_.width == fb_width_ ? "" : " (scaled up)", kShaderNames[int(frame_.settings.shader.kind)]);
  if (frame_.settings.mode == SessionMode::epi || frame_.settings.mode == SessionMode::rendercache) {
    ImGui::Text("samples/frame %zu (asked %zu, lag %.1f) | %.1f Mrays/s", frame_.stats.samples, frame_.stats.requested,
                frame_.stats.result_lag, frame_.mrays_per_second);
    ImGui::Text("cache %.1f%% of %zu points", frame_.cache_capacity ? 100.0 * double(frame_.cache_points) / double(frame_.cache_capacity) : 0.0,
                frame_.cache_capacity);
  } else {
    ImGui::Text("%s %d | %.1f Mrays/s", frame_.settings.mode == SessionMode::raytrace ? "passes" : "done", frame_.passes, frame_.mrays_per_second);
  }
  if (!frame_.error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.3f, 0.3f, 1.0f), "%s", frame_.error.c_str());
  if (session_->reference_progress() < 1.0) ImGui::Text("rendering the reference: %.0f%%", 100.0 * session_->reference_progress());
  ImGui::Text("input->screen %.0f ms | upload %.2f ms", last_latency_ms_, last_upload_ms_);
  // The per-stage time graph: one stacked bar per frame over the last 5 seconds.
  const ImVec2 size(300.0f, 70.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::Dummy(size);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y), IM_COL32(0, 0, 0, 120));
  double top = 1.0;
  for (const StatPoint& p : history_) top = std::max(top, p.ms.total);
  const float ms_to_px = size.y / float(top);
  for (const StatPoint& p : history_) {
    const float x = origin.x + size.x * float(1.0 - ms_between(p.time, now) / 5000.0);
    float y = origin.y + size.y;
    for (int k = 0; k < kStageTimeCount; ++k) {
      const float h = float(p.ms.ms[size_t(k)]) * ms_to_px;
      if (h > 0.0f) draw->AddLine(ImVec2(x, y), ImVec2(x, y - h), kStageTimeColors[k], 2.0f);
      y -= h;
    }
  }
  ImGui::Text("stage times, last 5 s (top %.1f ms):", top);
  for (int k = 0; k < kStageTimeCount; ++k) {
    if (k % 5) ImGui::SameLine();
    ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(kStageTimeColors[k]), "%s", render::kFrameStages[size_t(k)].label);
  }
  overlay_full_ = ImGui::GetWindowSize();
  ImGui::End();
}

void Viewer::draw_help() {
  if (!show_help_) return;
  ImGui::SetNextWindowPos(ImVec2(float(window_width_) * 0.5f, float(window_height_) * 0.5f), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  ImGui::Begin("keys (H)", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
  if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg)) {
    for (const auto& k : kKeyHelp) {
      ImGui::TableNextRow();
      ImGui::TableSetColumnIndex(0);
      ImGui::TextUnformatted(k[0]);
      ImGui::TableSetColumnIndex(1);
      ImGui::TextUnformatted(k[1]);
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

void Viewer::draw_panel() {
  if (!show_panel_) return;
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::Begin("epi-viewer (Tab, H: keys)", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::PushItemWidth(170.0f);
  SessionSettings& s = input_.settings;
  int mode = int(s.mode);
  if (ImGui::Combo("mode", &mode, kModeNames, 4)) s.mode = SessionMode(mode);
  int stage = int(s.stage);
  if (ImGui::Combo("view", &stage, kStageNames, render::kStageViewCount)) s.stage = StageView(stage);
  int shader = int(s.shader.kind);
  if (ImGui::Combo("shader", &shader, kShaderNames, 3)) s.shader.kind = ShaderKind(shader);
  if (ImGui::TreeNode("sample counts")) {
    auto count = [](const char* label, int& v, int low, int high) {
      int x = v;
      if (ImGui::InputInt(label, &x) && x >= low && x <= high) v = x;
    };
    count("area light", s.shader.area_light_samples, 1, 4096);
    count("glossy", s.shader.glossy_samples, 0, 4096);
    count("glossy light", s.shader.glossy_light_samples, 0, 4096);
    count("gi paths", s.shader.gi_paths, 0, 4096);
    count("gi light", s.shader.gi_light_samples, 0, 4096);
    count("gi bounces", s.shader.gi_max_bounces, 0, 64);
    count("reference spp", s.reference_spp, 1, 1 << 20);
    ImGui::TreePop();
  }
  float budget = float(s.frame.sample_budget);
  if (ImGui::SliderFloat("budget", &budget, 0.001f, 0.25f, "%.3f", ImGuiSliderFlags_Logarithmic)) s.frame.sample_budget = budget;
  float rest_budget = float(s.frame.rest_sample_budget);
  if (ImGui::SliderFloat("budget at rest", &rest_budget, 0.001f, 0.25f, "%.3f", ImGuiSliderFlags_Logarithmic))
    s.frame.rest_sample_budget = rest_budget;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("while nothing moves, the budget grows up to this as long as the shader keeps up");
  float motion_budget = float(s.frame.motion_sample_budget);
  if (ImGui::SliderFloat("budget in motion", &motion_budget, 0.001f, 0.25f, "%.3f", ImGuiSliderFlags_Logarithmic))
    s.frame.motion_sample_budget = motion_budget;
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("while moving, the budget grows up to this as long as the shader keeps up and frames come faster than the window's");
  ImGui::Checkbox("anti-aliasing", &s.frame.antialias);
  ImGui::SameLine();
  ImGui::Checkbox("complex filter", &s.frame.complex_filter);
  ImGui::Checkbox("view edges", &s.frame.view_edges);
  ImGui::SameLine();
  ImGui::Checkbox("shadow edges", &s.frame.shadow_edges);
  ImGui::Checkbox("soft shadow edges", &s.frame.soft_shadow_edges);
  ImGui::SameLine();
  ImGui::Checkbox("occlusion test", &s.frame.occlusion_test);
  ImGui::Checkbox("occlusion culling", &s.frame.occlusion_culling);
  ImGui::SameLine();
  ImGui::Checkbox("fill holes", &s.frame.fill_holes);
  ImGui::Checkbox("smooth sparse regions", &s.frame.sparse_blend);
  ImGui::SameLine();
  bool highlights = s.frame.cache.punctual_highlights();
  if (ImGui::Checkbox("punctual highlights", &highlights))
    s.frame.cache.punctual_highlight_share = highlights ? render::PointCacheSettings{}.punctual_highlight_share : render::PointCacheSettings::kNoPunctualHighlights;
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("point and spot lights' highlights recomputed for every frame's eye, not shown as shaded");
  ImGui::Checkbox("sync", &s.frame.sync);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("shade the budget inside each frame (deterministic for a seed)");
  ImGui::Checkbox("trace ahead (camera extrapolated by the lag)", &s.frame.trace_ahead);
  int threads = s.threads;
  if (ImGui::InputInt("threads (0: all)", &threads) && threads >= 0 && threads <= 1024) s.threads = threads;
  float max_fps = float(s.max_fps);
  if (ImGui::SliderFloat("frame cap", &max_fps, 0.0f, 240.0f, max_fps == 0.0f ? "none" : "%.0f fps")) s.max_fps = max_fps;
  float render_scale = float(render_scale_);
  if (ImGui::SliderFloat("render scale", &render_scale, 0.1f, 1.0f, "%.2f")) {  // the flag's range
    render_scale_ = render_scale, resized_at_ = Clock::now(), resize_pending_ = true;  // applied as a resize is
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("render this share of the window's width and height, scaled up to it: 0.5 renders a quarter of the pixels");
  float exposure = encoder_.exposure();
  if (ImGui::SliderFloat("exposure", &exposure, -8.0f, 8.0f, "%.1f stops")) encoder_.set_exposure(exposure);
  if (ImGui::SliderFloat("fov", &input_.camera.yfov_degrees, 5.0f, 120.0f, "%.1f deg")) changed_by_user();
  if (ImGui::Button("frame (F)")) frame_bounds(input_.camera, scene_.world_bounds()), changed_by_user();
  ImGui::SameLine();
  if (ImGui::Button("reset (R)")) reset();
  ImGui::SameLine();
  if (ImGui::Button("print (C)")) print_camera();
  ImGui::SameLine();
  if (ImGui::Button(recording_ ? "stop (K)" : "record (K)")) toggle_recording();

  if (ImGui::CollapsingHeader("objects")) {
    for (size_t o = 0; o < scene_.objects.size(); ++o) {
      ImGui::PushID(int(o));
      if (ImGui::Selectable(scene_.objects[o].name.c_str(), selected_object_ == int(o))) selected_object_ = int(o), selected_light_ = -1;
      if (selected_object_ == int(o)) {
        glm::vec3 t = glm::vec3(input_.objects[o][3]);
        if (ImGui::DragFloat3("position", &t.x, 0.01f * scene_radius_)) input_.objects[o][3] = glm::vec4(t, 1.0f), changed_by_user();
      }
      ImGui::PopID();
    }
  }
  if (ImGui::CollapsingHeader("lights")) {
    for (size_t l = 0; l < scene_.punctual_lights.size(); ++l) {
      const PunctualLight& light = scene_.punctual_lights[l];
      ImGui::PushID(int(1000 + l));
      const char* type = light.type == LightType::point ? "point" : light.type == LightType::spot ? "spot" : "directional";
      const std::string label = light.name + " (" + type + ")";
      if (ImGui::Selectable(label.c_str(), selected_light_ == int(l))) selected_light_ = int(l), selected_object_ = -1;
      if (selected_light_ == int(l) && light.type != LightType::directional)
        if (ImGui::DragFloat3("position", &input_.lights[l].x, 0.01f * scene_radius_)) changed_by_user();
      ImGui::PopID();
    }
    if (!scene_.area_lights.empty()) ImGui::TextDisabled("%zu area lights (move their objects)", scene_.area_lights.size());
  }
  if (s.stage == StageView::reachability && frame_.probe.pixel.x >= 0) {
    // The hovered pixel's 5x5: blue centre, green reached, red not; a dot: a usable sample.
    ImGui::Text("pixel (%d, %d), reach mask 0x%06x", frame_.probe.pixel.x, frame_.probe.pixel.y, frame_.probe.reach);
    const ImVec2 o = ImGui::GetCursorScreenPos();
    const float cell = 22.0f;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const ImVec2 a(o.x + float(dx + 2) * cell, o.y + float(dy + 2) * cell), b(a.x + cell - 2, a.y + cell - 2);
        const int type = frame_.probe.types[dy + 2][dx + 2];
        const bool centre = dx == 0 && dy == 0;
        const bool reached = !centre && (frame_.probe.reach >> reach_bit(dx, dy)) & 1u;
        draw->AddRectFilled(a, b, type < 0 ? IM_COL32(40, 40, 40, 255) : centre ? IM_COL32(50, 100, 255, 255) : reached ? IM_COL32(50, 200, 70, 255) : IM_COL32(200, 50, 40, 255));
        if (type == kTypeComplex) draw->AddRect(a, b, IM_COL32(255, 255, 255, 255), 0, 0, 2.0f);
        if (frame_.probe.samples[dy + 2][dx + 2]) draw->AddCircleFilled(ImVec2((a.x + b.x) * 0.5f, (a.y + b.y) * 0.5f), 3.0f, IM_COL32(255, 255, 255, 255));
      }
    ImGui::Dummy(ImVec2(cell * 5, cell * 5));
  }
  ImGui::PopItemWidth();
  const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
  panel_rect_ = {pos.x, pos.y, size.x, size.y};
  // Once its size is known (not on the frame it appears, when ImGui is still measuring it), a panel
  // that would hide much of a small window folds to its title bar (overlay_layout.h).
  if (!panel_fold_decided_ && !ImGui::IsWindowAppearing()) {
    panel_fold_decided_ = true;
    if (panel_starts_collapsed(panel_rect_, float(window_width_), float(window_height_))) ImGui::SetWindowCollapsed(true);
  }
  ImGui::End();
}

void Viewer::draw_ui() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  draw_light_markers();
  draw_panel();
  if (show_panel_) draw_overlay();
  draw_help();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

int Viewer::run() {
  open_window();
  // The frame thread encodes each frame straight into a mapped pixel buffer when one is free
  // (tagged), else into the frame's own pixels (copied into a PBO when taken).
  session_ = std::make_unique<render::Session>(scene_, input_, [this](const RgbImage& image, std::vector<uint32_t>& rgba) -> int64_t {
    int64_t tag = -1;
    if (uint32_t* pixels = ring_->acquire(image.width, image.height, tag)) {
      encoder_.encode(image, pixels);
      ring_->ready(tag);
      return tag;
    }
    rgba.resize(size_t(image.width) * size_t(image.height));
    encoder_.encode(image, rgba.data());
    return -1;
  });
  posted_ = input_, posted_once_ = true;
  const auto start = Clock::now();
  auto last = start;
  const auto ui_period = std::chrono::duration<double>(1.0 / options_.ui_fps);
  auto next_ui = start;
  bool benchmark_started = false;
  size_t benchmark_first_latency = 0, benchmark_first_upload = 0, benchmark_first_render = 0;
  Clock::time_point benchmark_start;
  uint64_t benchmark_first_frame = 0;
  while (!glfwWindowShouldClose(window_) && !quit_) {
    // Pace the window at --ui-fps (vsync caps it too where the display has it) without sleeping
    // through input: events wake the wait.
    const auto now0 = Clock::now();
    if (now0 < next_ui) glfwWaitEventsTimeout(std::chrono::duration<double>(next_ui - now0).count());
    glfwPollEvents();
    next_ui = std::max(next_ui + std::chrono::duration_cast<Clock::duration>(ui_period), Clock::now() - std::chrono::duration_cast<Clock::duration>(ui_period));
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;

    // The renderer follows the framebuffer size (times the render scale), once it has stayed the
    // same for 150 ms: a new size starts an empty point cache.
    int fw, fh;
    glfwGetFramebufferSize(window_, &fw, &fh);
    glfwGetWindowSize(window_, &window_width_, &window_height_);
    if (fw != fb_width_ || fh != fb_height_) fb_width_ = fw, fb_height_ = fh, resized_at_ = now, resize_pending_ = true;
    if (resize_pending_ && ms_between(resized_at_, now) > 150.0 && fw > 0 && fh > 0) {
      input_.settings.frame.width = render_extent(fw, render_scale_), input_.settings.frame.height = render_extent(fh, render_scale_);
      resize_pending_ = false;
    }

    run_script();
    if (options_.benchmark > 0) {
      // Benchmark: orbit a little every window frame, as a user dragging would.
      if (!benchmark_started && frame_.number >= 10) {
        benchmark_started = true, benchmark_start = now, benchmark_first_frame = frame_.number;
        benchmark_first_latency = latency_ms_.size(), benchmark_first_upload = upload_ms_.size();
        benchmark_first_render = render_frame_ms_.size();
        ui_frame_ms_.clear();
      }
      if (benchmark_started) {
        orbit(input_.camera, 2.0f, 0.0f), changed_by_user();
        ui_frame_ms_.push_back(dt * 1e3);
        if (ui_frame_ms_.size() > size_t(options_.benchmark)) quit_ = true;
      }
    }
    frame_input(dt);
    post_if_changed();
    const uint64_t shown = frame_.number;
    ring_->maintain();
    take_newest_frame();
    // --frames N ends the run at frame N, unless a script runs: then it only stops the renderer.
    if (options_.frames > 0 && options_.script.empty() && frame_.number >= uint64_t(options_.frames)) quit_ = true;

    // Redraw only when the window would show something new: a frame, the panel or a hover after
    // input (500 ms), a light's marker being dragged, a script, a screenshot, a resize, or a
    // quarter second passed (the panel's figures). Navigation (a camera or object drag, a dolly,
    // held keys) shows through the frames it causes: redrawing the same frame at --ui-fps while
    // the user drags took most of a core from the renderer under a software GL (docs/viewer.md,
    // "Redraws").
    const bool active = frame_.number != shown || ms_between(last_activity_, now) < 500.0 || !options_.script.empty() ||
                        drag_.kind == Drag::Kind::light || ImGui::GetIO().WantTextInput || !window_shots_.empty() ||
                        resize_pending_ || ms_between(last_draw_, now) > 250.0;
    if (!active) continue;
    last_draw_ = now;
    ui_frames_.push_back(now);
    redraws_ += benchmark_started;
    glViewport(0, 0, fb_width_, fb_height_);
    glClearColor(0.05f, 0.05f, 0.05f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    texture_->draw(fb_width_, fb_height_);
    draw_ui();
    for (const std::string& file : window_shots_) save_window(file);
    window_shots_.clear();
    glfwSwapBuffers(window_);
  }

  if (!options_.screenshot.empty()) save_image(options_.screenshot);
  if (options_.benchmark > 0) {
    const double seconds = std::chrono::duration<double>(Clock::now() - benchmark_start).count();
    auto tail = [](const std::vector<double>& v, size_t first) { return std::vector<double>(v.begin() + ptrdiff_t(std::min(first, v.size())), v.end()); };
    const Summary ui = summarize(ui_frame_ms_);
    const Summary rf = summarize(tail(render_frame_ms_, benchmark_first_render));
    const Summary up = summarize(tail(upload_ms_, benchmark_first_upload));
    const Summary upf = summarize(tail(upload_finish_ms_, benchmark_first_upload));
    const Summary lat = summarize(tail(latency_ms_, benchmark_first_latency));
    const double frames = double(frame_.number - benchmark_first_frame);
    std::printf("epi-viewer benchmark: %s, %dx%d (window %dx%d), %s, %s shader, %zu window frames over %.2f s\n",
                options_.render.scene.c_str(), frame_.width, frame_.height, fb_width_, fb_height_, render::to_string(frame_.settings.mode),
                kShaderNames[int(frame_.settings.shader.kind)], ui.n, seconds);
    std::printf("BENCHMARK_WINDOW_FPS %.1f (frame ms: median %.2f, min %.2f, max %.2f, sigma %.2f)\n", ui.mean > 0 ? 1000.0 / ui.mean : 0.0,
                ui.median, ui.min, ui.max, ui.sigma);
    std::printf("BENCHMARK_RENDER_FPS %.1f (frames shown %.0f; frame-loop ms: median %.2f, min %.2f, max %.2f)\n",
                seconds > 0 ? frames / seconds : 0.0, frames, rf.median, rf.min, rf.max);
    std::printf("BENCHMARK_REDRAWS %.1f a second (%zu window redraws: a new frame, or the panel's quarter-second refresh)\n",
                seconds > 0 ? double(redraws_) / seconds : 0.0, redraws_);
    std::printf("BENCHMARK_DISPLAY_MS median %.3f, max %.3f (the texture takes the frame from its pixel buffer, CPU); with glFinish median %.3f, max %.3f\n",
                up.median, up.max, upf.median, upf.max);
    std::printf("BENCHMARK_DISPLAY_PATH %llu frames from the frame thread's pixel buffers, %llu copied (no buffer free)\n",
                (unsigned long long)ring_frames_, (unsigned long long)copied_frames_);
    std::printf("BENCHMARK_LATENCY_MS median %.1f, p90 %.1f, max %.1f (input to the first frame on screen that reflects it; %zu inputs)\n",
                lat.median, lat.p90, lat.max, lat.n);
  }
  shader_held = false;  // a held shader lets go, so the session can stop
  session_.reset();
  ring_.reset();
  close_window();
  return 0;
}

}  // namespace

int run_viewer(const ViewerOptions& options) {
  // Everything the CLI checks, checked the same way, before any window opens.
  const cli::RenderOptions& r = options.render;
  cli::shader_settings(r);
  cli::check_sample_budget(r);
  std::vector<std::string> outputs;
  if (!options.screenshot.empty()) cli::check_output_image(options.screenshot), outputs.push_back(options.screenshot);
  if (!options.record.empty()) cli::check_output_file(options.record), outputs.push_back(options.record);
  std::vector<ScriptCommand> script;
  if (!options.script.empty()) {
    script = read_script(options.script);
    for (const ScriptCommand& c : script)
      if (c.kind == ScriptCommand::Kind::screenshot || c.kind == ScriptCommand::Kind::window_screenshot) {
        try {
          cli::check_output_image(c.file);
        } catch (const std::exception& e) {
          throw std::runtime_error(options.script + ":" + std::to_string(c.line) + ": " + e.what());
        }
      }
  }
  cli::check_distinct_outputs(outputs);
  LoadOptions load;
  load.subdiv_level_override = r.subdiv_level;
  const Scene scene = load_scene(r.scene, load);
  cli::report_repairs(scene, false);
  std::optional<render::CameraPath> path;
  if (!r.camera_path.empty()) path = render::read_camera_path(r.camera_path, scene);
  const Camera camera = path && !path->cameras.empty() ? path->camera_at(0) : cli::apply_camera_override(scene, r.camera);
  View view;
  view.camera = camera, view.width = r.width, view.height = r.height;
  const ViewFrame check(view);  // an unusable camera fails here, as in `epi render`
  Viewer viewer(options, scene, camera, std::move(path), std::move(script));
  return viewer.run();
}

}  // namespace epi::viewer

#include "render/camera_path.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

namespace epi::render {

namespace {

// glm::mix, except that a component equal at both keys is that value exactly: a(1 - t) + a t
// may differ from a in its last bit, and a held view or placement (two equal keys) must not
// move (the renderer's rest, FrameSettings::rest_sample_budget; a placement that moves starts a
// new epoch of shading).
glm::vec3 mix_keys(const glm::vec3& a, const glm::vec3& b, float t) {
  const glm::vec3 m = glm::mix(a, b, t);
  return {a.x == b.x ? a.x : m.x, a.y == b.y ? a.y : m.y, a.z == b.z ? a.z : m.z};
}

Camera lerp(const Camera& a, const Camera& b, float t) {
  Camera c = a;
  c.eye = mix_keys(a.eye, b.eye, t);
  c.target = mix_keys(a.target, b.target, t);
  c.up = mix_keys(a.up, b.up, t);
  c.yfov_degrees = a.yfov_degrees + (b.yfov_degrees - a.yfov_degrees) * t;
  return c;
}

// Index of the last key at or before `frame` among keys[first, last), and the blend to the next.
template <class Key>
std::pair<size_t, float> locate(const std::vector<Key>& keys, size_t first, size_t last, double frame) {
  if (frame <= keys[first].frame) return {first, 0.0f};
  if (frame >= keys[last - 1].frame) return {last - 1, 0.0f};
  size_t k = first;
  while (k + 1 < last && keys[k + 1].frame <= frame) ++k;
  const double span = keys[k + 1].frame - keys[k].frame;
  return {k, span > 0.0 ? float((frame - keys[k].frame) / span) : 0.0f};
}

}  // namespace

double CameraPath::last_frame() const {
  double last = 0.0;
  for (const CameraKey& k : cameras) last = std::max(last, k.frame);
  for (const ObjectKey& k : objects) last = std::max(last, k.frame);
  for (const LightKey& k : lights) last = std::max(last, k.frame);
  return last;
}

Camera CameraPath::camera_at(double frame) const {
  if (cameras.empty()) return Camera{};
  const auto [k, t] = locate(cameras, 0, cameras.size(), frame);
  return t > 0.0f ? lerp(cameras[k].camera, cameras[k + 1].camera, t) : cameras[k].camera;
}

std::vector<glm::mat4> CameraPath::object_transforms_at(const Scene& scene, double frame) const {
  std::vector<glm::mat4> out;
  for (const Object& o : scene.objects) out.push_back(o.object_to_world);
  for (size_t first = 0; first < objects.size();) {
    size_t last = first;
    while (last < objects.size() && objects[last].object == objects[first].object) ++last;
    const auto [k, t] = locate(objects, first, last, frame);
    const glm::vec3 offset = t > 0.0f ? mix_keys(objects[k].translate, objects[k + 1].translate, t) : objects[k].translate;
    glm::mat4& m = out[objects[first].object];
    m = glm::translate(glm::mat4(1.0f), offset) * m;
    first = last;
  }
  return out;
}

std::vector<glm::vec3> CameraPath::light_positions_at(const Scene& scene, double frame) const {
  std::vector<glm::vec3> out;
  for (const PunctualLight& l : scene.punctual_lights) out.push_back(l.position);
  for (size_t first = 0; first < lights.size();) {
    size_t last = first;
    while (last < lights.size() && lights[last].light == lights[first].light) ++last;
    const auto [k, t] = locate(lights, first, last, frame);
    out[lights[first].light] += t > 0.0f ? mix_keys(lights[k].translate, lights[k + 1].translate, t) : lights[k].translate;
    first = last;
  }
  return out;
}

CameraPath parse_camera_path(std::string_view text, const std::string& source, const Scene& scene) {
  const Camera base = scene.cameras.empty() ? Camera{} : scene.cameras.front();
  CameraPath path;
  std::istringstream lines{std::string(text)};
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    auto fail = [&](const std::string& problem) {
      throw std::runtime_error(source + ":" + std::to_string(number) + ": " + problem);
    };
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::string kind;
    if (!(in >> kind)) continue;
    double frame = 0;
    if (!(in >> frame) || !std::isfinite(frame) || frame < 0) fail("expected a frame number >= 0 after '" + kind + "'");
    auto read_vec3 = [&](const std::string& what) {
      glm::vec3 v;
      if (!(in >> v.x >> v.y >> v.z) || !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        fail("'" + what + "' needs three finite numbers");
      if (std::abs(v.x) > 1e30f || std::abs(v.y) > 1e30f || std::abs(v.z) > 1e30f) fail("'" + what + "' is out of range");
      return v;
    };
    if (kind == "camera") {
      CameraKey key{frame, base};
      bool eye = false, target = false;
      std::string field;
      while (in >> field) {
        if (field == "eye") key.camera.eye = read_vec3(field), eye = true;
        else if (field == "target") key.camera.target = read_vec3(field), target = true;
        else if (field == "up") key.camera.up = read_vec3(field);
        else if (field == "fov") {
          if (!(in >> key.camera.yfov_degrees) || !(key.camera.yfov_degrees > 0.0f && key.camera.yfov_degrees < 180.0f))
            fail("'fov' needs a field of view in (0, 180) degrees");
        } else {
          fail("unknown camera field '" + field + "' (eye, target, up, fov)");
        }
      }
      if (!eye || !target) fail("a camera key needs 'eye' and 'target'");
      if (const std::string problem = camera_problem(key.camera); !problem.empty()) fail(problem);
      path.cameras.push_back(key);
    } else if (kind == "object") {
      std::string name, field;
      if (!(in >> name)) fail("an object key needs the object's name");
      const auto it = std::find_if(scene.objects.begin(), scene.objects.end(), [&](const Object& o) { return o.name == name; });
      if (it == scene.objects.end()) fail("no object named '" + name + "' in the scene");
      if (!(in >> field) || field != "translate") fail("an object key needs 'translate X Y Z'");
      path.objects.push_back({frame, uint32_t(it - scene.objects.begin()), read_vec3(field)});
      if (in >> field) fail("unexpected '" + field + "' after the translation");
    } else if (kind == "light") {
      std::string name, field;
      if (!(in >> name)) fail("a light key needs the light's name");
      const auto it = std::find_if(scene.punctual_lights.begin(), scene.punctual_lights.end(),
                                   [&](const PunctualLight& l) { return l.name == name; });
      if (it == scene.punctual_lights.end()) fail("no point or spot light named '" + name + "' in the scene");
      if (it->type == LightType::directional)
        fail("light '" + name + "' is directional: it has a direction but no position, so it cannot be translated");
      if (!(in >> field) || field != "translate") fail("a light key needs 'translate X Y Z'");
      path.lights.push_back({frame, uint32_t(it - scene.punctual_lights.begin()), read_vec3(field)});
      if (in >> field) fail("unexpected '" + field + "' after the translation");
    } else {
      fail("unknown key '" + kind + "' (camera, object, light)");
    }
  }
  if (path.cameras.empty()) path.cameras.push_back({0, base});
  std::stable_sort(path.cameras.begin(), path.cameras.end(), [](const CameraKey& a, const CameraKey& b) { return a.frame < b.frame; });
  std::stable_sort(path.objects.begin(), path.objects.end(), [](const ObjectKey& a, const ObjectKey& b) {
    return a.object != b.object ? a.object < b.object : a.frame < b.frame;
  });
  std::stable_sort(path.lights.begin(), path.lights.end(), [](const LightKey& a, const LightKey& b) {
    return a.light != b.light ? a.light < b.light : a.frame < b.frame;
  });
  return path;
}

CameraPath read_camera_path(const std::filesystem::path& file, const Scene& scene) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the camera path");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  if (s.find('\0') != std::string::npos) throw std::runtime_error(file.string() + ": not a text file");
  return parse_camera_path(s, file.string(), scene);
}

PathClock::PathClock(double rate, int last_frame, std::vector<int> exact)
    : rate_(rate), last_(last_frame), exact_(std::move(exact)) {}

double PathClock::next(double clock_ms) {
  ++frames_;
  if (rate_ <= 0.0) {
    position_ = double(frames_ - 1);
    exact_now_ = exact_.empty() || std::binary_search(exact_.begin(), exact_.end(), frames_ - 1);
    return position_;
  }
  const double clock = std::clamp((clock_ms - paused_ms_) * 1e-3 * rate_, std::max(position_, 0.0), double(last_));
  exact_now_ = next_exact_ < exact_.size() && double(exact_[next_exact_]) <= clock;
  position_ = exact_now_ ? double(exact_[next_exact_++]) : clock;
  return position_;
}

bool PathClock::done() const { return position_ >= double(last_) && (rate_ <= 0.0 || next_exact_ == exact_.size()); }


CameraPath scene_camera_path(const Scene& scene, int frames) {
  CameraPath path;
  const Camera base = scene.cameras.empty() ? Camera{} : scene.cameras.front();
  if (scene.camera_path.empty()) {
    path.cameras.push_back({0, base});
    return path;
  }
  const size_t keys = scene.camera_path.size();
  for (size_t k = 0; k < keys; ++k) {
    Camera c = scene.camera_path[k];
    c.znear = base.znear;
    const double frame = keys == 1 ? 0.0 : double(k) * double(std::max(frames - 1, 0)) / double(keys - 1);
    path.cameras.push_back({frame, c});
  }
  return path;
}

}  // namespace epi::render

namespace epi::render {

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

std::string vec3(const glm::vec3& v) { return number(v.x) + " " + number(v.y) + " " + number(v.z); }

}  // namespace

std::string format_camera_key(double frame, const Camera& camera) {
  return "camera " + number(frame) + " eye " + vec3(camera.eye) + " target " + vec3(camera.target) + " up " +
         vec3(camera.up) + " fov " + number(camera.yfov_degrees);
}

std::string format_object_key(double frame, const std::string& object, const glm::vec3& translate) {
  return "object " + number(frame) + " " + object + " translate " + vec3(translate);
}

std::string format_light_key(double frame, const std::string& light, const glm::vec3& translate) {
  return "light " + number(frame) + " " + light + " translate " + vec3(translate);
}

}  // namespace epi::render

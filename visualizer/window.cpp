#include "window.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "draw.h"
#include "export.h"
#include "presets.h"
#include "steps.h"

namespace epi::vis {

namespace {

constexpr int kPanelWidth = 310;

// Everything the window shows, rebuilt when the source, density, seed or pixel changes.
struct Session {
  std::unique_ptr<Model> model;
  PixelTrace trace;
  std::vector<Step> steps;
  int step = 0;

  void follow(int x, int y) {
    trace = model->tracer().trace(x, y);
    steps = build_steps(*model, trace);
    step = std::min(step, int(steps.size()) - 1);
  }
  int first_of_stage(int stage) const {
    for (size_t i = 0; i < steps.size(); ++i)
      if (steps[i].stage == stage) return int(i);
    return step;
  }
};

// Key presses, queued by a GLFW callback: a press and release within one frame (a quick tap on
// a slow machine) still counts. ImGui's callbacks chain to it.
std::vector<int> pending_keys;
void on_key(GLFWwindow*, int key, int, int action, int) {
  if (action == GLFW_PRESS || action == GLFW_REPEAT) pending_keys.push_back(key);
}

void upload(GLuint texture, const std::vector<uint8_t>& rgb) {
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, kCanvasWidth, kCanvasHeight, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
}

void save_screenshot(const std::string& file, int width, int height) {
  std::vector<uint8_t> pixels(size_t(width) * size_t(height) * 3), flipped(pixels.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  const size_t row = size_t(width) * 3;
  for (int y = 0; y < height; ++y) std::copy_n(&pixels[size_t(height - 1 - y) * row], row, &flipped[size_t(y) * row]);
  write_png(file, flipped, width, height);
}

}  // namespace

int run_window(Model model, const WindowOptions& options) {
  if (!glfwInit()) throw std::runtime_error("cannot open a window (no display?); use --export DIR for headless output");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  const int width = kCanvasWidth + kPanelWidth, height = kCanvasHeight;
  GLFWwindow* window = glfwCreateWindow(width, height, "epi-visualizer", nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    throw std::runtime_error("cannot create an OpenGL 3.3 window");
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsLight();
  glfwSetKeyCallback(window, on_key);
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330");

  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // shown 1:1
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

  Session session;
  const bool pattern_source = model.source().pattern.has_value();
  std::string source = options.source;
  float density = float(options.density);
  int seed = int(options.seed), px = options.x, py = options.y;
  session.model = std::make_unique<Model>(std::move(model));
  session.follow(px, py);
  session.step = std::clamp(options.step - 1, 0, int(session.steps.size()) - 1);
  bool playing = false, dirty = true;
  float steps_per_second = 1.0f;
  double last_advance = glfwGetTime();
  std::string error;
  int frames = 0;

  auto rebuild = [&](const std::string& name) {
    try {
      session.model = std::make_unique<Model>(load_source(name, density, uint64_t(seed)));
      source = name;
      px = std::clamp(px, 0, session.model->width() - 1), py = std::clamp(py, 0, session.model->height() - 1);
      session.follow(px, py);
      error.clear();
    } catch (const std::exception& e) {
      error = e.what();
    }
    dirty = true;
  };

  while (!glfwWindowShouldClose(window)) {
    glfwPollEvents();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const int count = int(session.steps.size());
    if (playing && glfwGetTime() - last_advance >= 1.0 / steps_per_second) {
      last_advance = glfwGetTime();
      if (session.step + 1 < count) ++session.step, dirty = true;
      else playing = false;
    }
    // Keyboard: arrows step, space plays, Escape quits.
    for (const int key : pending_keys) {
      if (ImGui::GetIO().WantTextInput) break;
      if (key == GLFW_KEY_RIGHT && session.step + 1 < count) ++session.step, dirty = true;
      if (key == GLFW_KEY_LEFT && session.step > 0) --session.step, dirty = true;
      if (key == GLFW_KEY_SPACE) playing = !playing, last_advance = glfwGetTime();
      if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(window, 1);
    }
    pending_keys.clear();
    if (dirty) {
      upload(texture, render_rgb(*session.model, session.trace, session.steps, session.step));
      dirty = false;
    }

    // The drawing, full size; a click follows the pixel under the mouse.
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(float(kCanvasWidth), float(kCanvasHeight)));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.0f);  // the drawing exactly, pixel for pixel
    ImGui::Begin("canvas", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoBringToFrontOnFocus);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture)), ImVec2(float(kCanvasWidth), float(kCanvasHeight)));
    if (ImGui::IsItemClicked()) {
      const ImVec2 m = ImGui::GetMousePos();
      const Viewport v = viewport(*session.model, session.trace, session.steps[size_t(session.step)].view);
      const int cx = int(std::floor(v.ox + (m.x - origin.x - v.x0) / v.cell)), cy = int(std::floor(v.oy + (m.y - origin.y - v.y0) / v.cell));
      if (cx >= 0 && cy >= 0 && cx < session.model->width() && cy < session.model->height() && m.x - origin.x < 770) {
        px = cx, py = cy;
        session.follow(px, py);
        dirty = true;
      }
    }
    ImGui::End();
    ImGui::PopStyleVar(2);

    // The controls.
    ImGui::SetNextWindowPos(ImVec2(float(kCanvasWidth), 0));
    ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(kCanvasHeight)));
    ImGui::Begin("Controls", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::Text("Step %d of %d", session.step + 1, count);
    if (ImGui::Button("|<")) session.step = 0, dirty = true;
    ImGui::SameLine();
    if (ImGui::Button("< Back") && session.step > 0) --session.step, dirty = true;
    ImGui::SameLine();
    if (ImGui::Button(playing ? "Pause" : "Play")) playing = !playing, last_advance = glfwGetTime();
    ImGui::SameLine();
    if (ImGui::Button("Forward >") && session.step + 1 < count) ++session.step, dirty = true;
    ImGui::SameLine();
    if (ImGui::Button(">|")) session.step = count - 1, dirty = true;
    int shown = session.step + 1;
    if (ImGui::SliderInt("step", &shown, 1, count)) session.step = shown - 1, dirty = true;
    ImGui::SliderFloat("steps/s", &steps_per_second, 0.2f, 5.0f, "%.1f");
    ImGui::Separator();
    ImGui::Text("Jump to a stage");
    for (int s = 1; s <= kStageCount; ++s) {
      if (ImGui::Button((std::to_string(s) + " " + stage_name(s)).c_str(), ImVec2(145, 0)))
        session.step = session.first_of_stage(s), dirty = true;
      if (s % 2) ImGui::SameLine();
    }
    ImGui::Separator();
    ImGui::Text("Pixel (click the drawing)");
    int pixel[2] = {px, py};
    if (ImGui::InputInt2("x, y", pixel)) {
      px = std::clamp(pixel[0], 0, session.model->width() - 1), py = std::clamp(pixel[1], 0, session.model->height() - 1);
      session.follow(px, py);
      dirty = true;
    }
    ImGui::Separator();
    if (pattern_source || find_preset(source)) {
      if (ImGui::BeginCombo("preset", find_preset(source) ? source.c_str() : "(file)")) {
        for (const Preset& p : presets())
          if (ImGui::Selectable(p.name.c_str(), p.name == source)) px = p.pixel_x, py = p.pixel_y, rebuild(p.name);
        ImGui::EndCombo();
      }
      if (ImGui::SliderFloat("density", &density, 0.02f, 1.0f, "%.2f")) rebuild(source);
      if (ImGui::InputInt("seed", &seed)) rebuild(source);
    } else {
      ImGui::TextWrapped("EPI snapshot: samples come from the render.");
    }
    if (!error.empty()) ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "%s", error.c_str());
    ImGui::Separator();
    ImGui::TextWrapped("Keys: left/right arrows step, space plays and pauses, Escape quits.");
    ImGui::End();

    ImGui::Render();
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(1, 1, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (!options.screenshot.empty() && ++frames == 3) {
      save_screenshot(options.screenshot, fb_w, fb_h);
      glfwSetWindowShouldClose(window, 1);
    }
    if (!options.record.empty() && glfwWindowShouldClose(window)) {
      save_screenshot(options.record, fb_w, fb_h);
      std::printf("window closed at pixel (%d, %d), step %d of %d\n", px, py, session.step + 1, count);
    }
    glfwSwapBuffers(window);
  }
  glDeleteTextures(1, &texture);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

}  // namespace epi::vis

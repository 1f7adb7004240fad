#include "export.h"

#include <cairo-svg.h>
#include <cairo.h>
#include <png.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>


#include "draw.h"
#include "gif.h"

namespace epi::vis {

namespace fs = std::filesystem;

namespace {

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using Surface = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using Context = std::unique_ptr<cairo_t, ContextDeleter>;

void check(cairo_status_t status, const std::string& what) {
  if (status != CAIRO_STATUS_SUCCESS) throw std::runtime_error(what + ": " + cairo_status_to_string(status));
}

std::string numbered(const char* stem, int index, const char* ext) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%s_%03d.%s", stem, index + 1, ext);
  return buf;
}

}  // namespace

std::vector<uint8_t> render_rgb(const Model& model, const PixelTrace& trace, const std::vector<Step>& steps, int index) {
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, kCanvasWidth, kCanvasHeight));
  Context cr(cairo_create(surface.get()));
  draw_step(cr.get(), model, trace, steps[size_t(index)], index, int(steps.size()));
  cairo_surface_flush(surface.get());
  check(cairo_status(cr.get()), "drawing");
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  std::vector<uint8_t> rgb(size_t(kCanvasWidth) * kCanvasHeight * 3);
  for (int y = 0; y < kCanvasHeight; ++y)
    for (int x = 0; x < kCanvasWidth; ++x) {
      uint32_t p;
      std::memcpy(&p, data + size_t(y) * size_t(stride) + size_t(x) * 4, 4);  // native-endian xRGB
      uint8_t* o = &rgb[(size_t(y) * kCanvasWidth + size_t(x)) * 3];
      o[0] = uint8_t(p >> 16), o[1] = uint8_t(p >> 8), o[2] = uint8_t(p);
    }
  return rgb;
}

void write_png(const std::string& file, const std::vector<uint8_t>& rgb, int width, int height) {
  // libpng rather than Cairo's writer: a fast compression level (the drawings are flat colours,
  // so the files stay small) makes the export several times faster.
  FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) throw std::runtime_error(file + ": cannot open for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    throw std::runtime_error(file + ": cannot write the PNG");
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 2);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) png_write_row(png, &rgb[size_t(y) * size_t(width) * 3]);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(f) != 0) throw std::runtime_error(file + ": write error");
}

nlohmann::ordered_json trace_json(const Model& model, const PixelTrace& t, const std::vector<Step>& steps) {
  using Json = nlohmann::ordered_json;
  Json j;
  j["source"] = model.source().name;
  if (model.source().pattern) j["density"] = model.source().density, j["seed"] = model.source().seed;
  j["width"] = model.width(), j["height"] = model.height();
  j["pixel"] = {t.x, t.y};
  j["settings"] = {{"antialias", model.source().settings.antialias},
                   {"complex_filter", model.source().settings.complex_filter},
                   {"fill", model.source().settings.fill}};
  j["class"] = t.kind == CellKind::empty ? "empty" : t.kind == CellKind::simple ? "simple" : "complex";
  j["final"] = {{"edge_code", t.code}, {"type", t.type}, {"reach_mask", t.reach},
                {"result", {t.result[0], t.result[1], t.result[2]}}, {"priority", t.priority},
                {"rendercache", {t.rendercache[0], t.rendercache[1], t.rendercache[2]}}};
  Json list = Json::array();
  for (size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    list.push_back({{"index", i + 1},
                    {"stage", s.stage},
                    {"stage_name", stage_name(s.stage)},
                    {"section", s.section},
                    {"caption", s.caption},
                    {"values", s.values},
                    {"png", numbered("step", int(i), "png")},
                    {"svg", numbered("step", int(i), "svg")}});
  }
  j["steps"] = list;
  return j;
}

void export_steps(const Model& model, const PixelTrace& trace, const std::vector<Step>& steps, const std::string& dir,
                  double seconds_per_step) {
  const fs::path target(dir);
  std::error_code ec;
  if (fs::exists(target, ec)) {
    if (!fs::is_directory(target, ec)) throw std::runtime_error(dir + ": exists and is not a folder");
    if (!fs::is_empty(target, ec)) throw std::runtime_error(dir + ": exists and is not empty (export into a new folder)");
  }
  const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) throw std::runtime_error(dir + ": its parent folder does not exist");
  const fs::path staging = parent / (target.filename().string() + ".partial");
  fs::remove_all(staging, ec);
  if (!fs::create_directory(staging, ec)) throw std::runtime_error(dir + ": cannot create " + staging.string());
  try {
    // Frames, and the animation from the same pixels.
    std::vector<std::vector<uint8_t>> frames;
    for (size_t i = 0; i < steps.size(); ++i) {
      frames.push_back(render_rgb(model, trace, steps, int(i)));
      write_png((staging / numbered("step", int(i), "png")).string(), frames.back(), kCanvasWidth, kCanvasHeight);
      const std::string svg = (staging / numbered("step", int(i), "svg")).string();
      Surface surface(cairo_svg_surface_create(svg.c_str(), kCanvasWidth, kCanvasHeight));
      Context cr(cairo_create(surface.get()));
      draw_step(cr.get(), model, trace, steps[i], int(i), int(steps.size()));
      check(cairo_status(cr.get()), svg);
      cairo_surface_finish(surface.get());
      check(cairo_surface_status(surface.get()), svg);
    }
    write_gif((staging / "animation.gif").string(), frames, kCanvasWidth, kCanvasHeight,
              std::max(1, int(std::lround(seconds_per_step * 100))));
    for (const auto& entry : fs::directory_iterator(staging))  // giflib creates its file owner-only
      fs::permissions(entry.path(), fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read | fs::perms::others_read);
    std::ofstream json(staging / "trace.json");
    json << trace_json(model, trace, steps).dump(2) << "\n";
    json.close();
    if (!json) throw std::runtime_error("trace.json: write error");
    if (fs::exists(target)) fs::remove(target);  // empty (checked above)
    fs::rename(staging, target);
  } catch (const std::exception& e) {
    fs::remove_all(staging, ec);
    throw std::runtime_error(dir + ": " + e.what());
  }
}

}  // namespace epi::vis

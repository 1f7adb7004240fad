#include "draw.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "epi/epi_pixel.h"
#include "epi/geometry.h"

namespace epi::vis {

namespace {

constexpr double kMainX = 40, kMainY = 70, kMainW = 710, kMainH = 710;
constexpr double kSideX = 790, kSideW = 470;
const char* kFont = "DejaVu Sans";

void set(cairo_t* cr, Rgba c) { cairo_set_source_rgba(cr, c.r, c.g, c.b, c.a); }
double srgb(float linear) { return encode_srgb8(linear) / 255.0; }
void set_linear(cairo_t* cr, const float* rgb, double alpha = 1.0) {
  cairo_set_source_rgba(cr, srgb(rgb[0]), srgb(rgb[1]), srgb(rgb[2]), alpha);
}

void font(cairo_t* cr, double size, bool bold = false, bool italic = false) {
  cairo_select_font_face(cr, kFont, italic ? CAIRO_FONT_SLANT_ITALIC : CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
}

double text_width(cairo_t* cr, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

// Draws `text` wrapped to `width` from baseline y; returns the y after the last line.
double wrapped(cairo_t* cr, const std::string& text, double x, double y, double width, double line) {
  std::istringstream words(text);
  std::string word, current;
  auto flush = [&] {
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, current.c_str());
    y += line;
    current.clear();
  };
  while (words >> word) {
    const std::string candidate = current.empty() ? word : current + " " + word;
    if (!current.empty() && text_width(cr, candidate) > width) flush(), current = word;
    else current = candidate;
  }
  if (!current.empty()) flush();
  return y;
}

void centred_text(cairo_t* cr, const std::string& s, double cx, double cy, bool halo) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  const double x = cx - e.width / 2 - e.x_bearing, y = cy - e.height / 2 - e.y_bearing;
  if (halo) {
    cairo_save(cr);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.8);
    cairo_rectangle(cr, x + e.x_bearing - 3, y + e.y_bearing - 2, e.width + 6, e.height + 4);
    cairo_fill(cr);
    cairo_restore(cr);
  }
  cairo_move_to(cr, x, y);
  cairo_show_text(cr, s.c_str());
}

void hatch(cairo_t* cr, double x, double y, double w, double h, double spacing, Rgba color) {
  cairo_save(cr);
  cairo_rectangle(cr, x, y, w, h);
  cairo_clip(cr);
  set(cr, color);
  cairo_set_line_width(cr, 1.5);
  for (double d = -h; d < w; d += spacing) {
    cairo_move_to(cr, x + d, y + h), cairo_line_to(cr, x + d + h, y);
    cairo_move_to(cr, x + d, y), cairo_line_to(cr, x + d + h, y + h);
  }
  cairo_stroke(cr);
  cairo_restore(cr);
}

std::string value_text(const nlohmann::ordered_json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_array()) {
    std::string s;
    for (const auto& e : v) s += (s.empty() ? "" : ", ") + value_text(e);
    return s;
  }
  if (v.is_number_float()) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.4g", v.get<double>());
    return buf;
  }
  return v.dump();
}

class Painter {
 public:
  Painter(cairo_t* cr, const Model& m, const PixelTrace& t, const Step& s)
      : cr_(cr), m_(m), t_(t), s_(s), v_(viewport(m, t, s.view)) {}

  void main_area() {
    cairo_save(cr_);
    cairo_rectangle(cr_, kMainX, kMainY, kMainW, kMainH);
    cairo_clip(cr_);
    base();
    if (s_.view.classes) classes();
    for (const CellMark& mk : s_.view.marks) mark_fill(mk);
    for (const Shape& sh : s_.view.shapes) shape(sh);
    grid();
    if (s_.view.segments) segments();
    if (s_.view.reconstructed_edges) reconstructed_edges();
    if (s_.view.crossings) crossings();
    for (const CellMark& mk : s_.view.marks) mark_outline(mk);
    for (const Arrow& a : s_.view.arrows) arrow(a);
    if (s_.view.samples) samples();
    for (const CellMark& mk : s_.view.marks) mark_label(mk);
    for (const Text& t : s_.view.texts) {
      font(cr_, t.size, true);
      set(cr_, t.color);
      centred_text(cr_, t.text, cx(t.x), cy(t.y), true);
    }
    cairo_restore(cr_);
    // Frame and coordinates.
    cairo_set_source_rgb(cr_, 0.3, 0.3, 0.3);
    cairo_set_line_width(cr_, 1);
    cairo_rectangle(cr_, kMainX, kMainY, kMainW, kMainH);
    cairo_stroke(cr_);
    axis_labels();
  }

 private:
  double cx(double px) const { return v_.to_canvas_x(px); }
  double cy(double py) const { return v_.to_canvas_y(py); }

  void base() {
    const double alpha = s_.view.whole_image ? 1.0 : s_.view.base_alpha;
    cairo_push_group(cr_);
    cairo_rectangle(cr_, cx(0), cy(0), m_.width() * v_.cell, m_.height() * v_.cell);
    cairo_clip(cr_);
    if (const auto& pattern = m_.source().pattern) {
      cairo_set_source_rgb(cr_, srgb(pattern->background[0]), srgb(pattern->background[1]), srgb(pattern->background[2]));
      cairo_rectangle(cr_, cx(0), cy(0), m_.width() * v_.cell, m_.height() * v_.cell);
      cairo_fill(cr_);
      cairo_set_fill_rule(cr_, CAIRO_FILL_RULE_EVEN_ODD);
      for (const Polygon& p : pattern->polygons) {
        for (const auto& q : p.points) cairo_line_to(cr_, cx(q[0]), cy(q[1]));
        cairo_close_path(cr_);
        set_linear(cr_, p.color.data());
        cairo_fill(cr_);
      }
    } else {  // the EPI result as an image, each pixel a square (an embedded PNG in SVG)
      const RgbImage& img = m_.epi_result().image;
      cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, img.width, img.height);
      cairo_surface_flush(s);
      unsigned char* data = cairo_image_surface_get_data(s);
      const int stride = cairo_image_surface_get_stride(s);
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
          const float* c = img.at(x, y);
          const uint32_t p = uint32_t(encode_srgb8(c[0])) << 16 | uint32_t(encode_srgb8(c[1])) << 8 | encode_srgb8(c[2]);
          std::memcpy(data + size_t(y) * size_t(stride) + size_t(x) * 4, &p, 4);
        }
      cairo_surface_mark_dirty(s);
      cairo_save(cr_);
      cairo_translate(cr_, cx(0), cy(0));
      cairo_scale(cr_, v_.cell, v_.cell);
      cairo_set_source_surface(cr_, s, 0, 0);
      cairo_pattern_set_filter(cairo_get_source(cr_), CAIRO_FILTER_NEAREST);
      cairo_paint(cr_);
      cairo_restore(cr_);
      cairo_surface_destroy(s);
    }
    cairo_pop_group_to_source(cr_);
    cairo_paint_with_alpha(cr_, alpha);
    // Outside the image: hatched.
    for (int y = v_.py0; y <= v_.py1; ++y)
      for (int x = v_.px0; x <= v_.px1; ++x)
        if (x < 0 || y < 0 || x >= m_.width() || y >= m_.height()) {
          cairo_set_source_rgb(cr_, 0.88, 0.88, 0.88);
          cairo_rectangle(cr_, cx(x), cy(y), v_.cell, v_.cell);
          cairo_fill(cr_);
          hatch(cr_, cx(x), cy(y), v_.cell, v_.cell, 12, {0.6, 0.6, 0.6, 1});
        }
  }

  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < m_.width() && y < m_.height(); }

  void classes() {
    for (int y = v_.py0; y <= v_.py1; ++y)
      for (int x = v_.px0; x <= v_.px1; ++x) {
        if (!inside(x, y)) continue;
        const int type = m_.type_at(x, y);
        if (type == kTypeEmpty) cairo_set_source_rgba(cr_, 1, 1, 1, 0.55);
        else if (type == kTypeComplex) cairo_set_source_rgba(cr_, 0.95, 0.55, 0.72, 0.65);
        else cairo_set_source_rgba(cr_, 0.55, 0.82, 0.50, 0.65);
        cairo_rectangle(cr_, cx(x), cy(y), v_.cell, v_.cell);
        cairo_fill(cr_);
        if (type == kTypeComplex) hatch(cr_, cx(x), cy(y), v_.cell, v_.cell, 10, {0.75, 0.2, 0.45, 0.8});
      }
  }

  void mark_fill(const CellMark& mk) {
    if (mk.fill.a <= 0) return;
    set(cr_, mk.fill);
    cairo_rectangle(cr_, cx(mk.x), cy(mk.y), mk.w * v_.cell, mk.h * v_.cell);
    cairo_fill(cr_);
  }
  void mark_outline(const CellMark& mk) {
    if (mk.hatch) hatch(cr_, cx(mk.x), cy(mk.y), mk.w * v_.cell, mk.h * v_.cell, 10, {0.75, 0.2, 0.45, 0.9});
    if (mk.outline_width <= 0) return;
    set(cr_, mk.outline);
    cairo_set_line_width(cr_, mk.outline_width);
    const double inset = mk.outline_width / 2;
    cairo_rectangle(cr_, cx(mk.x) + inset, cy(mk.y) + inset, mk.w * v_.cell - 2 * inset, mk.h * v_.cell - 2 * inset);
    cairo_stroke(cr_);
  }
  void mark_label(const CellMark& mk) {
    if (mk.label.empty()) return;
    font(cr_, std::clamp(v_.cell * mk.w * 0.16, 11.0, 20.0), true);
    cairo_set_source_rgb(cr_, 0.05, 0.05, 0.05);
    centred_text(cr_, mk.label, cx(mk.x + mk.w / 2), cy(mk.y + mk.h * 0.8), true);
  }

  void shape(const Shape& sh) {
    if (sh.points.empty()) return;
    for (const auto& p : sh.points) cairo_line_to(cr_, cx(p[0]), cy(p[1]));
    if (sh.closed) cairo_close_path(cr_);
    if (sh.fill.a > 0) {
      set(cr_, sh.fill);
      sh.stroke.a > 0 ? cairo_fill_preserve(cr_) : cairo_fill(cr_);
    }
    if (sh.stroke.a > 0) {
      set(cr_, sh.stroke);
      cairo_set_line_width(cr_, sh.width);
      cairo_set_line_cap(cr_, CAIRO_LINE_CAP_BUTT);
      if (sh.dashed) {
        const double dash[2] = {6, 4};
        cairo_set_dash(cr_, dash, 2, 0);
      }
      cairo_stroke(cr_);
      cairo_set_dash(cr_, nullptr, 0, 0);
    }
    cairo_new_path(cr_);
  }

  void grid() {
    const bool whole = s_.view.whole_image;
    if (v_.cell < 4) return;  // a large image seen whole: lines would only grey it
    cairo_set_source_rgba(cr_, 0.35, 0.35, 0.35, whole ? 0.25 : 0.7);
    cairo_set_line_width(cr_, whole ? 0.5 : 1.0);
    for (int x = v_.px0; x <= v_.px1 + 1; ++x) cairo_move_to(cr_, cx(x), cy(v_.py0)), cairo_line_to(cr_, cx(x), cy(v_.py1 + 1));
    for (int y = v_.py0; y <= v_.py1 + 1; ++y) cairo_move_to(cr_, cx(v_.px0), cy(y)), cairo_line_to(cr_, cx(v_.px1 + 1), cy(y));
    cairo_stroke(cr_);
    if (v_.cell >= 150) {  // the 1/8 pieces as ticks on every pixel side
      cairo_set_source_rgba(cr_, 0.35, 0.35, 0.35, 0.8);
      for (int x = v_.px0; x <= v_.px1 + 1; ++x)
        for (int y = v_.py0; y <= v_.py1 + 1; ++y)
          for (int k = 1; k < 8; ++k) {
            cairo_move_to(cr_, cx(x + k / 8.0), cy(y) - 5), cairo_line_to(cr_, cx(x + k / 8.0), cy(y) + 5);
            cairo_move_to(cr_, cx(x) - 5, cy(y + k / 8.0)), cairo_line_to(cr_, cx(x) + 5, cy(y + k / 8.0));
          }
      cairo_stroke(cr_);
    }
    if (s_.view.subpixel_grid) {
      const double dash[2] = {5, 4};
      cairo_set_dash(cr_, dash, 2, 0);
      cairo_set_source_rgba(cr_, 0.2, 0.2, 0.2, 0.8);
      for (int x = v_.px0; x <= v_.px1; ++x) cairo_move_to(cr_, cx(x + 0.5), cy(v_.py0)), cairo_line_to(cr_, cx(x + 0.5), cy(v_.py1 + 1));
      for (int y = v_.py0; y <= v_.py1; ++y) cairo_move_to(cr_, cx(v_.px0), cy(y + 0.5)), cairo_line_to(cr_, cx(v_.px1 + 1), cy(y + 0.5));
      cairo_stroke(cr_);
      cairo_set_dash(cr_, nullptr, 0, 0);
    }
    if (s_.view.sample_regions) {
      cairo_set_source_rgba(cr_, 0.2, 0.2, 0.2, 0.6);
      cairo_set_line_width(cr_, 1);
      const double dash[2] = {3, 3};
      cairo_set_dash(cr_, dash, 2, 0);
      for (int k = 1; k < 4; ++k) {
        cairo_move_to(cr_, cx(t_.x + k / 4.0), cy(t_.y)), cairo_line_to(cr_, cx(t_.x + k / 4.0), cy(t_.y + 1));
        cairo_move_to(cr_, cx(t_.x), cy(t_.y + k / 4.0)), cairo_line_to(cr_, cx(t_.x + 1), cy(t_.y + k / 4.0));
      }
      cairo_stroke(cr_);
      cairo_set_dash(cr_, nullptr, 0, 0);
    }
  }

  void segments() {
    cairo_set_source_rgba(cr_, 0.1, 0.1, 0.1, 0.85);
    cairo_set_line_width(cr_, s_.view.whole_image ? 1.5 : 2.0);
    for (const Segment& g : m_.source().segments) {
      cairo_move_to(cr_, cx(g.x0), cy(g.y0));
      cairo_line_to(cr_, cx(g.x1), cy(g.y1));
    }
    cairo_stroke(cr_);
  }

  void reconstructed_edges() {
    const EpiImage& epi = m_.tracer().classified();
    cairo_set_source_rgba(cr_, 0.55, 0.0, 0.55, 1);
    cairo_set_line_width(cr_, 3);
    for (int y = v_.py0; y <= v_.py1; ++y)
      for (int x = v_.px0; x <= v_.px1; ++x) {
        if (!inside(x, y)) continue;
        const int code = edge_code(epi.edge[epi.index(x, y)]);
        if (code == kEmptyCode || code == kComplexCode) continue;
        const geom::CellEdge e = geom::cell_edge(code_low(code), code_high(code), 8);
        cairo_move_to(cr_, cx(x + e.a.x), cy(y + e.a.y));
        cairo_line_to(cr_, cx(x + e.b.x), cy(y + e.b.y));
      }
    cairo_stroke(cr_);
  }

  void crossings() {
    const BoundaryMasks& masks = m_.source().masks;
    cairo_set_source_rgba(cr_, 0.55, 0.0, 0.55, 0.9);
    cairo_set_line_width(cr_, std::clamp(v_.cell * 0.07, 3.0, 9.0));
    cairo_set_line_cap(cr_, CAIRO_LINE_CAP_BUTT);
    auto horizontal = [&](uint8_t mask, double x, double y) {
      for (int bit = 0; bit < 8; ++bit)
        if ((mask >> bit) & 1) cairo_move_to(cr_, cx(x + bit / 8.0), cy(y)), cairo_line_to(cr_, cx(x + (bit + 1) / 8.0), cy(y));
    };
    auto vertical = [&](uint8_t mask, double x, double y) {
      for (int bit = 0; bit < 8; ++bit)
        if ((mask >> bit) & 1) cairo_move_to(cr_, cx(x), cy(y + bit / 8.0)), cairo_line_to(cr_, cx(x), cy(y + (bit + 1) / 8.0));
    };
    for (int y = std::max(0, v_.py0); y <= std::min(m_.height(), v_.py1 + 1); ++y)
      for (int x = std::max(0, v_.px0); x <= std::min(m_.width(), v_.px1 + 1); ++x) {
        const size_t i = masks.index(x, y);
        if (x < m_.width()) horizontal(masks.top[i], x, y);
        if (y < m_.height()) vertical(masks.left[i], x, y);
        if (s_.view.crossings == 2 && masks.centre_lines && x < m_.width() && y < m_.height()) {
          horizontal(masks.centre_h[i], x, y + 0.5);
          vertical(masks.centre_v[i], x + 0.5, y);
        }
      }
    cairo_stroke(cr_);
  }

  void arrow(const Arrow& a) {
    const double x0 = cx(a.x0), y0 = cy(a.y0), x1 = cx(a.x1), y1 = cy(a.y1);
    const double len = std::hypot(x1 - x0, y1 - y0);
    if (len < 1) return;
    const double ux = (x1 - x0) / len, uy = (y1 - y0) / len, shorten = std::min(len * 0.3, v_.cell * 0.28);
    const double ex = x1 - ux * shorten, ey = y1 - uy * shorten, sx = x0 + ux * shorten, sy = y0 + uy * shorten;
    set(cr_, a.color);
    cairo_set_line_width(cr_, 4);
    cairo_move_to(cr_, sx, sy), cairo_line_to(cr_, ex, ey);
    cairo_stroke(cr_);
    const double head = 14;
    cairo_move_to(cr_, ex + ux * 4, ey + uy * 4);
    cairo_line_to(cr_, ex - ux * head - uy * head * 0.6, ey - uy * head + ux * head * 0.6);
    cairo_line_to(cr_, ex - ux * head + uy * head * 0.6, ey - uy * head - ux * head * 0.6);
    cairo_close_path(cr_);
    cairo_fill(cr_);
  }

  void samples() {
    const EpiImage& epi = m_.tracer().classified();
    const double r = std::clamp(v_.cell * 0.075, 2.0, 9.0);
    for (int y = std::max(0, v_.py0); y <= std::min(m_.height() - 1, v_.py1); ++y)
      for (int x = std::max(0, v_.px0); x <= std::min(m_.width() - 1, v_.px1); ++x) {
        const uint16_t e = epi.edge[epi.index(x, y)];
        if (!has_sample(e)) continue;
        const int region = sample_region(e);
        const double px = cx(x + ((region & 3) + 0.5) / 4), py = cy(y + ((region >> 2) + 0.5) / 4);
        float rgb[3];
        decode_color(epi.color[epi.index(x, y)], rgb);
        cairo_arc(cr_, px, py, r, 0, 2 * M_PI);
        set_linear(cr_, rgb);
        cairo_fill_preserve(cr_);
        const bool usable = usable_sample(e) || !s_.view.ambiguity;
        cairo_set_source_rgb(cr_, usable ? 0 : 0.85, 0, 0);
        cairo_set_line_width(cr_, usable ? 1.5 : 2.5);
        cairo_stroke(cr_);
        if (!usable && r > 4) {
          cairo_move_to(cr_, px - r * 1.5, py - r * 1.5), cairo_line_to(cr_, px + r * 1.5, py + r * 1.5);
          cairo_move_to(cr_, px - r * 1.5, py + r * 1.5), cairo_line_to(cr_, px + r * 1.5, py - r * 1.5);
          cairo_stroke(cr_);
        }
      }
  }

  void axis_labels() {
    if (s_.view.whole_image) return;
    font(cr_, 12);
    cairo_set_source_rgb(cr_, 0.3, 0.3, 0.3);
    for (int x = v_.px0; x <= v_.px1; ++x)
      if (x >= 0 && x < m_.width()) centred_text(cr_, std::to_string(x), cx(x + 0.5), kMainY - 8, false);
    for (int y = v_.py0; y <= v_.py1; ++y)
      if (y >= 0 && y < m_.height()) centred_text(cr_, std::to_string(y), kMainX - 14, cy(y + 0.5), false);
  }

  cairo_t* cr_;
  const Model& m_;
  const PixelTrace& t_;
  const Step& s_;
  Viewport v_;
};

void header(cairo_t* cr, const Step& s) {
  const double w = (kCanvasWidth - 40) / double(kStageCount);
  for (int k = 1; k <= kStageCount; ++k) {
    const double x = 20 + (k - 1) * w;
    const bool current = k == s.stage, past = k < s.stage;
    if (current) cairo_set_source_rgb(cr, 0.15, 0.25, 0.45);
    else if (past) cairo_set_source_rgb(cr, 0.78, 0.82, 0.90);
    else cairo_set_source_rgb(cr, 0.93, 0.93, 0.93);
    cairo_rectangle(cr, x + 2, 8, w - 4, 30);
    cairo_fill(cr);
    font(cr, 13, current);
    if (current) cairo_set_source_rgb(cr, 1, 1, 1);
    else cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
    centred_text(cr, std::to_string(k) + " " + stage_name(k), x + w / 2, 23, false);
  }
}

void sidebar(cairo_t* cr, const Model& m, const PixelTrace& t, const Step& s, int index, int count) {
  double y = 88;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  font(cr, 26, true);
  cairo_move_to(cr, kSideX, y);
  cairo_show_text(cr, (std::to_string(s.stage) + ". " + stage_name(s.stage)).c_str());
  y += 26;
  font(cr, 16, false, true);
  cairo_set_source_rgb(cr, 0.25, 0.3, 0.5);
  cairo_move_to(cr, kSideX, y);
  cairo_show_text(cr, ("Paper, section " + s.section).c_str());
  y += 22;
  font(cr, 14);
  cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
  cairo_move_to(cr, kSideX, y);
  cairo_show_text(cr, ("step " + std::to_string(index + 1) + " of " + std::to_string(count) + "   pixel (" +
                       std::to_string(t.x) + ", " + std::to_string(t.y) + ")")
                          .c_str());
  y += 34;
  font(cr, 19);
  cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
  y = wrapped(cr, s.caption, kSideX, y, kSideW, 25) + 10;
  // Values.
  for (const auto& [key, value] : s.values.items()) {
    if (y > 620) break;
    font(cr, 14, true);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    const std::string k = key + ":";
    cairo_move_to(cr, kSideX, y);
    cairo_show_text(cr, k.c_str());
    double kw = text_width(cr, k) + 8;
    if (kw > kSideW * 0.6) y += 19, kw = 24;  // a long key: the value on the next line
    font(cr, 14);
    y = wrapped(cr, value_text(value), kSideX + kw, y, kSideW - kw, 19) + 2;
  }
  // Swatches.
  if (!s.view.swatches.empty()) {
    const double size = 62, gap = std::min(95.0, kSideW / double(s.view.swatches.size()));
    const double sy = std::max(y + 6, 640.0);
    for (size_t k = 0; k < s.view.swatches.size(); ++k) {
      const double sx = kSideX + gap * double(k);
      const Rgb& c = s.view.swatches[k].rgb;
      set_linear(cr, c.data());
      cairo_rectangle(cr, sx, sy, size, size);
      cairo_fill_preserve(cr);
      cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
      cairo_set_line_width(cr, 1);
      cairo_stroke(cr);
      font(cr, 12);
      wrapped(cr, s.view.swatches[k].label, sx, sy + size + 15, gap - 6, 14);
    }
  }
  // Footer: the source.
  font(cr, 12);
  cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
  std::string src = m.source().name;
  if (m.source().pattern) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), ", density %.2f, seed %llu", m.source().density, (unsigned long long)m.source().seed);
    src += buf;
  } else {
    src += " (EPI snapshot)";
  }
  cairo_move_to(cr, kSideX, kCanvasHeight - 8);
  cairo_show_text(cr, ("epi-visualizer: " + src).c_str());
}

}  // namespace

Viewport viewport(const Model& m, const PixelTrace& t, const View& view) {
  Viewport v{};
  if (view.whole_image) {
    v.cell = std::min(kMainW / m.width(), kMainH / m.height());
    v.ox = 0, v.oy = 0;
    v.x0 = kMainX + (kMainW - v.cell * m.width()) / 2, v.y0 = kMainY + (kMainH - v.cell * m.height()) / 2;
    v.px0 = 0, v.py0 = 0, v.px1 = m.width() - 1, v.py1 = m.height() - 1;
    return v;
  }
  const int n = 2 * view.radius + 1;
  v.cell = std::min(kMainW, kMainH) / n;
  v.ox = t.x - view.radius, v.oy = t.y - view.radius;
  v.x0 = kMainX + (kMainW - v.cell * n) / 2, v.y0 = kMainY + (kMainH - v.cell * n) / 2;
  v.px0 = t.x - view.radius, v.px1 = t.x + view.radius;
  v.py0 = t.y - view.radius, v.py1 = t.y + view.radius;
  return v;
}

void draw_step(cairo_t* cr, const Model& model, const PixelTrace& trace, const Step& step, int index, int count) {
  cairo_save(cr);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  header(cr, step);
  Painter(cr, model, trace, step).main_area();
  sidebar(cr, model, trace, step, index, count);
  cairo_restore(cr);
}

}  // namespace epi::vis

#include "steps.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <set>

#include "epi/geometry.h"
#include "epi/interpolate.h"
#include "epi/reachability.h"
#include "epi/tables.h"

namespace epi::vis {

namespace {

using Json = nlohmann::ordered_json;

// Colours of the drawing (Figure 5 of the paper: empty white, simple green, complex pink).
constexpr Rgba kSimpleFill{0.55, 0.82, 0.50, 0.55}, kComplexFill{0.95, 0.55, 0.72, 0.55},
    kEmptyFill{1, 1, 1, 0.35}, kFocus{1.0, 0.55, 0.0, 1}, kReached{1.0, 0.82, 0.15, 0.6},
    kUnreached{0.35, 0.35, 0.35, 0.5}, kRegionA{0.30, 0.50, 0.95, 0.35}, kRegionB{0.95, 0.40, 0.45, 0.35},
    kAmbiguous{0.6, 0.6, 0.6, 0.55}, kArrow{0.85, 0.35, 0.0, 1}, kWeight{0.20, 0.65, 0.30, 0.45},
    kEdgeLine{0.55, 0.0, 0.55, 1};

std::string num(double v, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
  return buf;
}
double srgb(float linear) { return encode_srgb8(linear) / 255.0; }
std::string offset(int dx, int dy) { return "(" + std::to_string(dx) + "," + std::to_string(dy) + ")"; }
std::string pixel_name(int x, int y) { return "(" + std::to_string(x) + ", " + std::to_string(y) + ")"; }
std::string bits_of(unsigned v, int n) {
  std::string s;
  for (int k = n - 1; k >= 0; --k) s += ((v >> k) & 1) ? '1' : '0';
  return s;
}
// A 4-bit reachability mask in the paper's order (Pa-Pb, Pa-Sb, Sa-Pb, Sa-Sb).
std::string reach4(uint8_t m) {
  return std::string("(") + char('0' + (m & 1)) + "," + char('0' + ((m >> 1) & 1)) + "," + char('0' + ((m >> 2) & 1)) +
         "," + char('0' + ((m >> 3) & 1)) + ")";
}
// A linear colour as shown: "(r, g, b)", 3 decimals.
std::string rgb_json(const Rgb& c) { return "(" + num(c[0]) + ", " + num(c[1]) + ", " + num(c[2]) + ")"; }
const char* side_name(int side) {
  static const char* names[4] = {"top", "right", "bottom", "left"};
  return names[side];
}
const char* kind_name(CellKind k) { return k == CellKind::empty ? "empty" : k == CellKind::simple ? "simple" : "complex"; }
std::string type_name(int type) {
  if (type == kTypeEmpty) return "empty";
  if (type == kTypeComplex) return "complex";
  static const char* pairs[6] = {"top-right", "top-bottom", "top-left", "right-bottom", "right-left", "bottom-left"};
  return std::string("simple ") + pairs[(type - 2) / 2] + ((type - 2) & 1 ? ", primary B" : ", primary A");
}
std::string type_short(int type) {
  if (type == kTypeEmpty) return "E";
  if (type == kTypeComplex) return "C";
  static const char* pairs[6] = {"TR", "TB", "TL", "RB", "RL", "BL"};
  return std::string(pairs[(type - 2) / 2]) + ((type - 2) & 1 ? "/B" : "/A");
}
const char* dir_name(int d) {
  static const char* names[4] = {"right", "down", "left", "up"};
  return names[d];
}

// Where a boundary position's piece lies on the unit cell: its two ends.
std::array<std::array<double, 2>, 2> piece(int p, int n) {
  const geom::Vec2 a = geom::boundary_point(p, n, 0.0), b = geom::boundary_point(p, n, 1.0);
  return {{{a.x, a.y}, {b.x, b.y}}};
}

Shape translated(std::vector<std::array<double, 2>> pts, double x, double y, double scale = 1.0) {
  Shape s;
  for (auto& p : pts) p = {x + scale * p[0], y + scale * p[1]};
  s.points = std::move(pts);
  return s;
}

CellMark pixel_mark(int x, int y, Rgba fill, Rgba outline = {0, 0, 0, 0}, double width = 0, std::string label = {}) {
  return {double(x), double(y), 1, 1, fill, outline, width, std::move(label), false};
}
CellMark focus(int x, int y) { return pixel_mark(x, y, {0, 0, 0, 0}, kFocus, 5); }

class Builder {
 public:
  Builder(const Model& m, const PixelTrace& t) : m_(m), t_(t) {}
  std::vector<Step> build() {
    input();
    rasterization();
    classification();
    reachability();
    interpolation();
    antialiasing();
    complex_pixels();
    priority();
    return std::move(steps_);
  }

 private:
  Step& add(int stage, std::string section, std::string caption) {
    steps_.push_back({});
    Step& s = steps_.back();
    s.stage = stage, s.section = std::move(section), s.caption = std::move(caption);
    s.view.marks.push_back(focus(t_.x, t_.y));
    s.view.ambiguity = stage >= 3;
    if (stage >= 4) s.view.base_alpha = 0.25;
    return s;
  }
  int samples_in(int x0, int y0, int x1, int y1) const {
    int n = 0;
    for (int y = std::max(0, y0); y <= std::min(m_.height() - 1, y1); ++y)
      for (int x = std::max(0, x0); x <= std::min(m_.width() - 1, x1); ++x) n += has_sample(m_.source().epi.edge[m_.source().epi.index(x, y)]);
    return n;
  }
  bool segment_in_window(const Segment& g, int r) const {
    const double x0 = t_.x - r, x1 = t_.x + r + 1, y0 = t_.y - r, y1 = t_.y + r + 1;
    if (std::max(g.x0, g.x1) < x0 || std::min(g.x0, g.x1) > x1 || std::max(g.y0, g.y1) < y0 || std::min(g.y0, g.y1) > y1) return false;
    // Liang-Barsky: does the segment meet the window?
    double t0 = 0, t1 = 1;
    const double dx = g.x1 - g.x0, dy = g.y1 - g.y0;
    const double p[4] = {-dx, dx, -dy, dy}, q[4] = {g.x0 - x0, x1 - g.x0, g.y0 - y0, y1 - g.y0};
    for (int k = 0; k < 4; ++k) {
      if (p[k] == 0) {
        if (q[k] < 0) return false;
        continue;
      }
      const double u = q[k] / p[k];
      if (p[k] < 0) t0 = std::max(t0, u);
      else t1 = std::min(t1, u);
    }
    return t0 <= t1;
  }

  // Stage 1.
  void input() {
    const Source& src = m_.source();
    {
      Step& s = add(1, "4 Edge-and-point image",
                    src.pattern ? "The input: " + std::to_string(src.pattern->polygons.size()) +
                                      " polygons in pixel units; their " + std::to_string(src.segments.size()) +
                                      " boundary segments are the edges the EPI will record."
                                : "The input: one rendered frame's " + std::to_string(src.segments.size()) +
                                      " visible edge segments, drawn over the frame the EPI reconstructs.");
      s.view.whole_image = true, s.view.samples = false;
      s.values["image"] = std::to_string(m_.width()) + " x " + std::to_string(m_.height()) + " px";
      s.values["edge segments"] = src.segments.size();
      s.values["followed pixel"] = pixel_name(t_.x, t_.y);
    }
    {
      Step& s = add(1, "4.4 EPI pixels",
                    "The pixel grid: we follow pixel " + pixel_name(t_.x, t_.y) +
                        " (orange) through every stage, inside this 9x9 window.");
      s.view.samples = false;
      s.values["window"] = pixel_name(t_.x - 4, t_.y - 4) + " to " + pixel_name(t_.x + 4, t_.y + 4);
    }
    {
      const int n = samples_in(t_.x - 4, t_.y - 4, t_.x + 4, t_.y + 4);
      Step& s = add(1, "4.3 Point representation",
                    "The samples: each pixel holds at most one shaded point, stored by which of 16 sub-pixel regions "
                    "(4 bits) it fell in; dots sit at their region's centre.");
      s.view.sample_regions = true;
      if (src.pattern) s.values["density"] = src.density, s.values["seed"] = src.seed;
      s.values["samples in window"] = n;
      s.values["this pixel"] = t_.has_sample ? "sample in region " + std::to_string(t_.sample_region) + " (rx " +
                                                   std::to_string(t_.sample_region & 3) + ", ry " +
                                                   std::to_string(t_.sample_region >> 2) + ")"
                                             : std::string("no sample");
    }
  }

  // Stage 2.
  void rasterization() {
    const Source& src = m_.source();
    std::vector<const Segment*> near;
    for (const Segment& g : src.segments)
      if (segment_in_window(g, 4)) near.push_back(&g);
    auto distance = [&](const Segment* g) {  // from the followed pixel's centre to the segment
      const double px = t_.x + 0.5, py = t_.y + 0.5, dx = g->x1 - g->x0, dy = g->y1 - g->y0;
      const double len2 = dx * dx + dy * dy;
      const double u = len2 > 0 ? std::clamp(((px - g->x0) * dx + (py - g->y0) * dy) / len2, 0.0, 1.0) : 0.0;
      return std::hypot(g->x0 + u * dx - px, g->y0 + u * dy - py);
    };
    std::stable_sort(near.begin(), near.end(), [&](const Segment* a, const Segment* b) { return distance(a) < distance(b); });
    constexpr size_t kShown = 6;
    for (size_t i = 0; i < std::min(near.size(), kShown); ++i) {
      const Segment& g = *near[i];
      BoundaryMasks one(m_.width(), m_.height(), false);
      rasterize_edges(one, std::span<const Segment>(&g, 1));
      int crossings = 0;
      for (uint8_t b : one.top) crossings += std::popcount(unsigned(b));
      for (uint8_t b : one.left) crossings += std::popcount(unsigned(b));
      Step& s = add(2, "4.5 Constructing the edge-and-point image",
                    "Edge " + std::to_string(i + 1) + " of " + std::to_string(near.size()) +
                        " in the window (nearest first) is intersected with every grid line it crosses; each crossing sets the bit of "
                        "its 1/8-pixel piece (purple).");
      s.view.samples = false;
      add_crossings(s.view, one, 0, kEdgeLine);
      Shape line;
      line.points = {{g.x0, g.y0}, {g.x1, g.y1}};
      line.closed = false, line.stroke = kFocus, line.width = 4;
      s.view.shapes.push_back(line);
      s.values["from"] = Json::array({num(g.x0, 2), num(g.y0, 2)});
      s.values["to"] = Json::array({num(g.x1, 2), num(g.y1, 2)});
      s.values["grid-line crossings"] = crossings;
    }
    {
      Step& s = add(2, "4.5 Constructing the edge-and-point image",
                    near.size() > kShown ? "All " + std::to_string(near.size()) +
                                               " edges of the window rasterized: the masks are the OR of every edge's crossings."
                                         : "All edges rasterized: each pixel side keeps an 8-bit mask, shared by the two pixels it separates.");
      s.view.samples = false, s.view.crossings = 1;
      s.values["edges in window"] = near.size();
    }
    // The followed pixel's four sides, bit by bit.
    for (int side = 0; side < 4; ++side) {
      const uint8_t mask = t_.sides[side];
      std::string positions;
      for (int bit = 0; bit < 8; ++bit)
        if ((mask >> bit) & 1) positions += (positions.empty() ? "" : ", ") + std::to_string(boundary_position(side, bit, 8));
      Step& s = add(2, "4.2 Edge representation",
                    std::string("The ") + side_name(side) + " side of the pixel: its 8-bit mask " +
                        (mask ? "marks the pieces an edge crosses, numbered clockwise around the pixel as boundary positions."
                              : "is empty: no edge crosses it."));
      s.view.radius = 1, s.view.samples = false, s.view.crossings = 1;
      s.view.marks.clear();  // the side itself is the highlight
      const Rgba kSide{0.0, 0.55, 0.75, 0.9};
      for (int bit = 0; bit < 8; ++bit) {
        const int position = boundary_position(side, bit, 8);
        const auto ends = piece(position, 8);
        Shape sl;
        sl.points = {{t_.x + ends[0][0], t_.y + ends[0][1]}, {t_.x + ends[1][0], t_.y + ends[1][1]}};
        sl.closed = false, sl.width = 10;
        sl.stroke = ((mask >> bit) & 1) ? Rgba{0.55, 0.0, 0.55, 1} : kSide;
        s.view.shapes.push_back(sl);
        // The piece's boundary position, just inside the pixel.
        const double mx = 0.5 * (ends[0][0] + ends[1][0]), my = 0.5 * (ends[0][1] + ends[1][1]);
        const double ix = mx + (side == 1 ? -0.07 : side == 3 ? 0.07 : 0), iy = my + (side == 0 ? 0.07 : side == 2 ? -0.07 : 0);
        s.view.texts.push_back({t_.x + ix, t_.y + iy, std::to_string(position), 13,
                                ((mask >> bit) & 1) ? Rgba{0.55, 0.0, 0.55, 1} : Rgba{0.0, 0.35, 0.5, 1}});
      }
      s.values["side"] = side_name(side);
      s.values["mask (bit 7..0)"] = bits_of(mask, 8);
      s.values["boundary positions"] = positions.empty() ? "none" : positions;
    }
    {
      std::string caption;
      const int count = std::popcount(unsigned(t_.sides[0])) + std::popcount(unsigned(t_.sides[1])) +
                        std::popcount(unsigned(t_.sides[2])) + std::popcount(unsigned(t_.sides[3]));
      // Complex although its crossings alone make one edge: the centre lines showed a corner.
      const bool corner = t_.kind == CellKind::complex && geom::classify_cell(t_.sides, 8).kind == CellKind::simple;
      if (t_.kind == CellKind::simple)
        caption = "Two crossings on different sides make one edge, coded in 10 bits as its two boundary positions "
                  "(5 bits each): code = " + std::to_string(t_.p_low) + " << 5 | " + std::to_string(t_.p_high) + ".";
      else if (t_.kind == CellKind::empty)
        caption = count == 0 ? "No crossing on any side: the pixel's code is 0 (empty)."
                             : "A single crossing (an edge ending inside) cannot split the pixel: code 0 (empty).";
      else if (corner)
        caption = "Two crossings on different sides, but the centre lines show the edge leaving their chord by more "
                  "than 1/8 pixel: a corner inside the pixel, not one straight edge: code 1 (complex).";
      else
        caption = std::to_string(count) + " crossings (or two on one side) cannot be one straight edge: code 1 (complex).";
      Step& s = add(2, "4.2 Edge representation", caption);
      s.view.radius = 1, s.view.samples = false, s.view.crossings = corner ? 2 : 1, s.view.reconstructed_edges = true;
      s.values["crossings"] = count;
      s.values["edge code"] = t_.code;
      s.values["code bits"] = bits_of(unsigned(t_.code), 10);
      if (t_.kind == CellKind::simple) s.values["ends"] = Json::array({t_.p_low, t_.p_high});
    }
  }

  void add_crossings(View& v, const BoundaryMasks& masks, int /*unused*/, Rgba color) {
    const int r = 5;
    for (int y = std::max(0, t_.y - r); y <= std::min(m_.height(), t_.y + r); ++y)
      for (int x = std::max(0, t_.x - r); x <= std::min(m_.width(), t_.x + r); ++x) {
        const uint8_t top = masks.top[masks.index(x, y)], left = masks.left[masks.index(x, y)];
        for (int bit = 0; bit < 8; ++bit) {
          if ((top >> bit) & 1) {
            Shape s;
            s.points = {{x + bit / 8.0, double(y)}, {x + (bit + 1) / 8.0, double(y)}};
            s.closed = false, s.stroke = color, s.width = 7;
            v.shapes.push_back(s);
          }
          if ((left >> bit) & 1) {
            Shape s;
            s.points = {{double(x), y + bit / 8.0}, {double(x), y + (bit + 1) / 8.0}};
            s.closed = false, s.stroke = color, s.width = 7;
            v.shapes.push_back(s);
          }
        }
      }
  }

  // Stage 3.
  void classification() {
    int counts[3] = {};
    for (int y = std::max(0, t_.y - 4); y <= std::min(m_.height() - 1, t_.y + 4); ++y)
      for (int x = std::max(0, t_.x - 4); x <= std::min(m_.width() - 1, t_.x + 4); ++x) {
        const int type = m_.type_at(x, y);
        ++counts[type == kTypeEmpty ? 0 : type == kTypeComplex ? 2 : 1];
      }
    {
      Step& s = add(3, "4.1 Pixel classification",
                    "Every pixel is classified from its crossings: empty (white), simple (green: one edge spanning it) "
                    "or complex (pink: anything else, and a corner the centre lines show).");
      s.view.classes = true, s.view.crossings = 1, s.view.samples = false, s.view.reconstructed_edges = true;
      s.values["empty"] = counts[0], s.values["simple"] = counts[1], s.values["complex"] = counts[2];
    }
    {
      std::string caption = t_.kind == CellKind::simple
                                ? "The followed pixel is simple: its edge joins the centres of the two crossed pieces and "
                                  "cuts it into region A (clockwise from the first end) and region B."
                            : t_.kind == CellKind::empty
                                ? "The followed pixel is empty: no edge splits it, the whole pixel is one region."
                                : "The followed pixel is complex: no single edge describes it, so reachability will stop there.";
      Step& s = add(3, "4.1 Pixel classification", caption);
      s.view.radius = 1, s.view.crossings = 1, s.view.reconstructed_edges = true, s.view.samples = false;
      if (t_.kind == CellKind::simple) shade_regions(s.view, kRegionA, kRegionB);
      else s.view.marks.push_back(pixel_mark(t_.x, t_.y, t_.kind == CellKind::empty ? kEmptyFill : kComplexFill));
      s.values["class"] = kind_name(t_.kind);
      if (t_.kind == CellKind::simple) {
        s.values["colours"] = "blue: A, pink: B";
        s.values["area of A"] = num(t_.area_a), s.values["area of B"] = num(1 - t_.area_a);
      }
    }
    {
      std::string caption;
      if (t_.kind != CellKind::simple)
        caption = t_.has_sample ? "Sidedness: with no edge in the pixel (or a complex one), its sample needs no side test."
                                : "Sidedness: this pixel holds no sample; neighbouring samples are tested in their own pixels.";
      else if (!t_.has_sample)
        caption = "Sidedness: a table lookup (edge code x 4-bit region) tells, for each of the 16 regions, side A, side B "
                  "or edge-ambiguous (grey); this pixel has no sample to test.";
      else
        caption = std::string("Sidedness: the table (edge code x 4-bit region) puts this pixel's sample in ") +
                  (t_.sample_side == 0 ? "region A." : t_.sample_side == 1 ? "region B." : "neither: it is edge-ambiguous and unusable.");
      Step& s = add(3, "4.3 Point representation", caption);
      s.view.radius = 1, s.view.reconstructed_edges = true, s.view.sample_regions = true;
      if (t_.kind == CellKind::simple) {
        const EpiTables& tb = epi_tables();
        for (int region = 0; region < 16; ++region) {
          const int side = tb.side(t_.code, region);
          CellMark mk{t_.x + (region & 3) * 0.25, t_.y + (region >> 2) * 0.25, 0.25, 0.25,
                      side == 0 ? kRegionA : side == 1 ? kRegionB : kAmbiguous, {0, 0, 0, 0}, 0, {}, side == 2};
          s.view.marks.push_back(mk);
        }
      }
      if (t_.kind == CellKind::simple) s.values["colours"] = "blue: A, pink: B, hatched grey: edge-ambiguous";
      s.values["sample"] = t_.has_sample ? "region " + std::to_string(t_.sample_region) : std::string("none");
      if (t_.has_sample) s.values["side"] = t_.sample_side < 0 ? "whole pixel" : t_.sample_side == 0 ? "A" : t_.sample_side == 1 ? "B" : "ambiguous";
      s.values["usable"] = t_.usable;
    }
    {
      std::string caption;
      if (t_.kind == CellKind::simple)
        caption = t_.usable ? std::string("The region holding the usable sample is primary: region ") + (t_.primary_is_b ? "B" : "A") +
                                  "; the other is secondary."
                            : std::string("Without a usable sample the larger region is primary: region ") +
                                  (t_.primary_is_b ? "B" : "A") + ".";
      else
        caption = std::string("An ") + (t_.kind == CellKind::empty ? "empty" : "complex") +
                  " pixel is all primary; its 4-bit type (class and the two sides the edge touches) is what reachability reads.";
      Step& s = add(3, "5.1 Pixel regions", caption);
      s.view.radius = 1, s.view.reconstructed_edges = true;
      if (t_.kind == CellKind::simple) {
        const Rgba primary{0.2, 0.45, 0.95, 0.45}, secondary{0.95, 0.55, 0.7, 0.35};
        shade_regions(s.view, t_.primary_is_b ? secondary : primary, t_.primary_is_b ? primary : secondary);
      }
      if (t_.kind == CellKind::simple) s.values["colours"] = "blue: primary, pink: secondary";
      s.values["primary"] = t_.kind == CellKind::simple ? (t_.primary_is_b ? "B" : "A") : "whole pixel";
      s.values["type (4 bits)"] = std::to_string(t_.type) + " = " + type_name(t_.type);
    }
  }

  void shade_regions(View& v, Rgba a, Rgba b) const {
    Shape sa = translated(region_polygon(t_.p_low, t_.p_high, 8, 0), t_.x, t_.y);
    sa.fill = a;
    Shape sb = translated(region_polygon(t_.p_low, t_.p_high, 8, 1), t_.x, t_.y);
    sb.fill = b;
    v.shapes.push_back(sa), v.shapes.push_back(sb);
  }

  // Stage 4.
  void type_marks(View& v) const {
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int k = (dy + 2) * 5 + dx + 2, type = t_.types[k];
        CellMark mk = pixel_mark(t_.x + dx, t_.y + dy, type == kTypeEmpty ? Rgba{0, 0, 0, 0} : type == kTypeComplex ? kComplexFill : kSimpleFill);
        mk.hatch = type == kTypeComplex;
        mk.label = t_.inside[k] ? type_short(type) : "out";
        v.marks.push_back(mk);
      }
  }

  void reachability() {
    const char* section = "5.2 Reachability map";
    {
      Step& s = add(4, section,
                    "Reachability reads only the 5x5 pixel types: E empty, C complex, and for simple pixels the two "
                    "sides their edge touches (T, R, B, L) with the primary region.");
      s.view.radius = 2, s.view.samples = false, s.view.reconstructed_edges = true;
      type_marks(s.view);
      int complex = 0;
      for (int k = 0; k < 25; ++k) complex += t_.types[k] == kTypeComplex;
      s.values["complex or outside"] = complex;
    }
    if (t_.reach_fast_path) {
      Step& s = add(4, section,
                    "All 25 pixels are empty, so no edge can block a path: every neighbour is reachable without a "
                    "single table lookup (the fast path).");
      s.view.radius = 2, s.view.samples = false;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx)
          if (dx || dy) s.view.marks.push_back(pixel_mark(t_.x + dx, t_.y + dy, kReached));
      s.values["24-bit mask"] = "0xffffff";
      return;
    }
    uint8_t done[25] = {};
    bool have[25] = {};
    for (const ReachStep& r : t_.reach_steps) {
      std::string caption;
      auto pred_name = [&](int k) { return r.pred_dx[k] == 0 && r.pred_dy[k] == 0 ? std::string("the centre") : offset(r.pred_dx[k], r.pred_dy[k]); };
      const bool complex_here = r.type == kTypeComplex;
      if (t_.types[12] == kTypeComplex && r.preds == 1 && r.pred_dx[0] == 0 && r.pred_dy[0] == 0)
        caption = "The centre is complex, so the table gives side neighbour " + offset(r.dx, r.dy) +
                  " no reachability (0000): a complex pixel reaches nothing and takes the simple estimate (stage 5).";
      else if (complex_here)
        caption = "Neighbour " + offset(r.dx, r.dy) + " is " + (t_.inside[(r.dy + 2) * 5 + r.dx + 2] ? "complex" : "outside the image") +
                  ": complex pixels are unreachable and stop propagation (mask 0000).";
      else if (r.preds == 1 && r.pred_dx[0] == 0 && r.pred_dy[0] == 0)
        caption = "Side neighbour " + offset(r.dx, r.dy) + ": the neighbour table, indexed by the two 4-bit types and the "
                  "direction " + dir_name(r.dir[0]) + ", gives the 4-bit reachability " + reach4(r.mask) + " directly.";
      else if (r.preds == 1)
        caption = "Neighbour " + offset(r.dx, r.dy) + " via " + pred_name(0) + ": the table's step " + reach4(r.neighbour[0]) +
                  " is chained onto centre<->" + pred_name(0) + " " + reach4(done[(r.pred_dy[0] + 2) * 5 + r.pred_dx[0] + 2]) +
                  " through both of its regions, giving " + reach4(r.mask) + ".";
      else
        caption = "Diagonal " + offset(r.dx, r.dy) + " has two paths, via " + pred_name(0) + " " + reach4(r.path[0]) + " and via " +
                  pred_name(1) + " " + reach4(r.path[1]) + ": combining ORs them into " + reach4(r.mask) + ".";
      Step& s = add(4, section, caption);
      s.view.radius = 2, s.view.samples = false, s.view.reconstructed_edges = true;
      for (int k = 0; k < 25; ++k) {
        const int dx = k % 5 - 2, dy = k / 5 - 2;
        if (!have[k] || (dx == 0 && dy == 0)) continue;
        s.view.marks.push_back(pixel_mark(t_.x + dx, t_.y + dy, (done[k] & kReachPP) ? kReached : kUnreached, {0, 0, 0, 0}, 0, reach4(done[k])));
      }
      {
        CellMark c = pixel_mark(t_.x, t_.y, {0, 0, 0, 0}, {0, 0, 0, 0}, 0, "centre");
        s.view.marks.push_back(c);
      }
      CellMark target = pixel_mark(t_.x + r.dx, t_.y + r.dy, (r.mask & kReachPP) ? kReached : kUnreached, {0.1, 0.1, 0.1, 1}, 4, reach4(r.mask));
      target.hatch = complex_here;
      s.view.marks.push_back(target);
      for (int k = 0; k < r.preds; ++k)
        s.view.arrows.push_back({t_.x + r.pred_dx[k] + 0.5, t_.y + r.pred_dy[k] + 0.5, t_.x + r.dx + 0.5, t_.y + r.dy + 0.5, kArrow});
      s.values["colours"] = "yellow: primary reachable from the centre, grey: not";
      s.values["offset"] = offset(r.dx, r.dy);
      s.values["type"] = type_name(r.type);
      for (int k = 0; k < r.preds; ++k) {
        const std::string p = "via " + offset(r.pred_dx[k], r.pred_dy[k]);
        s.values[p + ": table[" + dir_name(r.dir[k]) + "][" + type_short(r.pred_type[k]) + "," + type_short(r.type) + "]"] = reach4(r.neighbour[k]);
        if (!(r.pred_dx[k] == 0 && r.pred_dy[k] == 0)) s.values[p + ": chained path"] = reach4(r.path[k]);
      }
      s.values["mask (Pa-Pb,Pa-Sb,Sa-Pb,Sa-Sb)"] = reach4(r.mask);
      s.values["primary reachable"] = bool(r.mask & kReachPP);
      const int k = (r.dy + 2) * 5 + r.dx + 2;
      done[k] = r.mask, have[k] = true;
    }
    {
      const int reached = std::popcount(t_.reach);
      Step& s = add(4, section,
                    "The final 24-bit mask keeps the primary-to-primary bit of each neighbour: " + std::to_string(reached) +
                        " of 24 are reachable (yellow) and may lend their samples.");
      s.view.radius = 2, s.view.reconstructed_edges = true;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx)
          if (dx || dy) s.view.marks.push_back(pixel_mark(t_.x + dx, t_.y + dy, ((t_.reach >> reach_bit(dx, dy)) & 1) ? kReached : kUnreached));
      char hex[16];
      std::snprintf(hex, sizeof(hex), "0x%06x", t_.reach);
      s.values["24-bit mask"] = hex;
      s.values["reachable"] = reached;
    }
  }

  // Stage 5.
  void interpolation() {
    const char* section = "5.3 Interpolation";
    {
      Step& s = add(5, section,
                    "The interpolation kernel w = 1 / (1 + dx^2 + dy^2)^2 is sharply peaked: the pixel's own sample weighs 1, "
                    "its side neighbours 1/4, the corners of the 5x5 1/81.");
      s.view.radius = 2;
      static const char* labels[25] = {"1/81", "1/36", "1/25", "1/36", "1/81", "1/36", "1/9", "1/4", "1/9", "1/36", "1/25", "1/4", "1",
                                       "1/4", "1/25", "1/36", "1/9", "1/4", "1/9", "1/36", "1/81", "1/36", "1/25", "1/36", "1/81"};
      for (int k = 0; k < 25; ++k) s.view.marks.push_back(pixel_mark(t_.x + k % 5 - 2, t_.y + k / 5 - 2, {1, 1, 1, 0.5}, {0, 0, 0, 0}, 0, labels[k]));
    }
    {
      std::string caption = t_.complex_estimate
                                ? "A complex pixel ignores reachability: the simple estimate takes every sample of its 5x5 (" +
                                      std::to_string(t_.contributions.size()) + ") with the kernel weights."
                                : "Only reachable pixels with a usable sample count: " + std::to_string(t_.contributions.size()) +
                                      " samples; unreachable and empty pixels weigh 0.";
      Step& s = add(5, section, caption);
      s.view.radius = 2, s.view.reconstructed_edges = true;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx)
          if ((dx || dy) && !t_.complex_estimate && !((t_.reach >> reach_bit(dx, dy)) & 1))
            s.view.marks.push_back(pixel_mark(t_.x + dx, t_.y + dy, kUnreached));
      Json list = Json::array();
      for (const auto& c : t_.contributions) {
        s.view.marks.push_back(pixel_mark(t_.x + c.dx, t_.y + c.dy, kWeight, {0.1, 0.5, 0.2, 1}, 3, "w " + num(c.weight, 3)));
        list.push_back(offset(c.dx, c.dy) + " w " + num(c.weight, 4));
      }
      s.values["colours"] = "green: samples used (weight w), grey: unreachable, crossed red: edge-ambiguous";
      s.values["samples used"] = list;
      s.values["total weight W"] = num(t_.total_weight, 4);
    }
    if (!t_.fallback) {
      Step& s = add(5, section,
                    "Renormalize: the colour is sum(w c) / W over the used samples, so the missing weight does not darken it.");
      s.view.radius = 2;
      for (const auto& c : t_.contributions) s.view.marks.push_back(pixel_mark(t_.x + c.dx, t_.y + c.dy, kWeight));
      s.view.swatches.push_back({"interpolated", t_.interpolated});
      s.values["W"] = num(t_.total_weight, 4);
      s.values["colour (linear)"] = rgb_json(t_.interpolated);
      Step& f = add(5, "5.3 Interpolation (fill: our addition)",
                    "The pixel found reachable samples, so neither the 7x7 fallback nor the fill step runs for it.");
      f.view.radius = 2;
      f.view.swatches.push_back({"primary colour", t_.filled});
      f.values["fallback"] = false;
    } else {
      std::string caption = t_.fallback_contributions.empty()
                                ? "No sample is reachable in the 5x5, nor in the 7x7 (reachability one ring further): the last resort "
                                  "applies (the simple estimate where the 5x5 holds an edge, black where it does not)."
                                : "No sample is reachable in the 5x5: the 7x7 fallback extends reachability one ring further and "
                                  "takes the " + std::to_string(t_.fallback_contributions.size()) + " reachable samples there.";
      Step& s = add(5, "5.3 Interpolation (7x7 fallback)", caption);
      s.view.radius = 3;
      for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx)
          if (dx || dy)
            s.view.marks.push_back(pixel_mark(t_.x + dx, t_.y + dy, ((t_.reach7 >> window7_bit(dx, dy)) & 1) ? kReached : kUnreached));
      for (const auto& c : t_.fallback_contributions)
        s.view.marks.push_back(pixel_mark(t_.x + c.dx, t_.y + c.dy, kWeight, {0.1, 0.5, 0.2, 1}, 3, "w " + num(c.weight, 3)));
      s.view.swatches.push_back({"fallback colour", t_.interpolated});
      s.values["7x7 samples"] = t_.fallback_contributions.size();
      s.values["colour (linear)"] = rgb_json(t_.interpolated);
      s.values["priority"] = "16 (reached nothing)";
      std::string fill_caption = !t_.fill_ran ? "Fill is off: the pixel keeps its fallback colour."
                                 : t_.fill_contributions.empty()
                                     ? "Fill: no reachable neighbour found samples either, so the fallback colour stays."
                                     : "Fill: the kernel-weighted mean of the primary colours of the " +
                                           std::to_string(t_.fill_contributions.size()) +
                                           " reachable neighbours that did find samples replaces the fallback.";
      Step& f = add(5, "5.3 Interpolation (fill: our addition)", fill_caption);
      f.view.radius = 2;
      for (const auto& c : t_.fill_contributions)
        f.view.marks.push_back(pixel_mark(t_.x + c.dx, t_.y + c.dy, kWeight, {0.1, 0.5, 0.2, 1}, 3, "w " + num(c.weight, 3)));
      f.view.swatches.push_back({"fallback", t_.interpolated});
      f.view.swatches.push_back({"after fill", t_.filled});
      f.values["neighbours used"] = t_.fill_contributions.size();
      f.values["colour (linear)"] = rgb_json(t_.filled);
    }
  }

  void comparison(Step& s) const {
    s.view.swatches.push_back({"EPI result", t_.result});
    if (const RgbImage* exact = m_.exact()) {
      const float* e = exact->at(t_.x, t_.y);
      s.view.swatches.push_back({"exact coverage", {e[0], e[1], e[2]}});
      s.values["exact coverage"] = rgb_json({e[0], e[1], e[2]});
    }
    s.view.swatches.push_back({"render cache", t_.rendercache});
    s.values["EPI result"] = rgb_json(t_.result);
    s.values["render cache"] = rgb_json(t_.rendercache);
  }

  // Stage 6.
  void antialiasing() {
    const char* section = "5.3 Anti-aliasing";
    if (t_.output != PixelTrace::Output::antialiased) {
      std::string caption = t_.kind == CellKind::complex
                                ? "Anti-aliasing blends only simple pixels; this complex pixel is shaded by the complex filter (stage 7)."
                                : t_.kind == CellKind::empty
                                      ? "An empty pixel has no edge to anti-alias: its output is its interpolated (primary) colour."
                                      : "Anti-aliasing is off: the simple pixel keeps its primary colour.";
      Step& s = add(6, section, caption);
      s.view.radius = 1, s.view.reconstructed_edges = true;
      if (t_.output == PixelTrace::Output::filled) comparison(s);
      s.values["anti-aliased"] = false;
      return;
    }
    {
      Step& s = add(6, section,
                    "The edge splits the pixel's area: the primary region covers " + num(t_.primary_area, 3) + " of it, the secondary " +
                        num(1 - t_.primary_area, 3) + " (an area table indexed by the edge code).");
      s.view.radius = 1, s.view.reconstructed_edges = true;
      const Rgba primary{0.2, 0.45, 0.95, 0.45}, secondary{0.95, 0.55, 0.7, 0.35};
      shade_regions(s.view, t_.primary_is_b ? secondary : primary, t_.primary_is_b ? primary : secondary);
      s.values["primary area a"] = num(t_.primary_area, 4);
    }
    {
      std::string caption;
      if (t_.secondary_neighbour < 0)
        caption = "The neighbour the table picks for the secondary colour lies outside the image: the pixel keeps its primary colour.";
      else
        caption = "The secondary region borrows the primary colour of neighbour " +
                  offset(kNeighbourDx[t_.secondary_neighbour], kNeighbourDy[t_.secondary_neighbour]) +
                  ", the one with the most area on the edge's far side (an edge-indexed table).";
      Step& s = add(6, section, caption);
      s.view.radius = 1, s.view.reconstructed_edges = true;
      if (t_.secondary_neighbour >= 0) {
        const int nx = t_.x + kNeighbourDx[t_.secondary_neighbour], ny = t_.y + kNeighbourDy[t_.secondary_neighbour];
        s.view.marks.push_back(pixel_mark(nx, ny, {0.95, 0.55, 0.7, 0.35}, {0.7, 0.1, 0.3, 1}, 4, "secondary"));
        s.view.arrows.push_back({nx + 0.5, ny + 0.5, t_.x + 0.5, t_.y + 0.5, kArrow});
      }
      s.view.swatches.push_back({"primary", t_.filled});
      if (t_.secondary_neighbour >= 0) s.view.swatches.push_back({"secondary", t_.secondary});
      s.values["primary colour"] = rgb_json(t_.filled);
      if (t_.secondary_neighbour >= 0) s.values["secondary colour"] = rgb_json(t_.secondary);
    }
    {
      Step& s = add(6, section,
                    "Blend in linear light: a x primary + (1 - a) x secondary, with a = " + num(t_.primary_area, 3) +
                        ": an anti-aliased edge from one sample per few pixels.");
      s.view.radius = 1, s.view.reconstructed_edges = true;
      comparison(s);
    }
  }

  // Stage 7.
  void complex_pixels() {
    const char* section = "5.4 Complex pixels";
    if (t_.output != PixelTrace::Output::complex_filter) {
      Step& s = add(7, section,
                    t_.kind == CellKind::complex
                        ? "The complex filter is off: this complex pixel keeps the simple estimate."
                        : std::string("The complex filter runs only for complex pixels; this ") + kind_name(t_.kind) +
                              " pixel is done.");
      s.view.radius = 1, s.view.reconstructed_edges = true;
      s.values["complex filter"] = false;
      return;
    }
    const ComplexTrace& c = t_.complex;
    auto sub_rect = [&](int u, int v) { return std::array<double, 2>{t_.x - 1 + u * 0.5, t_.y - 1 + v * 0.5}; };
    int kinds[3] = {};
    for (int v = 0; v < 6; ++v)
      for (int u = 0; u < 6; ++u) ++kinds[int(c.sub[v][u].kind)];
    {
      Step& s = add(7, section,
                    "Centre lines through every pixel (recorded during rasterization) cut the 3x3 neighbourhood into 6x6 "
                    "sub-pixels with 4 pieces per side.");
      s.view.radius = 1, s.view.subpixel_grid = true, s.view.crossings = 2, s.view.samples = false;
    }
    {
      Step& s = add(7, section,
                    "Each sub-pixel is classified like a pixel: " + std::to_string(kinds[0]) + " empty, " + std::to_string(kinds[1]) +
                        " simple (with an edge), " + std::to_string(kinds[2]) + " complex or outside.");
      s.view.radius = 1, s.view.subpixel_grid = true, s.view.crossings = 2, s.view.samples = false;
      for (int v = 0; v < 6; ++v)
        for (int u = 0; u < 6; ++u) {
          const auto& sp = c.sub[v][u];
          const auto o = sub_rect(u, v);
          CellMark mk{o[0], o[1], 0.5, 0.5, sp.kind == CellKind::empty ? kEmptyFill : sp.kind == CellKind::simple ? kSimpleFill : kComplexFill, {0, 0, 0, 0}, 0, {}, sp.kind == CellKind::complex};
          s.view.marks.push_back(mk);
          if (sp.kind == CellKind::simple) {
            const geom::CellEdge e = geom::cell_edge(sp.p_low, sp.p_high, 4);
            Shape line;
            line.points = {{o[0] + 0.5 * e.a.x, o[1] + 0.5 * e.a.y}, {o[0] + 0.5 * e.b.x, o[1] + 0.5 * e.b.y}};
            line.closed = false, line.stroke = kEdgeLine, line.width = 3;
            s.view.shapes.push_back(line);
          }
        }
    }
    std::vector<int> groups;
    auto group_color = [&](int g) {
      auto it = std::find(groups.begin(), groups.end(), g);
      if (it == groups.end()) groups.push_back(g), it = groups.end() - 1;
      static const Rgba palette[8] = {{0.30, 0.55, 0.95, 0.5}, {0.95, 0.60, 0.20, 0.5}, {0.40, 0.80, 0.40, 0.5}, {0.80, 0.40, 0.85, 0.5},
                                      {0.95, 0.85, 0.25, 0.5}, {0.30, 0.85, 0.85, 0.5}, {0.85, 0.35, 0.40, 0.5}, {0.60, 0.60, 0.35, 0.5}};
      return palette[size_t(it - groups.begin()) % 8];
    };
    {
      Step& s = add(7, section, "");
      s.view.radius = 1, s.view.subpixel_grid = true, s.view.samples = false;
      for (int v = 0; v < 6; ++v)
        for (int u = 0; u < 6; ++u) {
          const auto& sp = c.sub[v][u];
          const auto o = sub_rect(u, v);
          if (sp.kind == CellKind::complex) {
            s.view.marks.push_back({o[0], o[1], 0.5, 0.5, kComplexFill, {0, 0, 0, 0}, 0, {}, true});
          } else if (sp.kind == CellKind::empty) {
            s.view.marks.push_back({o[0], o[1], 0.5, 0.5, group_color(sp.group[0]), {0, 0, 0, 0}, 0, {}, false});
          } else {
            for (int region = 0; region < 2; ++region) {
              Shape sh = translated(region_polygon(sp.p_low, sp.p_high, 4, region), o[0], o[1], 0.5);
              sh.fill = group_color(sp.group[region]);
              s.view.shapes.push_back(sh);
            }
          }
        }
      s.caption = "Sub-pixel regions that touch across a side with no edge between them are joined (one colour per connected "
                  "region): " + std::to_string(groups.size()) + " regions.";
      s.values["connected regions"] = groups.size();
    }
    {
      int placed = 0;
      for (const auto& sm : c.samples) placed += sm.region < 2;
      Step& s = add(7, section,
                    "The 3x3's samples are placed in their sub-pixel regions: " + std::to_string(placed) + " placed, " +
                        std::to_string(c.samples.size() - size_t(placed)) + " dropped (edge-ambiguous at sub-pixel level, or in a complex sub-pixel).");
      s.view.radius = 1, s.view.subpixel_grid = true;
      for (const auto& sm : c.samples) {
        const auto o = sub_rect(sm.u, sm.v);
        s.view.marks.push_back({o[0], o[1], 0.5, 0.5, sm.region < 2 ? group_color(sm.group) : Rgba{0.5, 0.5, 0.5, 0.5},
                                sm.region < 2 ? Rgba{0.1, 0.5, 0.2, 1} : Rgba{0.8, 0.1, 0.1, 1}, 3,
                                sm.region < 2 ? "placed" : "dropped", sm.region >= 2});
      }
      s.values["placed"] = placed;
      s.values["dropped"] = c.samples.size() - size_t(placed);
    }
    {
      Step& s = add(7, section,
                    "Each of the pixel's four sub-pixels takes its regions' sample colours (kernel-weighted; simple ones blended by "
                    "area, unreached ones the simple estimate), and the pixel is their average.");
      s.view.radius = 1, s.view.subpixel_grid = true;
      for (int k = 0; k < 4; ++k) {
        const auto& ce = c.centre[k];
        const int u = 2 + (k & 1), v = 2 + (k >> 1);
        const auto o = sub_rect(u, v);
        s.view.marks.push_back({o[0], o[1], 0.5, 0.5, {srgb(ce.rgb[0]), srgb(ce.rgb[1]), srgb(ce.rgb[2]), 1.0}, {0.1, 0.1, 0.1, 1}, 2,
                                std::string("sub ") + std::to_string(k + 1), false});
        s.view.swatches.push_back({"sub-pixel " + std::to_string(k + 1), {ce.rgb[0], ce.rgb[1], ce.rgb[2]}});
        s.values["sub-pixel " + std::to_string(k + 1)] = rgb_json({ce.rgb[0], ce.rgb[1], ce.rgb[2]});
      }
      s.values["simple estimate"] = rgb_json(t_.estimate);
      comparison(s);
    }
  }

  // Stage 8.
  void priority() {
    const char* section = "5.3 Prioritized sampling";
    std::string caption;
    if (t_.fallback)
      caption = "The pixel reached no sample in its 5x5, so it gets the highest priority, 16: the next frame's samples go here first.";
    else if (t_.usable)
      caption = "The pixel has its own usable sample, so its priority only grows with the sample's age: age / 16 = " +
                num(t_.priority, 3) + ".";
    else
      caption = "Without a usable sample of its own, the priority is 1 / W (capped at 15): the less reachable weight it found, "
                "the more it asks for a sample.";
    Step& s = add(8, section, caption);
    s.view.radius = 2, s.view.reconstructed_edges = true;
    for (const auto& c : t_.contributions)
      if (!t_.fallback) s.view.marks.push_back(pixel_mark(t_.x + c.dx, t_.y + c.dy, kWeight));
    s.values["priority"] = num(t_.priority, 4);
    if (t_.usable) s.values["sample age"] = t_.age;
    else if (!t_.fallback) s.values["W"] = num(t_.total_weight, 4);
    comparison(s);
  }

  const Model& m_;
  const PixelTrace& t_;
  std::vector<Step> steps_;
};

}  // namespace

const char* stage_name(int stage) {
  static const char* names[kStageCount] = {"Input", "Edge rasterization", "Classification", "Reachability",
                                           "Interpolation", "Anti-aliasing", "Complex pixels", "Priority"};
  return stage >= 1 && stage <= kStageCount ? names[stage - 1] : "?";
}

std::vector<std::array<double, 2>> region_polygon(int p_low, int p_high, int n, int region) {
  const geom::CellEdge e = geom::cell_edge(p_low, p_high, n);
  std::vector<std::array<double, 2>> pts;
  const double from = p_low + 0.5, to = p_high + 0.5;
  if (region == 0) {
    pts.push_back({e.a.x, e.a.y});
    for (int k = 1; k < 4; ++k)
      if (k * n > from && k * n < to) {
        const geom::Vec2 c = geom::perimeter_point(k * n, n);
        pts.push_back({c.x, c.y});
      }
    pts.push_back({e.b.x, e.b.y});
  } else {
    pts.push_back({e.b.x, e.b.y});
    for (int k = 1; k <= 4; ++k) {
      const int corner = k % 4;  // perimeter coordinate k * n, corner 0 at 4n
      if (k * n > to) {
        const geom::Vec2 c = geom::perimeter_point(corner * n, n);
        pts.push_back({c.x, c.y});
      }
    }
    for (int k = 1; k < 4; ++k)
      if (k * n < from) {
        const geom::Vec2 c = geom::perimeter_point(k * n, n);
        pts.push_back({c.x, c.y});
      }
    pts.push_back({e.a.x, e.a.y});
  }
  return pts;
}

std::vector<Step> build_steps(const Model& model, const PixelTrace& trace) { return Builder(model, trace).build(); }

}  // namespace epi::vis

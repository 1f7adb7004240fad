#include "epi/pattern.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace epi {

namespace {

using nlohmann::json;

std::array<float, 3> parse_color(const json& j, const std::string& where, const std::string& name) {
  if (!j.is_array() || j.size() != 3) throw PatternError(name + ": " + where + ": expected [r,g,b]");
  std::array<float, 3> c{};
  for (size_t k = 0; k < 3; ++k) {
    if (!j[k].is_number()) throw PatternError(name + ": " + where + ": expected [r,g,b] numbers");
    const double v = j[k].get<double>();
    if (!std::isfinite(v) || v < 0.0 || v > 1.0)
      throw PatternError(name + ": " + where + ": colour components must be in [0,1]");
    c[k] = float(v);
  }
  return c;
}

// 64-bit mixing (splitmix64), so the sampling is the same on every platform.
uint64_t mix(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
double uniform(uint64_t& state) { return double((state = mix(state)) >> 11) * 0x1.0p-53; }

bool inside_polygon(const Polygon& p, double x, double y) {
  bool inside = false;
  const size_t n = p.points.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const double xi = p.points[i][0], yi = p.points[i][1], xj = p.points[j][0], yj = p.points[j][1];
    if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) inside = !inside;
  }
  return inside;
}

}  // namespace

Pattern parse_pattern(const std::string& text, const std::string& name) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw PatternError(name + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  } catch (const json::exception&) {  // out_of_range.406: a number too large for a double (1e400)
    throw PatternError(name + ": a number is too large for a double");
  }
  if (!j.is_object()) throw PatternError(name + ": expected a JSON object");
  Pattern p;
  for (const char* key : {"width", "height"}) {
    if (!j.contains(key) || !j[key].is_number_integer())
      throw PatternError(name + ": '" + key + "' must be an integer");
    const long long v = j[key].get<long long>();
    if (v < 1 || v > kMaxPatternSize)
      throw PatternError(name + ": '" + key + "' must be in [1, " + std::to_string(kMaxPatternSize) + "]");
    (key[0] == 'w' ? p.width : p.height) = int(v);
  }
  if (j.contains("background")) p.background = parse_color(j["background"], "background", name);
  if (j.contains("polygons")) {
    if (!j["polygons"].is_array()) throw PatternError(name + ": 'polygons' must be an array");
    for (size_t i = 0; i < j["polygons"].size(); ++i) {
      const json& pj = j["polygons"][i];
      const std::string where = "polygons[" + std::to_string(i) + "]";
      if (!pj.is_object()) throw PatternError(name + ": " + where + ": expected an object");
      Polygon poly;
      if (!pj.contains("color")) throw PatternError(name + ": " + where + ": missing 'color'");
      poly.color = parse_color(pj["color"], where + ".color", name);
      if (!pj.contains("points") || !pj["points"].is_array() || pj["points"].size() < 3)
        throw PatternError(name + ": " + where + ".points: expected at least 3 [x,y] points");
      for (size_t k = 0; k < pj["points"].size(); ++k) {
        const json& q = pj["points"][k];
        const std::string at = where + ".points[" + std::to_string(k) + "]";
        if (!q.is_array() || q.size() != 2 || !q[0].is_number() || !q[1].is_number())
          throw PatternError(name + ": " + at + ": expected [x,y] numbers");
        const double x = q[0].get<double>(), y = q[1].get<double>();
        if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > 1e7 || std::abs(y) > 1e7)
          throw PatternError(name + ": " + at + ": coordinates must be finite and within 1e7");
        poly.points.push_back({x, y});
      }
      p.polygons.push_back(std::move(poly));
    }
  }
  return p;
}

Pattern load_pattern(const std::string& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw PatternError(file + ": is a folder, not a pattern file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw PatternError(file + ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_pattern(text.str(), file);
}

std::vector<Segment> pattern_edges(const Pattern& pattern) {
  std::vector<Segment> edges;
  for (const Polygon& p : pattern.polygons)
    for (size_t i = 0; i < p.points.size(); ++i) {
      const auto& a = p.points[i];
      const auto& b = p.points[(i + 1) % p.points.size()];
      if (a != b) edges.push_back({a[0], a[1], b[0], b[1]});
    }
  return edges;
}

std::array<float, 3> pattern_color(const Pattern& pattern, double x, double y) {
  for (size_t i = pattern.polygons.size(); i-- > 0;)
    if (inside_polygon(pattern.polygons[i], x, y)) return pattern.polygons[i].color;
  return pattern.background;
}

int64_t sample_pattern(const Pattern& pattern, double density, uint64_t seed, EpiImage& epi) {
  int64_t count = 0;
  for (int y = 0; y < epi.height; ++y)
    for (int x = 0; x < epi.width; ++x) {
      uint64_t state = mix(seed ^ mix(uint64_t(y) * 0x100000001b3ull + uint64_t(x)));
      if (uniform(state) >= density) {
        epi.clear_sample(x, y);
        continue;
      }
      const double fx = uniform(state), fy = uniform(state);
      const std::array<float, 3> c = pattern_color(pattern, x + fx, y + fy);
      epi.set_sample(x, y, fx, fy, c.data(), 0);
      ++count;
    }
  return count;
}

std::vector<uint8_t> edge_pixels(const Pattern& pattern) {
  BoundaryMasks masks(pattern.width, pattern.height, false);
  const std::vector<Segment> edges = pattern_edges(pattern);
  rasterize_edges(masks, edges);
  std::vector<uint8_t> touched(size_t(pattern.width) * size_t(pattern.height), 0);
  for (int y = 0; y < pattern.height; ++y)
    for (int x = 0; x < pattern.width; ++x) {
      uint8_t sides[4];
      masks.pixel_sides(x, y, sides);
      touched[size_t(y) * size_t(pattern.width) + size_t(x)] = (sides[0] | sides[1] | sides[2] | sides[3]) != 0;
    }
  for (const Segment& s : edges)
    for (const auto& [px, py] : {std::pair{s.x0, s.y0}, std::pair{s.x1, s.y1}}) {
      const double fx = std::floor(px), fy = std::floor(py);
      if (fx >= 0 && fy >= 0 && fx < pattern.width && fy < pattern.height)
        touched[size_t(fy) * size_t(pattern.width) + size_t(fx)] = 1;
    }
  return touched;
}

RgbImage exact_image(const Pattern& pattern, int n) {
  RgbImage image(pattern.width, pattern.height);
  const std::vector<uint8_t> touched = edge_pixels(pattern);
  for (int y = 0; y < pattern.height; ++y)
    for (int x = 0; x < pattern.width; ++x) {
      float* out = image.at(x, y);
      if (!touched[size_t(y) * size_t(pattern.width) + size_t(x)]) {
        const auto c = pattern_color(pattern, x + 0.5, y + 0.5);
        out[0] = c[0], out[1] = c[1], out[2] = c[2];
        continue;
      }
      double sum[3] = {0, 0, 0};
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const auto c = pattern_color(pattern, x + (i + 0.5) / n, y + (j + 0.5) / n);
          for (int k = 0; k < 3; ++k) sum[k] += c[k];
        }
      for (int k = 0; k < 3; ++k) out[k] = float(sum[k] / (n * n));
    }
  return image;
}

}  // namespace epi

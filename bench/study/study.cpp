#include "study.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "image_io.h"

namespace epi::study {
namespace {

// Bump when the reference renderer (render_image, the shader) changes what it produces.
constexpr int kReferenceVersion = 1;

std::string exact(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", v);
  return buf;
}

std::string vec(const glm::vec3& v) { return exact(v.x) + " " + exact(v.y) + " " + exact(v.z); }

std::string number(double v) {
  if (!std::isfinite(v)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string join(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t k = 0; k < fields.size(); ++k) line += (k ? "," : "") + fields[k];
  return line;
}

}  // namespace

uint64_t fnv1a(std::string_view bytes, uint64_t seed) {
  uint64_t h = seed;
  for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

uint64_t file_hash(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot be read");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return fnv1a(bytes.str());
}

std::string key_text(const ReferenceKey& k) {
  const ShaderSettings& s = k.shader;
  std::ostringstream t;
  t << "epi study reference v" << kReferenceVersion << "\n"
    << "scene " << std::hex << k.scene_hash << std::dec << " subdiv " << k.subdiv_level << "\n"
    << "camera eye " << vec(k.camera.eye) << " target " << vec(k.camera.target) << " up " << vec(k.camera.up)
    << " yfov " << exact(k.camera.yfov_degrees) << " znear " << exact(k.camera.znear) << "\n"
    << "shader kind " << int(s.kind) << " area " << s.area_light_samples << " glossy " << s.glossy_samples << " "
    << s.glossy_light_samples << " gi " << s.gi_paths << " " << s.gi_light_samples << " " << s.gi_max_bounces << " "
    << s.gi_roulette_bounce << " " << exact(s.gi_path_clamp) << " specular " << s.specular << " seed " << s.seed
    << " offset " << exact(s.ray_offset) << "\n"
    << "size " << k.width << "x" << k.height << " spp " << k.spp << "\n";
  return t.str();
}

std::filesystem::path reference_file(const std::filesystem::path& dir, const std::string& label, const ReferenceKey& key) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a(key_text(key))));
  return dir / (label + "_" + hex + ".exr");
}

RgbImage cached_reference(const std::filesystem::path& dir, const std::string& label, const ReferenceKey& key,
                          const std::function<RgbImage()>& render, bool* rendered) {
  const std::filesystem::path file = reference_file(dir, label, key);
  if (std::filesystem::exists(file)) {
    try {
      RgbImage image = read_image(file);
      if (image.width == key.width && image.height == key.height) {
        if (rendered) *rendered = false;
        return image;
      }
    } catch (const std::exception&) {
      // unreadable (a truncated file from another tool): rendered again below
    }
  }
  RgbImage image = render();
  std::filesystem::create_directories(dir);
  write_image(file, image);
  if (rendered) *rendered = true;
  return image;
}

std::vector<bool> pareto_front(std::span<const double> time, std::span<const double> error) {
  if (time.size() != error.size()) throw std::invalid_argument("pareto_front: time and error differ in length");
  const size_t n = time.size();
  std::vector<bool> front(n, false);
  auto finite = [&](size_t i) { return std::isfinite(time[i]) && std::isfinite(error[i]); };
  for (size_t i = 0; i < n; ++i) {
    if (!finite(i)) continue;
    bool dominated = false;
    for (size_t j = 0; j < n && !dominated; ++j)
      dominated = j != i && finite(j) && time[j] <= time[i] && error[j] <= error[i] &&
                  (time[j] < time[i] || error[j] < error[i]);
    front[i] = !dominated;
  }
  return front;
}

const std::vector<std::string>& summary_columns() {
  static const std::vector<std::string> c = {"scene", "camera", "knob", "setting", "width", "height", "is_default", "frames", "evaluated",
                                             "ms", "ms_no_shade", "cpu_ms", "rmse", "relative_mse", "over_0_1", "over_0_2",
                                             "rmse_last", "pareto_knob", "pareto_all"};
  return c;
}

const std::vector<std::string>& frame_columns() {
  static const std::vector<std::string> c = {"scene", "camera", "knob", "setting", "frame", "ms", "ms_no_shade",
                                             "cpu_ms", "evaluated", "rmse", "relative_mse", "over_0_1", "over_0_2"};
  return c;
}

std::string csv_header(const std::vector<std::string>& columns) { return join(columns); }

std::string csv_line(const SummaryRow& r) {
  return join({text(r.scene), text(r.camera), text(r.knob), text(r.setting), std::to_string(r.width),
               std::to_string(r.height), r.is_default ? "1" : "0",
               std::to_string(r.frames), std::to_string(r.evaluated), number(r.ms), number(r.ms_no_shade), number(r.cpu_ms), number(r.rmse),
               number(r.relative_mse), number(r.over_0_1), number(r.over_0_2), number(r.rmse_last),
               r.pareto_knob ? "1" : "0", r.pareto_all ? "1" : "0"});
}

std::string csv_line(const FrameRow& r) {
  return join({text(r.scene), text(r.camera), text(r.knob), text(r.setting), std::to_string(r.frame), number(r.ms),
               number(r.ms_no_shade), number(r.cpu_ms), r.evaluated ? "1" : "0", number(r.rmse), number(r.relative_mse),
               number(r.over_0_1), number(r.over_0_2)});
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quoted) {
      if (c == '"' && k + 1 < line.size() && line[k + 1] == '"') fields.back() += '"', ++k;
      else if (c == '"') quoted = false;
      else fields.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

void mark_pareto(std::vector<SummaryRow>& rows) {
  std::map<std::tuple<std::string, std::string, int, int>, std::vector<size_t>> groups;  // (scene, camera, size) -> rows
  for (size_t i = 0; i < rows.size(); ++i)
    groups[{rows[i].scene, rows[i].camera, rows[i].width, rows[i].height}].push_back(i);
  auto front_of = [&](const std::vector<size_t>& members) {
    std::vector<double> t, e;
    for (size_t i : members) t.push_back(rows[i].cpu_ms), e.push_back(rows[i].rmse);
    return pareto_front(t, e);
  };
  for (const auto& [key, members] : groups) {
    const std::vector<bool> all = front_of(members);
    std::map<std::string, std::vector<size_t>> knobs;
    const SummaryRow* default_row = nullptr;
    size_t default_index = 0;
    for (size_t m = 0; m < members.size(); ++m) {
      SummaryRow& r = rows[members[m]];
      r.pareto_all = all[m], r.pareto_knob = all[m];
      if (r.is_default) default_row = &r, default_index = members[m];
      else if (r.knob != "baseline") knobs[r.knob].push_back(members[m]);
    }
    for (auto& [knob, knob_rows] : knobs) {
      if (default_row) knob_rows.push_back(default_index);
      const std::vector<bool> front = front_of(knob_rows);
      for (size_t m = 0; m < knob_rows.size(); ++m)
        if (knob_rows[m] != default_index || !default_row) rows[knob_rows[m]].pareto_knob = front[m];
    }
  }
}

std::vector<SummaryRow> read_summary(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot be read");
  std::string line;
  if (!std::getline(in, line) || split_csv_line(line) != summary_columns())
    throw std::runtime_error(file.string() + ":1: not the header of a study.csv (" + csv_header(summary_columns()) + ")");
  std::vector<SummaryRow> rows;
  for (int n = 2; std::getline(in, line); ++n) {
    const std::vector<std::string> f = split_csv_line(line);
    const std::string where = file.string() + ":" + std::to_string(n) + ": ";
    if (f.size() != summary_columns().size())
      throw std::runtime_error(where + std::to_string(f.size()) + " fields, expected " + std::to_string(summary_columns().size()));
    auto real = [&](size_t k) {
      if (f[k].empty()) return std::numeric_limits<double>::quiet_NaN();
      size_t used = 0;
      double v = 0;
      try {
        v = std::stod(f[k], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != f[k].size() || used == 0) throw std::runtime_error(where + summary_columns()[k] + " '" + f[k] + "' is not a number");
      return v;
    };
    SummaryRow r;
    r.scene = f[0], r.camera = f[1], r.knob = f[2], r.setting = f[3];
    r.width = int(real(4)), r.height = int(real(5)), r.is_default = f[6] == "1", r.frames = int(real(7));
    r.evaluated = int(real(8)), r.ms = real(9), r.ms_no_shade = real(10), r.cpu_ms = real(11), r.rmse = real(12);
    r.relative_mse = real(13), r.over_0_1 = real(14), r.over_0_2 = real(15), r.rmse_last = real(16);
    r.pareto_knob = f[17] == "1", r.pareto_all = f[18] == "1";
    rows.push_back(r);
  }
  return rows;
}

void write_summary(const std::filesystem::path& file, const std::vector<SummaryRow>& rows) {
  const std::filesystem::path temporary = file.string() + ".tmp";
  {
    std::ofstream out(temporary);
    out << csv_header(summary_columns()) << "\n";
    for (const SummaryRow& row : rows) out << csv_line(row) << "\n";
    if (!out) throw std::runtime_error(temporary.string() + ": cannot be written");
  }
  std::filesystem::rename(temporary, file);
}

}  // namespace epi::study

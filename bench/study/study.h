// The pieces of the speed/accuracy study (bench/study/epi_study.cpp, docs/tradeoff.md) that can be
// wrong in ways a test can see: the key of a cached reference image, the Pareto front, and the
// CSV the plots read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "image/image.h"
#include "scene/scene.h"
#include "shade/shader.h"

namespace epi::study {

// Everything a converged reference image depends on. scene_hash is the hash of the scene file's
// bytes (file_hash), so editing the scene renders new references.
struct ReferenceKey {
  uint64_t scene_hash = 0;
  int subdiv_level = -1;  // LoadOptions::subdiv_level_override the scene was loaded with
  Camera camera;
  ShaderSettings shader;
  int width = 0, height = 0;
  int spp = 0;
};

uint64_t fnv1a(std::string_view bytes, uint64_t seed = 0xcbf29ce484222325ull);
// The hash of a file's bytes; throws std::runtime_error naming the file if it cannot be read.
uint64_t file_hash(const std::filesystem::path& file);
// The canonical text of a key: every field, floats written exactly (hex floats), a version tag
// that is bumped when the reference renderer changes.
std::string key_text(const ReferenceKey& key);
// The cache file: <dir>/<label>_<16 hex digits of fnv1a(key_text)>.exr (label: scene and camera,
// for people browsing the folder).
std::filesystem::path reference_file(const std::filesystem::path& dir, const std::string& label, const ReferenceKey& key);

// The reference of `key`: read from its cache file when that exists and has the key's size;
// otherwise render() is called and its image written there (atomically). `rendered` (optional)
// tells which happened.
RgbImage cached_reference(const std::filesystem::path& dir, const std::string& label, const ReferenceKey& key,
                          const std::function<RgbImage()>& render, bool* rendered = nullptr);

// Indices of the points on the Pareto front of (time, error), both to be minimised: no other point
// is at most as slow and at most as wrong and better in one of the two. Points with a non-finite
// coordinate are never on the front and dominate nothing. Equal points are all on the front.
std::vector<bool> pareto_front(std::span<const double> time, std::span<const double> error);

// One row of the summary CSV (study.csv): a knob setting on one scene and camera.
struct SummaryRow {
  std::string scene, camera, knob, setting;  // camera: "path" or "still"
  int width = 0, height = 0;                 // image size
  bool is_default = false;                   // the default settings (knob "default")
  int frames = 0;                            // frames rendered
  int evaluated = 0;                         // of which compared with a reference
  double ms = 0, ms_no_shade = 0;            // median frame time, ms; without shading (NaN: not separable)
  double cpu_ms = 0;                         // median process CPU time per frame, all threads (load-robust)
  double rmse = 0, relative_mse = 0, over_0_1 = 0, over_0_2 = 0;  // means over the evaluated frames
  double rmse_last = 0;                      // the last evaluated frame's display RMSE
  // On the front of this knob's settings and the default (scene, camera and size fixed); for the default
  // and the baselines (knob "baseline"): the same as pareto_all.
  bool pareto_knob = false;
  bool pareto_all = false;  // on the front of every row of this scene, camera and size
};

// One row of the per-frame CSV (study_frames.csv).
struct FrameRow {
  std::string scene, camera, knob, setting;
  int frame = 0;
  double ms = 0, ms_no_shade = 0, cpu_ms = 0;
  bool evaluated = false;
  double rmse = 0, relative_mse = 0, over_0_1 = 0, over_0_2 = 0;  // NaN when not evaluated
};

// The column names, in order (the schema plot_study.py reads; docs/tradeoff.md lists them).
const std::vector<std::string>& summary_columns();
const std::vector<std::string>& frame_columns();
// A line of each (no newline); text fields are quoted when they hold a comma or a quote.
std::string csv_line(const SummaryRow& row);
std::string csv_line(const FrameRow& row);
std::string csv_header(const std::vector<std::string>& columns);
// Splits one CSV line as csv_line writes it (quoted fields, doubled quotes); for the tests.
std::vector<std::string> split_csv_line(const std::string& line);

// Sets pareto_knob and pareto_all on every row (groups as documented on SummaryRow; time: cpu_ms,
// the work a frame costs, which the load of a shared machine moves far less than wall time;
// error: rmse).
void mark_pareto(std::vector<SummaryRow>& rows);

// Reads a study.csv as csv_line wrote it (the header must be summary_columns()); throws
// std::runtime_error naming the file and line otherwise. Empty cells read as NaN.
std::vector<SummaryRow> read_summary(const std::filesystem::path& file);
// Writes rows with the header, atomically (a temporary file renamed into place).
void write_summary(const std::filesystem::path& file, const std::vector<SummaryRow>& rows);

}  // namespace epi::study

// Small pieces the subcommands share: a progress bar for terminals, output-path checks, and
// staged output (every file written beside its target first, moved into place only when all
// of a command's outputs are complete, so a failure leaves nothing behind).
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "image_compare.h"

namespace epi {
struct Scene;
}

namespace epi::cli {

// A progress bar on stderr, drawn only when stderr is a terminal, not quiet, and the work has
// taken more than a second. update() is cheap and may be called from any one thread at a time.
class ProgressBar {
 public:
  ProgressBar(std::string label, bool quiet);
  ~ProgressBar();
  void update(double fraction);
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  int last_percent_ = -1;
  std::chrono::steady_clock::time_point start_;
};

// Throws std::runtime_error("<file>: <problem>") unless `file` can be written: its folder
// exists and is writable, and the file is not a folder (nor an existing read-only file).
// Call for every output before long work starts.
void check_output_file(const std::filesystem::path& file);
// Throws "<file>: given for two outputs" if two of the non-empty paths name the same file.
void check_distinct_outputs(const std::vector<std::string>& files);
// Throws "<file>: names an input" if one of the non-empty outputs is the file `input`.
void check_not_input(const std::vector<std::string>& outputs, const std::string& input);
// The same, plus a supported image extension (io/image).
void check_output_image(const std::filesystem::path& file);

// A command's outputs. Each add_* writes a temporary file beside its target at once (throws
// "<file>: <problem>" on failure); commit() moves them all into place. Destroyed without
// commit() (an exception on the way), it removes every temporary file: nothing is left.
class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  ~StagedOutputs();

  void add_text(const std::filesystem::path& file, const std::string& text);
  void add_json(const std::filesystem::path& file, const nlohmann::json& json);
  void add_image(const std::filesystem::path& file, const RgbImage& image, float exposure = 0.0f);
  void commit();

 private:
  std::filesystem::path temporary_for(const std::filesystem::path& file);
  struct Staged {
    std::filesystem::path temporary, target;
  };
  std::vector<Staged> staged_;
};

// A reference image for `compare` and `render --reference`: read (or refused with
// "<file>: <problem>": missing, unreadable, or, when width > 0, not width x height) before work.
struct ReferenceImage {
  std::string file;
  RgbImage image;
  ImageEncoding encoding = ImageEncoding::linear;
};
ReferenceImage read_reference(const std::string& file, int width = 0, int height = 0);
// The metrics (io/image/image_compare.h) on one line, and as JSON.
std::string difference_line(const ImageDifference& d);
nlohmann::json difference_json(const ImageDifference& d);

// One line on stderr with the repairs made while loading (degenerate triangles dropped, zero
// normals replaced), unless quiet or there were none.
void report_repairs(const Scene& scene, bool quiet);

}  // namespace epi::cli

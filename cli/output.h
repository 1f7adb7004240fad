// Small pieces the subcommands share: a progress bar for terminals, and atomic file output.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

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

// Writes text to `file` through a temporary file beside it, renamed when complete.
// Throws std::runtime_error("<file>: <problem>").
void write_text_atomically(const std::filesystem::path& file, const std::string& text);
void write_json(const std::filesystem::path& file, const nlohmann::json& json);

// Throws if `file`'s folder does not exist (checked before long work starts).
void check_output_folder(const std::filesystem::path& file);

}  // namespace epi::cli

#include "output.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

#include "image_io.h"
#include "scene/scene.h"

namespace epi::cli {

namespace fs = std::filesystem;

ProgressBar::ProgressBar(std::string label, bool quiet)
    : label_(std::move(label)), enabled_(!quiet && ::isatty(STDERR_FILENO)), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(double fraction) {
  if (!enabled_) return;
  const int percent = int(fraction * 100.0);
  if (percent == last_percent_) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (seconds < 1.0) return;
  last_percent_ = percent;
  constexpr int kWidth = 40;
  const int filled = std::min(kWidth, std::max(0, int(fraction * kWidth)));
  std::fprintf(stderr, "\r%s [%s%s] %3d%% %.1fs", label_.c_str(), std::string(size_t(filled), '#').c_str(),
               std::string(size_t(kWidth - filled), ' ').c_str(), percent, seconds);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (drawn_) std::fprintf(stderr, "\r\033[K");
  drawn_ = false;
  enabled_ = false;
}

void check_output_file(const fs::path& file) {
  if (file.empty()) throw std::runtime_error("empty output file name");
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error(file.string() + ": output folder '" + folder.string() + "' does not exist");
  if (fs::is_directory(file, ec)) throw std::runtime_error(file.string() + ": is a folder, not a file");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw std::runtime_error(file.string() + ": output folder '" + folder.string() + "' is not writable");
  if (fs::exists(file, ec) && ::access(file.c_str(), W_OK) != 0)
    throw std::runtime_error(file.string() + ": exists and is not writable");
  // access() says yes to root everywhere, and to folders (/proc, read-only mounts) where no file
  // can be made: create and remove a probe file, as the staged output will later.
  const fs::path probe = folder / (".tmp-" + std::to_string(::getpid()) + "-probe");
  if (!std::ofstream(probe, std::ios::binary))
    throw std::runtime_error(file.string() + ": cannot create a file in folder '" + folder.string() + "'");
  fs::remove(probe, ec);
}

void check_distinct_outputs(const std::vector<std::string>& files) {
  std::vector<fs::path> seen;
  for (const std::string& file : files) {
    if (file.empty()) continue;
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(fs::absolute(file), ec);
    if (std::find(seen.begin(), seen.end(), canonical) != seen.end())
      throw std::runtime_error(file + ": given for two outputs");
    seen.push_back(canonical);
  }
}

void check_output_image(const fs::path& file) {
  check_output_file(file);
  check_output_path(file);  // the extension
}

void check_not_input(const std::vector<std::string>& outputs, const std::string& input) {
  if (input.empty()) return;
  std::error_code ec;
  const fs::path in = fs::weakly_canonical(input, ec);
  for (const std::string& output : outputs)
    if (!output.empty() && fs::weakly_canonical(output, ec) == in) throw std::runtime_error(output + ": names an input");
}

ReferenceImage read_reference(const std::string& file, int width, int height) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw std::runtime_error(file + ": no such file");
  if (fs::is_directory(file, ec)) throw std::runtime_error(file + ": is a folder");
  ReferenceImage reference{file, read_image(file), encoding_of_file(file)};
  if (width > 0 && (reference.image.width != width || reference.image.height != height))
    throw std::runtime_error(file + ": the reference is " + std::to_string(reference.image.width) + "x" +
                             std::to_string(reference.image.height) + ", the image " + std::to_string(width) + "x" +
                             std::to_string(height));
  return reference;
}

std::string difference_line(const ImageDifference& d) {
  char text[256];
  std::snprintf(text, sizeof text,
                "display RMSE %.4f | relative MSE %.5f | pixels off by > 0.1: %.2f %%, by > 0.2: %.2f %% | max %.3f",
                d.display_rmse, d.relative_mse, 100.0 * d.over_0_1, 100.0 * d.over_0_2, d.max_display_error);
  return text;
}

nlohmann::json difference_json(const ImageDifference& d) {
  return {{"width", d.width},
          {"height", d.height},
          {"display_rmse", d.display_rmse},
          {"relative_mse", d.relative_mse},
          {"over_0_1", d.over_0_1},
          {"over_0_2", d.over_0_2},
          {"max_display_error", d.max_display_error}};
}

StagedOutputs::~StagedOutputs() {
  for (const Staged& s : staged_) {
    std::error_code ec;
    fs::remove(s.temporary, ec);
  }
}

fs::path StagedOutputs::temporary_for(const fs::path& file) {
  check_output_file(file);
  // Hidden, unique per process and output, and keeping the extension (the image writer picks
  // its format from it).
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  return folder / (".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(staged_.size()) + "-" +
                   file.filename().string());
}

void StagedOutputs::add_text(const fs::path& file, const std::string& text) {
  const fs::path temporary = temporary_for(file);
  staged_.push_back({temporary, file});
  std::ofstream out(temporary, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw std::runtime_error(file.string() + ": could not write");
}

void StagedOutputs::add_json(const fs::path& file, const nlohmann::json& json) {
  add_text(file, json.dump(2) + "\n");
}

void StagedOutputs::add_image(const fs::path& file, const RgbImage& image, float exposure) {
  check_output_path(file);
  const fs::path temporary = temporary_for(file);
  staged_.push_back({temporary, file});
  try {
    ImageWriteOptions options;
    options.exposure = exposure;
    write_image(temporary, image, options);
  } catch (const ImageIOError&) {
    throw std::runtime_error(file.string() + ": could not write the image");
  }
}

void StagedOutputs::commit() {
  for (size_t i = 0; i < staged_.size(); ++i) {
    std::error_code ec;
    fs::rename(staged_[i].temporary, staged_[i].target, ec);
    if (ec) {
      // All or nothing: remove the outputs already moved into place; the destructor drops the rest.
      const std::string message = staged_[i].target.string() + ": could not move the finished file into place: " + ec.message();
      for (size_t k = 0; k < i; ++k) fs::remove(staged_[k].target, ec);
      staged_.erase(staged_.begin(), staged_.begin() + std::ptrdiff_t(i));
      throw std::runtime_error(message);
    }
  }
  staged_.clear();
}

void report_repairs(const Scene& scene, bool quiet) {
  if (quiet || scene.repairs.empty()) return;
  constexpr size_t kShown = 3;
  std::string line;
  for (size_t i = 0; i < std::min(kShown, scene.repairs.size()); ++i) line += (i ? "; " : "") + scene.repairs[i];
  if (scene.repairs.size() > kShown)
    line += "; and " + std::to_string(scene.repairs.size() - kShown) + " more (epi info lists them)";
  std::fprintf(stderr, "epi: %s: repaired while loading: %s\n", scene.source.c_str(), line.c_str());
}

}  // namespace epi::cli

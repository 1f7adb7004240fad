#include "output.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

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

void check_output_folder(const fs::path& file) {
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error(file.string() + ": output folder '" + folder.string() + "' does not exist");
}

void write_text_atomically(const fs::path& file, const std::string& text) {
  check_output_folder(file);
  const fs::path temporary = file.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" + file.filename().string());
  {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(temporary, ec);
      throw std::runtime_error(file.string() + ": could not write");
    }
  }
  std::error_code ec;
  fs::rename(temporary, file, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw std::runtime_error(file.string() + ": could not move the finished file into place");
  }
}

void write_json(const fs::path& file, const nlohmann::json& json) { write_text_atomically(file, json.dump(2) + "\n"); }

}  // namespace epi::cli

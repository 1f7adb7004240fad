// The loaders read files: each fuzz input is written to one scratch file per process (in
// /dev/shm when it exists), overwritten by the next input and removed at exit.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace epi::fuzz {

class ScratchFile {
 public:
  ScratchFile(const std::string& extension, const uint8_t* data, size_t size) {
    std::error_code ec;
    const std::filesystem::path folder = std::filesystem::is_directory("/dev/shm", ec) ? "/dev/shm" : std::filesystem::temp_directory_path();
    path_ = folder / ("epi-fuzz-" + std::to_string(::getpid()) + "." + extension);
    std::ofstream(path_, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  ~ScratchFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace epi::fuzz

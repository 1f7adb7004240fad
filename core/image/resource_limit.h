// Resource limits, checked before the work: an estimate of the bytes a request will take, made
// from the input's own numbers (subdivision level and cage faces, pattern size, image size), is
// refused with one line naming what asked, the estimate and the limit. docs/reliability.md
// lists the estimates and how they were measured.
#pragma once

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace epi {

// The default: well inside a 24 GiB machine shared by a few programs. `--memory-limit GIB` raises it.
inline constexpr uint64_t kDefaultMemoryLimit = uint64_t(4) << 30;

// what(): "<what>: <request> needs about <estimate> (limit <limit>; --memory-limit raises it)".
struct ResourceLimitError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline std::string format_memory(double bytes) {
  char text[32];
  if (bytes >= double(uint64_t(1) << 30)) std::snprintf(text, sizeof text, "%.2f GiB", bytes / double(uint64_t(1) << 30));
  else std::snprintf(text, sizeof text, "%.1f MiB", bytes / double(1 << 20));
  return text;
}

// Throws ResourceLimitError when `estimate_bytes` exceeds `limit_bytes`. `where` names the file
// (and the part of it) that asked; `request` says what it asked for.
inline void check_memory_estimate(const std::string& where, const std::string& request, double estimate_bytes,
                                  uint64_t limit_bytes) {
  if (!(estimate_bytes <= double(limit_bytes)))
    throw ResourceLimitError(where + ": " + request + " needs about " + format_memory(estimate_bytes) + " (limit " +
                             format_memory(double(limit_bytes)) + "; --memory-limit GIB raises it)");
}

}  // namespace epi

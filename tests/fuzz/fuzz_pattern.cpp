// libFuzzer target: the pattern parser of the 2D harness (core/epi), then, for patterns small
// enough, the whole 2D pipeline on what it parsed: edges, rasterization, sampling and the EPI
// reconstruction. Any outcome but a result or a PatternError is a finding. docs/reliability.md.
#include <cstddef>
#include <cstdint>
#include <string>

#include "epi/pattern.h"
#include "epi/reconstruct.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  epi::Pattern pattern;
  try {
    pattern = epi::parse_pattern(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
  } catch (const epi::PatternError&) {
    return 0;
  }
  if (pattern.width * pattern.height > 64 * 64) return 0;  // the parser is the target; keep runs fast
  epi::BoundaryMasks masks(pattern.width, pattern.height, true);
  epi::rasterize_edges(masks, epi::pattern_edges(pattern));
  epi::EpiImage epi(pattern.width, pattern.height);
  epi::sample_pattern(pattern, 0.2, 1, epi);
  epi::Schedule schedule;
  schedule.threads = 1;
  epi::reconstruct_tiled(epi, masks, epi::ReconstructSettings{}, schedule);
  return 0;
}

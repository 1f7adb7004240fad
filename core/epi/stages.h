// The reconstruction's stages, declared once: name, the planes each reads and how many rows
// around its own it reads of each (its footprint), and the plane it writes. The lag of each
// stage behind classification, the rows a band must compute and the ring sizes of the tiled
// schedule all follow from this table; the schedules (reconstruct.h), the timings, the CLI's
// series and the benches iterate it. docs/epi.md, "Stages and schedules".
#pragma once

#include <array>
#include <cstddef>

namespace epi {

// The rows the stages pass on to each other (one row per image row).
enum class Plane : int {
  edge,    // classified edge words (uint16: code, usable bit, sample bits)
  types,   // pixel types (uint8)
  samples, // decoded for the row kernels: linear colour planes, usable and sampled flags, side words
  reach,   // 24-bit reach masks (uint32)
  interp,  // interpolated primary colours (3 floats) and found flags (uint8)
  filled,  // primary colours after the fill step (3 floats)
  image,   // the output row (3 floats): anti-aliasing writes it, the complex filter overwrites complex pixels
  count,
};
constexpr int kPlaneCount = int(Plane::count);

enum class Stage : int { classify, decode, reachability, interpolate, fill, antialias, complex, count };
constexpr int kStageCount = int(Stage::count);

struct StageInput {
  Plane plane;
  int radius;  // rows read above and below the stage's own row
};

struct StageInfo {
  Stage stage;
  const char* name;         // as timed (ReconstructTimes) and reported
  const char* file;         // where its per-pixel oracle lives (core/epi)
  const char* footprint;    // in pixels, for the docs and the CLI
  Plane output;
  std::array<StageInput, 4> inputs;
  int input_count;
};

// In order: a stage reads only planes written by stages before it (the complex filter also
// reads the image row anti-aliasing wrote, radius 0). Classification reads the input EPI and
// the boundary masks, which are not planes.
inline constexpr std::array<StageInfo, kStageCount> kStages = {{
    {Stage::classify, "classify", "classify.cpp", "1x1", Plane::edge, {}, 0},
    // Colours to linear planes once per row, for the vector kernels (nothing for the oracle).
    {Stage::decode, "decode", "reconstruct.cpp", "1x1", Plane::samples, {{{Plane::edge, 0}, {Plane::types, 0}}}, 2},
    {Stage::reachability, "reachability", "reachability.cpp", "5x5", Plane::reach,
     {{{Plane::types, 2}, {Plane::samples, 2}}}, 2},
    // 7x7 types, edge words and decoded samples for the fallback (reach_window7, the whole-window
    // mean's kernel), the own reach mask.
    {Stage::interpolate, "interpolate", "interpolate.cpp", "5x5 (7x7 fallback)", Plane::interp,
     {{{Plane::types, 3}, {Plane::edge, 3}, {Plane::reach, 0}, {Plane::samples, 3}}}, 4},
    {Stage::fill, "fill", "fill.cpp", "5x5", Plane::filled, {{{Plane::interp, 2}, {Plane::reach, 0}}}, 2},
    {Stage::antialias, "antialias", "antialias.cpp", "3x3", Plane::image,
     {{{Plane::filled, 1}, {Plane::types, 0}, {Plane::edge, 0}}}, 3},
    {Stage::complex, "complex", "complex_filter.cpp", "3x3 (6x6 sub-pixels)", Plane::image,
     {{{Plane::filled, 0}, {Plane::edge, 1}, {Plane::image, 0}}}, 3},
}};

constexpr const StageInfo& stage_info(Stage s) { return kStages[size_t(s)]; }

// The stage that writes a plane (the first, for the image: anti-aliasing).
constexpr Stage producer(Plane p) {
  if (p == Plane::types) return Stage::classify;
  for (const StageInfo& s : kStages)
    if (s.output == p) return s.stage;
  return Stage::count;
}

// How many rows a stage's output row lags the classified row in a row stream: enough that
// every row it reads was produced earlier in the same pass.
constexpr std::array<int, kStageCount> kStageLags = [] {
  std::array<int, kStageCount> lag{};
  for (const StageInfo& s : kStages) {
    int l = 0;
    for (int i = 0; i < s.input_count; ++i) {
      const int from = lag[size_t(producer(s.inputs[size_t(i)].plane))] + s.inputs[size_t(i)].radius;
      l = from > l ? from : l;
    }
    lag[size_t(s.stage)] = l;
  }
  return lag;
}();
constexpr int stage_lag(Stage s) { return kStageLags[size_t(s)]; }
constexpr int kMaxLag = [] {
  int m = 0;
  for (int l : kStageLags) m = l > m ? l : m;
  return m;
}();

// Rows of a plane live at once in a row stream: from the newest (its producer's row) back to
// the oldest any reader still needs, rounded up to a power of two (rings indexed row & (size - 1)).
// The reach plane also keeps the two rows above its newest (the symmetry reuse reads them).
constexpr int ring_rows(Plane p) {
  const int newest = stage_lag(producer(p));
  int oldest = newest + (p == Plane::reach ? 2 : 0);
  for (const StageInfo& s : kStages)
    for (int i = 0; i < s.input_count; ++i)
      if (s.inputs[size_t(i)].plane == p) {
        const int o = stage_lag(s.stage) + s.inputs[size_t(i)].radius;
        oldest = o > oldest ? o : oldest;
      }
  int size = 1;
  while (size < oldest - newest + 1) size *= 2;
  return size;
}
// Edge words and types share one ring (EpiRows indexes both with one mask).
constexpr int kClassRingRows = ring_rows(Plane::edge) > ring_rows(Plane::types) ? ring_rows(Plane::edge)
                                                                                  : ring_rows(Plane::types);

// The timing series the CLI, the stats JSON and the paper's table 2 report: the stages, with
// the fill step counted in "interpolate" (its series predates the fill step) and decoding in
// "classify".
constexpr Stage reported_as(Stage s) {
  return s == Stage::fill ? Stage::interpolate : s == Stage::decode ? Stage::classify : s;
}
constexpr bool is_reported(Stage s) { return reported_as(s) == s; }

}  // namespace epi

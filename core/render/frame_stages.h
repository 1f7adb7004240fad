// The frame's stages, declared once (the paper's table 2): the renderer's StageTimes, the CLI's
// `stages_ms`, render_bench's counters, bench/perf_tables.py and the viewer's time graph iterate
// this table. The reconstruction's stages are its reported series (core/epi/stages.h).
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

#include "epi/stages.h"

namespace epi::render {

enum class FrameStage : int {
  find_edges,       // the edge finder (core/edges): silhouettes, sharp, borders, shadow edges
  rasterize_edges,  // depth filter, projection, clipping, occlusion culling, rasterization
  points,           // insert, project, depth cull, occlusion test, fill the EPI
  classify,         // the reconstruction's reported series (epi::reported_as) ...
  reachability,
  interpolate,      // ... interpolate includes the hole fill
  antialias,
  complex,
  sparse_blend,     // sparse regions smoothed (sparse_blend.h), after the reconstruction
  sampling,         // choose the next requests: predictive occupancy, dither, submit
  shade,            // sync mode only: shading this frame's budget (inside the total, not a loop stage)
  count,
};
constexpr int kFrameStageCount = int(FrameStage::count);

struct FrameStageInfo {
  FrameStage stage;
  const char* name;   // the stats JSON key (`stages_ms`) and render_bench's counter (name + "_ms")
  const char* label;  // short, for the viewer's legend and the tables' headers
  bool loop;          // part of the frame loop's own time (false: shading, excluded as in the paper)
};

inline constexpr std::array<FrameStageInfo, kFrameStageCount> kFrameStages = {{
    {FrameStage::find_edges, "find_edges", "find edges", true},
    {FrameStage::rasterize_edges, "rasterize_edges", "raster", true},
    {FrameStage::points, "points", "points", true},
    {FrameStage::classify, "classify", "classify", true},
    {FrameStage::reachability, "reachability", "reach", true},
    {FrameStage::interpolate, "interpolate", "interp", true},
    {FrameStage::antialias, "antialias", "AA", true},
    {FrameStage::complex, "complex", "complex", true},
    {FrameStage::sparse_blend, "sparse_blend", "sparse", true},
    {FrameStage::sampling, "sampling", "sampling", true},
    {FrameStage::shade, "shade_sync", "shade", false},
}};

constexpr const FrameStageInfo& frame_stage_info(FrameStage s) { return kFrameStages[size_t(s)]; }

// The frame stage of a reconstruction stage's reported series; the reported series of
// core/epi's table are exactly the frame's reconstruction stages, in order, by name.
constexpr FrameStage frame_stage(Stage s) {
  return FrameStage(int(FrameStage::classify) + [s] {
    int k = 0;
    for (const StageInfo& i : kStages) {
      if (i.stage == reported_as(s)) return k;
      k += is_reported(i.stage);
    }
    return k;
  }());
}
static_assert([] {
  for (const StageInfo& i : kStages)
    if (is_reported(i.stage) && std::string_view(frame_stage_info(frame_stage(i.stage)).name) != i.name) return false;
  return frame_stage(Stage::complex) == FrameStage::complex;
}(), "the frame's reconstruction stages must be core/epi's reported series, in order");

// Per-stage wall time of one frame, ms, indexed by FrameStage; total: the whole frame (with
// shading in sync mode); loop_ms(): the total without shading.
struct StageTimes {
  std::array<double, kFrameStageCount> ms{};
  double total = 0;
  double& operator[](FrameStage s) { return ms[size_t(s)]; }
  double operator[](FrameStage s) const { return ms[size_t(s)]; }
  double loop_ms() const { return total - ms[size_t(FrameStage::shade)]; }
};

}  // namespace epi::render

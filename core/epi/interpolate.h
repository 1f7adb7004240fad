// Edge-respecting interpolation of the primary colour, and the sampling priority.
// Footprint: 5x5 samples + the pixel's reachability mask; 7x7 types and samples for the fallback.
// Kernel: w(dx, dy) = 1 / (1 + dx^2 + dy^2)^2 (1, 1/4, 1/9, 1/25, 1/36, 1/81): sharply peaked;
// unreachable pixels and pixels without a usable sample weigh 0 and the rest are renormalized.
// Complex pixels use every sample of the 5x5 (the paper's simple estimate). A pixel that
// reaches no sample takes fallback_color, and the fill step (fill.h) then replaces that with
// reachable neighbours' colours where it can. docs/epi.md, "Interpolation".
#pragma once

#include <cstdint>
#include <vector>

#include "epi/epi_pixel.h"
#include "epi/reachability.h"
#include "epi/rows.h"

namespace epi {

// Priority scale: pixels with a usable sample get age / 16 (at most 255/16); the others get
// 1 / (total weight before renormalization), capped at kMaxReachedPriority; a pixel that
// reaches no sample gets kMaxPriority, strictly above every other case.
constexpr float kMaxPriority = 16.0f;
constexpr float kMaxReachedPriority = 15.0f;
inline float age_priority(int age) { return float(age) * (1.0f / 16.0f); }
inline float weight_priority(float total_weight) {
  return total_weight * kMaxReachedPriority > 1.0f ? 1.0f / total_weight : kMaxReachedPriority;
}

extern const float kInterpolationWeights[25];

// The primary colour of pixel (x, y) into rgb; returns its priority. *found tells whether the
// colour came from reachable samples (complex pixels: from any sample of the 5x5). Reads rows
// y-2..y+2 of `rows`, y-3..y+3 in the fallback (fallback_color, with blend_near_edges).
float interpolate_pixel(const EpiRows& rows, int x, int y, uint32_t reach, float rgb[3], bool* found = nullptr,
                        bool blend_near_edges = true);

// The colour of a pixel that reaches no sample in its 5x5: the kernel-weighted mean of the
// usable samples it reaches in its 7x7 (reach_window7); failing that, where its own 5x5 holds an
// edge (a non-empty type; without blend_near_edges: where the pixel itself is not empty), the
// simple estimate, then the uniform 7x7 average; otherwise black. Colour never crosses an edge
// into a pixel whose 5x5 is edge-free (ReconstructSettings::blend_unreached_near_edges).
void fallback_color(const EpiRows& rows, int x, int y, float rgb[3], bool blend_near_edges = true);

// fallback_color for every pixel x of row y whose found[x] is 0, into rgb + 3 x: the same bits
// (the schedules' interpolation stage, where such pixels come in runs after motion). The 7x7
// windows' hole and edge tests read seven column ORs instead of 49 words, and an edge-free
// window inside the image takes its weighted sum without a branch per sample. `scratch` keeps
// the column ORs' storage (a thread's, between rows).
//
// With `defer_whole_windows` those edge-free windows inside the image are left to the caller's
// vector kernel (simd::WindowMeanRow, the same bits): their pixels are marked 1 in
// scratch.whole_window (0 elsewhere in [span_first, span_end)) and their colours left as
// they were; returns how many were marked. With `defer_reaching` the other pixels that need the
// 7x7 reachability are marked in scratch.reaching likewise (their count in reaching_count): the
// caller writes their masks (reach_window7's) into scratch.reach7 and finishes them with
// fallback_reaching_row.
struct FallbackScratch {
  std::vector<uint16_t> edge_or;  // per column: the edge words of rows y-3..y+3, ORed
  std::vector<uint8_t> type_or;   // per column: their types, ORed
  std::vector<uint8_t> whole_window;  // deferred pixels (defer_whole_windows)
  std::vector<uint8_t> reaching;      // deferred pixels (defer_reaching)
  std::vector<uint64_t> reach7;       // the caller's: their 7x7 masks, pixel x at [x]
  std::vector<uint8_t> reach7_found;  // the caller's: whether their reachable mean found a sample
  std::vector<uint8_t> relations;     // the caller's: storage for its kernel's inputs
  int span_first = 0, span_end = 0;   // the span of the marks written this row
  int reaching_count = 0;
};
int fallback_row(const EpiRows& rows, int y, const uint8_t* found, float* rgb, bool blend_near_edges,
                 FallbackScratch& scratch, bool defer_whole_windows = false, bool defer_reaching = false);
// The colours of the pixels fallback_row marked in scratch.reaching, from their masks in
// scratch.reach7: fallback_color's bits. With `found` (simd::WindowMeanRow's, by masks) the
// reachable means of the pixels from x = 3 on are already in rgb: those with found[x] = 0 only
// take the last resort.
void fallback_reaching_row(const EpiRows& rows, int y, float* rgb, bool blend_near_edges,
                           const FallbackScratch& scratch, const uint8_t* found = nullptr);


// The paper's simple estimate: every sample of the 5x5, same kernel. Returns the total weight.
float simple_estimate(const EpiRows& rows, int x, int y, float rgb[3]);
// Uniform average of the samples in the (2r+1)^2 window. Returns the sample count.
int window_average(const EpiRows& rows, int x, int y, int r, float rgb[3]);

}  // namespace epi

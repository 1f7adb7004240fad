// Edge-respecting interpolation of the primary colour, and the sampling priority.
// Footprint: 5x5 samples + the pixel's reachability mask; 7x7 samples for the last fallback.
// Kernel: w(dx, dy) = 1 / (1 + dx^2 + dy^2)^2 (1, 1/4, 1/9, 1/25, 1/36, 1/81): sharply peaked;
// unreachable pixels and pixels without a usable sample weigh 0 and the rest are renormalized.
// Complex pixels use every sample of the 5x5 (the paper's simple estimate). A pixel that
// reaches no sample falls back to the simple estimate, then to the uniform 7x7 average, and
// the fill step (fill.h) then replaces that with reachable neighbours' colours where it can.
#pragma once

#include <cstdint>

#include "epi/epi_pixel.h"

namespace epi {

// Priority scale: pixels with a sample get age / 16; pixels without one get 1 / (total weight
// before renormalization), capped at kMaxPriority, which is also what nothing reachable gets.
constexpr float kMaxPriority = 16.0f;
inline float age_priority(int age) { return float(age) * (1.0f / 16.0f); }
inline float weight_priority(float total_weight) {
  return total_weight * kMaxPriority > 1.0f ? 1.0f / total_weight : kMaxPriority;
}

extern const float kInterpolationWeights[25];

// The primary colour of pixel (x, y) into rgb; returns its priority. *found tells whether the
// colour came from reachable samples (complex pixels: from any sample of the 5x5).
float interpolate_pixel(const EpiImage& epi, int x, int y, uint32_t reach, float rgb[3], bool* found = nullptr);


// The paper's simple estimate: every sample of the 5x5, same kernel. Returns the total weight.
float simple_estimate(const EpiImage& epi, int x, int y, float rgb[3]);
// Uniform average of the samples in the (2r+1)^2 window. Returns the sample count.
int window_average(const EpiImage& epi, int x, int y, int r, float rgb[3]);

}  // namespace epi

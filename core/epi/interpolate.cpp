#include "epi/interpolate.h"

#include "epi/geometry.h"
#include "epi/reachability.h"

namespace epi {

const float kInterpolationWeights[25] = {
    1.0f / 81, 1.0f / 36, 1.0f / 25, 1.0f / 36, 1.0f / 81,  //
    1.0f / 36, 1.0f / 9,  1.0f / 4,  1.0f / 9,  1.0f / 36,  //
    1.0f / 25, 1.0f / 4,  1.0f,      1.0f / 4,  1.0f / 25,  //
    1.0f / 36, 1.0f / 9,  1.0f / 4,  1.0f / 9,  1.0f / 36,  //
    1.0f / 81, 1.0f / 36, 1.0f / 25, 1.0f / 36, 1.0f / 81};

namespace {

// Weighted sum over the 5x5: pixels in the image, holding a sample that passes `use`.
template <typename Use>
float weighted_sum(const EpiImage& epi, int x, int y, Use use, float rgb[3]) {
  float sum[3] = {0, 0, 0}, total = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int px = x + dx, py = y + dy;
      if (!epi.inside(px, py)) continue;
      const size_t i = epi.index(px, py);
      if (!use(epi.edge[i], dx, dy)) continue;
      const float w = kInterpolationWeights[(dy + 2) * 5 + dx + 2];
      float c[3];
      decode_color(epi.color[i], c);
      sum[0] += w * c[0], sum[1] += w * c[1], sum[2] += w * c[2];
      total += w;
    }
  if (total > 0)
    for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / total;
  return total;
}

}  // namespace

float simple_estimate(const EpiImage& epi, int x, int y, float rgb[3]) {
  return weighted_sum(epi, x, y, [](uint16_t e, int, int) { return has_sample(e); }, rgb);
}

int window_average(const EpiImage& epi, int x, int y, int r, float rgb[3]) {
  float sum[3] = {0, 0, 0};
  int count = 0;
  for (int py = y - r; py <= y + r; ++py)
    for (int px = x - r; px <= x + r; ++px) {
      if (!epi.inside(px, py)) continue;
      const size_t i = epi.index(px, py);
      if (!has_sample(epi.edge[i])) continue;
      float c[3];
      decode_color(epi.color[i], c);
      sum[0] += c[0], sum[1] += c[1], sum[2] += c[2];
      ++count;
    }
  for (int k = 0; k < 3; ++k) rgb[k] = count ? sum[k] / float(count) : 0.0f;
  return count;
}

float interpolate_pixel(const EpiImage& epi, int x, int y, uint32_t reach, float rgb[3]) {
  const size_t centre = epi.index(x, y);
  const bool complex = pixel_type(epi.cache[centre]) == kTypeComplex;
  float total;
  if (complex) {
    total = simple_estimate(epi, x, y, rgb);
  } else {
    total = weighted_sum(
        epi, x, y,
        [reach](uint16_t e, int dx, int dy) {
          return usable_sample(e) && ((dx == 0 && dy == 0) || ((reach >> reach_bit(dx, dy)) & 1));
        },
        rgb);
    if (total == 0 && simple_estimate(epi, x, y, rgb) > 0) return kMaxPriority;
  }
  if (total == 0) {
    window_average(epi, x, y, 3, rgb);
    return kMaxPriority;
  }
  const uint16_t e = epi.edge[centre];
  return usable_sample(e) ? age_priority(sample_age(epi.color[centre])) : weight_priority(total);
}

}  // namespace epi

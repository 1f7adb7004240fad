#include "epi/rendercache.h"

#include "epi/interpolate.h"

namespace epi {

float rendercache_pixel(const EpiImage& epi, int x, int y, float rgb[3]) {
  static constexpr float kWeights[9] = {0.25f, 0.5f, 0.25f, 0.5f, 1.0f, 0.5f, 0.25f, 0.5f, 0.25f};
  float sum[3] = {0, 0, 0}, total = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int px = x + dx, py = y + dy;
      if (!epi.inside(px, py)) continue;
      const size_t i = epi.index(px, py);
      if (!has_sample(epi.edge[i])) continue;
      const float w = kWeights[(dy + 1) * 3 + dx + 1];
      float c[3];
      decode_color(epi.color[i], c);
      sum[0] += w * c[0], sum[1] += w * c[1], sum[2] += w * c[2];
      total += w;
    }
  if (total == 0) {
    window_average(epi, x, y, 3, rgb);
    return kMaxPriority;
  }
  for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / total;
  const uint16_t e = epi.edge[epi.index(x, y)];
  return has_sample(e) ? age_priority(sample_age(epi.color[epi.index(x, y)])) : weight_priority(total);
}

}  // namespace epi

#include "epi/rendercache.h"

#include <algorithm>

#include "epi/interpolate.h"

namespace epi {

float rendercache_pixel(const EpiRows& rows, int x, int y, float rgb[3]) {
  static constexpr float kWeights[9] = {0.25f, 0.5f, 0.25f, 0.5f, 1.0f, 0.5f, 0.25f, 0.5f, 0.25f};
  const auto& lut = epi_color8_to_linear();
  const int dx0 = std::max(-1, -x), dx1 = std::min(1, rows.width - 1 - x);
  const int dy0 = std::max(-1, -y), dy1 = std::min(1, rows.height - 1 - y);
  float sum[3] = {0, 0, 0}, total = 0;
  for (int dy = dy0; dy <= dy1; ++dy)  // branch-free: pixels without a sample weigh 0
    for (int dx = dx0; dx <= dx1; ++dx) {
      const float w = kWeights[(dy + 1) * 3 + dx + 1] * float(has_sample(rows.edge_at(x + dx, y + dy)));
      const uint32_t c = rows.color_at(x + dx, y + dy);
      sum[0] += w * lut[c & 255], sum[1] += w * lut[(c >> 8) & 255], sum[2] += w * lut[(c >> 16) & 255];
      total += w;
    }
  if (total == 0) {
    window_average(rows, x, y, 3, rgb);
    return kMaxPriority;
  }
  for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / total;
  return has_sample(rows.edge_at(x, y)) ? age_priority(sample_age(rows.color_at(x, y))) : weight_priority(total);
}

}  // namespace epi

#include "epi/fill.h"

#include "epi/interpolate.h"

namespace epi {

void fill_pixel(int x, int width, uint32_t reach, const float* const rows[5], const uint8_t* const found[5],
                float out[3]) {
  const float* own = rows[2] + 3 * x;
  out[0] = own[0], out[1] = own[1], out[2] = own[2];
  if (found[2][x]) return;
  // The 24-bit mask spread over the 25 window positions, the centre left out.
  const uint32_t take = (reach & 0xfffu) | ((reach & 0xfff000u) << 1);
  float sum[3] = {0, 0, 0}, total = 0;
  for (int dy = -2; dy <= 2; ++dy) {
    if (!rows[dy + 2]) continue;
    for (int dx = -2; dx <= 2; ++dx) {
      const int px = x + dx, k = (dy + 2) * 5 + dx + 2;
      if (px < 0 || px >= width || !((take >> k) & 1) || !found[dy + 2][px]) continue;
      const float w = kInterpolationWeights[k];
      const float* c = rows[dy + 2] + 3 * px;
      sum[0] += w * c[0], sum[1] += w * c[1], sum[2] += w * c[2];
      total += w;
    }
  }
  if (total > 0)
    for (int c = 0; c < 3; ++c) out[c] = sum[c] / total;
}

}  // namespace epi

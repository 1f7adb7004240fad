#include "render/sparse_blend.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace epi::render {

namespace {

constexpr size_t C = kSparseBlendChannels;

// The recursive filter y = x + a y_prev along a line, forward then backward, restarted after each
// barrier pixel (keep = 0: it neither passes nor takes, and keeps its values); the two directions
// added less the centre give the kernel a^|d|. Both passes below compute exactly this per line,
// on planar data (plane c of pixel i at planes[c * n + i]), many lines at once so that the
// dependent chains of one line overlap with the others'.

// Down the columns [x0, x1) (at most kStrip): each step is a row segment, contiguous (vector lanes).
constexpr int kStrip = 32;
void filter_columns(float* planes, const float* keep, size_t n, int w, int h, int x0, int x1, float a,
                    std::vector<float>& forward) {
  const size_t span = size_t(x1 - x0);
  forward.resize(size_t(h) * span);  // one plane's strip: with the strip's data, within L2
  float acc[kStrip];
  for (size_t c = 0; c < C; ++c) {
    float* plane = planes + c * n;
    float* f = forward.data();
    std::fill(acc, acc + span, 0.0f);
    for (int y = 0; y < h; ++y) {
      const float* v = plane + size_t(y) * size_t(w) + size_t(x0);
      const float* k = keep + size_t(y) * size_t(w) + size_t(x0);
      float* fy = f + size_t(y) * span;
      for (size_t j = 0; j < span; ++j) fy[j] = acc[j] = k[j] * (v[j] + a * acc[j]);
    }
    std::fill(acc, acc + span, 0.0f);
    for (int y = h; y-- > 0;) {
      float* v = plane + size_t(y) * size_t(w) + size_t(x0);
      const float* k = keep + size_t(y) * size_t(w) + size_t(x0);
      const float* fy = f + size_t(y) * span;
      for (size_t j = 0; j < span; ++j) {
        const float x = v[j];
        acc[j] = k[j] * (x + a * acc[j]);
        v[j] = k[j] != 0.0f ? fy[j] + acc[j] - x : x;
      }
    }
  }
}

// Along the rows [y0, y1) (at most kRows): the rows' chains interleaved, pixel by pixel.
constexpr int kRows = 8;
void filter_rows(float* planes, const float* keep, size_t n, int w, int y0, int y1, float a, std::vector<float>& forward) {
  const int rows = y1 - y0;
  forward.resize(size_t(kRows) * size_t(w));
  for (size_t c = 0; c < C; ++c) {
    float* plane = planes + c * n;
    float acc[kRows] = {};
    for (int x = 0; x < w; ++x)
      for (int r = 0; r < rows; ++r) {
        const size_t i = size_t(y0 + r) * size_t(w) + size_t(x);
        forward[size_t(r) * size_t(w) + size_t(x)] = acc[r] = keep[i] * (plane[i] + a * acc[r]);
      }
    for (float& v : acc) v = 0.0f;
    for (int x = w; x-- > 0;)
      for (int r = 0; r < rows; ++r) {
        const size_t i = size_t(y0 + r) * size_t(w) + size_t(x);
        const float v = plane[i];
        acc[r] = keep[i] * (v + a * acc[r]);
        plane[i] = keep[i] != 0.0f ? forward[size_t(r) * size_t(w) + size_t(x)] + acc[r] - v : v;
      }
  }
}

}  // namespace

void filter_samples(const EpiImage& epi, std::span<const uint8_t> barrier, const SparseBlendSettings& settings,
                    std::vector<float>& sums) {
  const int w = epi.width, h = epi.height;
  const size_t n = size_t(w) * size_t(h);
  if (barrier.size() != n) throw std::invalid_argument("sparse_blend: one barrier flag per pixel");
  if (!(settings.sigma > 0.0f) || settings.iterations < 1) throw std::invalid_argument("sparse_blend: sigma > 0, iterations >= 1");
  // Planes r, g, b, weight, mass, then the keep mask (1 where no barrier).
  sums.resize((C + 1) * n);
  float* keep = sums.data() + C * n;
  tbb::parallel_for(0, h, [&](int y) {
    for (size_t i = size_t(y) * size_t(w), end = i + size_t(w); i != end; ++i) {
      float rgb[3] = {0.0f, 0.0f, 0.0f};
      const bool sample = has_sample(epi.edge[i]) && !barrier[i];
      if (sample) decode_color(epi.color[i], rgb);
      sums[i] = rgb[0], sums[n + i] = rgb[1], sums[2 * n + i] = rgb[2];
      sums[3 * n + i] = sample ? 1.0f : 0.0f;
      sums[4 * n + i] = keep[i] = barrier[i] ? 0.0f : 1.0f;
    }
  });
  // The domain transform's scales: iteration k (from 0) filters at
  // sigma sqrt(3) 2^(N-k-1) / sqrt(4^N - 1), so that the N iterations make sigma together.
  const int iterations = settings.iterations;
  for (int k = 0; k < iterations; ++k) {
    const float sigma_k = settings.sigma * std::sqrt(3.0f) * std::exp2(float(iterations - k - 1)) /
                          std::sqrt(std::exp2(2.0f * float(iterations)) - 1.0f);
    const float a = std::exp(-std::sqrt(2.0f) / sigma_k);
    tbb::parallel_for(0, (h + kRows - 1) / kRows, [&](int group) {
      thread_local std::vector<float> forward;
      filter_rows(sums.data(), keep, n, w, group * kRows, std::min(h, (group + 1) * kRows), a, forward);
    });
    tbb::parallel_for(0, (w + kStrip - 1) / kStrip, [&](int strip) {
      thread_local std::vector<float> forward;
      filter_columns(sums.data(), keep, n, w, h, strip * kStrip, std::min(w, (strip + 1) * kStrip), a, forward);
    });
  }
}

bool any_sparse_block(const EpiImage& epi, float dense) {
  constexpr int B = kSparseBlendBlock;
  const int w = epi.width, h = epi.height;
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, (h + B - 1) / B), false,
      [&](const tbb::blocked_range<int>& r, bool any) {
        std::vector<int> count(size_t((w + B - 1) / B));
        for (int by = r.begin(); by != r.end() && !any; ++by) {
          std::fill(count.begin(), count.end(), 0);
          const int y1 = std::min(h, (by + 1) * B);
          for (int y = by * B; y < y1; ++y)
            for (int x = 0; x < w; ++x) count[size_t(x / B)] += has_sample(epi.edge[epi.index(x, y)]);
          for (size_t bx = 0; bx < count.size(); ++bx) {
            const int pixels = (std::min(w, int(bx + 1) * B) - int(bx) * B) * (y1 - by * B);
            any |= float(count[bx]) < dense * float(pixels);
          }
        }
        return any;
      },
      std::logical_or<bool>());
}

size_t sparse_blend(RgbImage& image, const EpiImage& epi, std::span<const uint8_t> barrier,
                    const SparseBlendSettings& settings, SparseBlendScratch& scratch) {
  if (!any_sparse_block(epi, settings.dense)) return 0;  // a still view: nothing to blend
  filter_samples(epi, barrier, settings, scratch.sums);
  const size_t n = size_t(epi.width) * size_t(epi.height);
  const float* s = scratch.sums.data();
  const float span = std::max(settings.dense - settings.sparse, 1e-6f);
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 1 << 14), size_t(0),
      [&](const tbb::blocked_range<size_t>& r, size_t changed) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const float weight = s[3 * n + i];
          if (barrier[i] || !(weight > 0.0f)) continue;
          const float t = std::clamp((settings.dense - weight / s[4 * n + i]) / span, 0.0f, 1.0f);
          if (t <= 0.0f) continue;
          for (size_t c = 0; c < 3; ++c) {
            float& p = image.pixels[3 * i + c];
            p += t * (s[c * n + i] / weight - p);
          }
          ++changed;
        }
        return changed;
      },
      std::plus<size_t>());
}

}  // namespace epi::render

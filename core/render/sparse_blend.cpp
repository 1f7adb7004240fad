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

// One line of the filter: `n` pixels of kChannels floats, `stride` floats apart. Forward then
// backward y = x + a y_prev, restarted after each barrier pixel (which neither passes nor takes,
// and keeps its values); the two directions added less the centre give the kernel a^|d|.
void filter_line(float* data, const uint8_t* barrier, size_t n, size_t stride, size_t barrier_stride, float a,
                 std::vector<float>& forward) {
  constexpr size_t C = kSparseBlendChannels;
  forward.resize(C * n);
  float acc[C] = {};
  for (size_t k = 0; k < n; ++k) {
    const float* v = data + k * stride;
    const float keep = barrier[k * barrier_stride] ? 0.0f : 1.0f;
    for (size_t c = 0; c < C; ++c) forward[C * k + c] = acc[c] = keep * (v[c] + a * acc[c]);
  }
  for (float& c : acc) c = 0.0f;
  for (size_t k = n; k-- > 0;) {
    float* v = data + k * stride;
    if (barrier[k * barrier_stride]) {
      for (float& c : acc) c = 0.0f;
      continue;
    }
    for (size_t c = 0; c < C; ++c) {
      const float x = v[c];
      acc[c] = x + a * acc[c];
      v[c] = forward[C * k + c] + acc[c] - x;
    }
  }
}

}  // namespace

void filter_samples(const EpiImage& epi, std::span<const uint8_t> barrier, const SparseBlendSettings& settings,
                    std::vector<float>& sums) {
  constexpr size_t C = kSparseBlendChannels;
  const int w = epi.width, h = epi.height;
  const size_t n = size_t(w) * size_t(h);
  if (barrier.size() != n) throw std::invalid_argument("sparse_blend: one barrier flag per pixel");
  if (!(settings.sigma > 0.0f) || settings.iterations < 1) throw std::invalid_argument("sparse_blend: sigma > 0, iterations >= 1");
  sums.resize(C * n);
  tbb::parallel_for(0, h, [&](int y) {
    for (size_t i = size_t(y) * size_t(w), end = i + size_t(w); i != end; ++i) {
      float* s = sums.data() + C * i;
      s[0] = s[1] = s[2] = s[3] = 0.0f;
      s[4] = barrier[i] ? 0.0f : 1.0f;
      if (has_sample(epi.edge[i]) && !barrier[i]) {
        decode_color(epi.color[i], s);
        s[3] = 1.0f;
      }
    }
  });
  // The domain transform's scales: iteration k (from 0) filters at
  // sigma sqrt(3) 2^(N-k-1) / sqrt(4^N - 1), so that the N iterations make sigma together.
  const int iterations = settings.iterations;
  for (int k = 0; k < iterations; ++k) {
    const float sigma_k = settings.sigma * std::sqrt(3.0f) * std::exp2(float(iterations - k - 1)) /
                          std::sqrt(std::exp2(2.0f * float(iterations)) - 1.0f);
    const float a = std::exp(-std::sqrt(2.0f) / sigma_k);
    tbb::parallel_for(0, h, [&](int y) {
      thread_local std::vector<float> forward;
      filter_line(sums.data() + C * size_t(y) * size_t(w), barrier.data() + size_t(y) * size_t(w), size_t(w), C, 1, a,
                  forward);
    });
    tbb::parallel_for(0, w, [&](int x) {
      thread_local std::vector<float> forward;
      filter_line(sums.data() + C * size_t(x), barrier.data() + size_t(x), size_t(h), C * size_t(w), size_t(w), a,
                  forward);
    });
  }
}

size_t sparse_blend(RgbImage& image, const EpiImage& epi, std::span<const uint8_t> barrier,
                    const SparseBlendSettings& settings, SparseBlendScratch& scratch) {
  constexpr size_t C = kSparseBlendChannels;
  filter_samples(epi, barrier, settings, scratch.sums);
  const float* s = scratch.sums.data();
  const float span = std::max(settings.dense - settings.sparse, 1e-6f);
  const size_t n = size_t(epi.width) * size_t(epi.height);
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 1 << 14), size_t(0),
      [&](const tbb::blocked_range<size_t>& r, size_t changed) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const float* v = s + C * i;
          if (barrier[i] || !(v[3] > 0.0f)) continue;
          const float t = std::clamp((settings.dense - v[3] / v[4]) / span, 0.0f, 1.0f);
          if (t <= 0.0f) continue;
          for (size_t c = 0; c < 3; ++c) {
            float& p = image.pixels[3 * i + c];
            p += t * (v[c] / v[3] - p);
          }
          ++changed;
        }
        return changed;
      },
      std::plus<size_t>());
}

}  // namespace epi::render

#include "render/sparse_blend.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "render/sparse_blend_kernels.h"

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

// The filter's inputs at pixel i: linear r, g, b and a weight of 1 where the EPI holds a sample
// and no barrier (else zeros), and a mass of 1 where no barrier. `lut`: epi_color8_to_linear(),
// whose entry 0 is 0 (no sample: black).
// Without branches: samples, barriers and empty pixels alternate at random (a branch on them was
// the row pass's most sampled instruction).
inline void pixel_values(const EpiImage& epi, std::span<const uint8_t> barrier, const float* lut, size_t i, float v[C]) {
  const uint32_t open = uint32_t(barrier[i] == 0), sample = open & uint32_t(has_sample(epi.edge[i]));
  const uint32_t colour = epi.color[i] & (0u - sample);
  v[0] = lut[colour & 255], v[1] = lut[(colour >> 8) & 255], v[2] = lut[(colour >> 16) & 255];
  v[3] = float(sample);
  v[4] = float(open);
}

void check_inputs(const EpiImage& epi, std::span<const uint8_t> barrier, const SparseBlendSettings& settings) {
  if (barrier.size() != size_t(epi.width) * size_t(epi.height))
    throw std::invalid_argument("sparse_blend: one barrier flag per pixel");
  if (!(settings.sigma > 0.0f) || settings.iterations < 1) throw std::invalid_argument("sparse_blend: sigma > 0, iterations >= 1");
}

// The domain transform's scales: iteration k (from 0) filters at
// sigma sqrt(3) 2^(N-k-1) / sqrt(4^N - 1), so that the N iterations make sigma together; the
// recursion's coefficient a = exp(-sqrt 2 / sigma_k).
float blend_span(const SparseBlendSettings& settings) { return std::max(settings.dense - settings.sparse, 1e-6f); }

float iteration_coefficient(const SparseBlendSettings& settings, int k) {
  const int iterations = settings.iterations;
  const float sigma_k = settings.sigma * std::sqrt(3.0f) * std::exp2(float(iterations - k - 1)) /
                        std::sqrt(std::exp2(2.0f * float(iterations)) - 1.0f);
  return std::exp(-std::sqrt(2.0f) / sigma_k);
}

}  // namespace

void filter_samples(const EpiImage& epi, std::span<const uint8_t> barrier, const SparseBlendSettings& settings,
                    std::vector<float>& sums) {
  check_inputs(epi, barrier, settings);
  const int w = epi.width, h = epi.height;
  const size_t n = size_t(w) * size_t(h);
  // Planes r, g, b, weight, mass, then the keep mask (1 where no barrier).
  sums.resize((C + 1) * n);
  float* keep = sums.data() + C * n;
  const float* lut = epi_color8_to_linear().data();
  tbb::parallel_for(0, h, [&](int y) {
    for (size_t i = size_t(y) * size_t(w), end = i + size_t(w); i != end; ++i) {
      float v[C];
      pixel_values(epi, barrier, lut, i, v);
      for (size_t c = 0; c < C; ++c) sums[c * n + i] = v[c];
      keep[i] = barrier[i] ? 0.0f : 1.0f;
    }
  });
  for (int k = 0; k < settings.iterations; ++k) {
    const float a = iteration_coefficient(settings, k);
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

void count_block_samples(const EpiImage& epi, int by, uint32_t* row) {
  constexpr int B = kSparseBlendBlock;
  const int w = epi.width, bw = (w + B - 1) / B;
  std::fill(row, row + bw, 0u);
  for (int y = by * B; y < std::min(epi.height, (by + 1) * B); ++y) {
    const uint16_t* edge = epi.edge.data() + epi.index(0, y);
    for (int bx = 0; bx < bw; ++bx) {
      uint32_t n = 0;
      for (int x = bx * B; x < std::min(w, (bx + 1) * B); ++x) n += has_sample(edge[x]);
      row[bx] += n;
    }
  }
}

bool any_sparse_block(const EpiImage& epi, float dense) {
  constexpr int B = kSparseBlendBlock;
  const int w = epi.width, h = epi.height;
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, (h + B - 1) / B), false,
      [&](const tbb::blocked_range<int>& r, bool any) {
        std::vector<uint32_t> count(size_t((w + B - 1) / B));
        for (int by = r.begin(); by != r.end() && !any; ++by) {
          const int y1 = std::min(h, (by + 1) * B);
          count_block_samples(epi, by, count.data());
          for (size_t bx = 0; bx < count.size(); ++bx) {
            const int pixels = (std::min(w, int(bx + 1) * B) - int(bx) * B) * (y1 - by * B);
            any |= float(count[bx]) < dense * float(pixels);
          }
        }
        return any;
      },
      std::logical_or<bool>());
}

size_t sparse_blend_reference(RgbImage& image, const EpiImage& epi, std::span<const uint8_t> barrier,
                              const SparseBlendSettings& settings, std::vector<float>& sums) {
  check_inputs(epi, barrier, settings);
  if (!any_sparse_block(epi, settings.dense)) return 0;  // a still view: nothing to blend
  filter_samples(epi, barrier, settings, sums);
  const size_t n = size_t(epi.width) * size_t(epi.height);
  const float* s = sums.data();
  const float span = blend_span(settings);
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

size_t sparse_blend(RgbImage& image, const EpiImage& epi, std::span<const uint8_t> barrier,
                    const SparseBlendSettings& settings, SparseBlendScratch& scratch) {
  check_inputs(epi, barrier, settings);
  if (!any_sparse_block(epi, settings.dense)) return 0;  // a still view: nothing to blend
  const int w = epi.width, h = epi.height;
  const size_t n = size_t(w) * size_t(h);
  constexpr int L = kSparseRowLanes;
  scratch.sums.resize(C * n);
  float* planes = scratch.sums.data();
  const float* lut = epi_color8_to_linear().data();
  size_t changed = 0;
  for (int k = 0; k < settings.iterations; ++k) {
    const float a = iteration_coefficient(settings, k);
    // Rows, L at a time in vector lanes: the group's values gathered into lanes (from the EPI at
    // the first iteration, from the planes after), filtered, put back into the planes.
    tbb::parallel_for(0, (h + L - 1) / L, [&](int group) {
      thread_local std::vector<float> lanes, keep, forward;
      lanes.resize(size_t(w) * C * L), keep.resize(size_t(w) * L), forward.resize(size_t(w) * C * L);
      const SparseRowGroup rows{epi.edge.data(), k == 0 ? epi.color.data() : nullptr, lut, planes, n, barrier.data(), w,
                                std::min(L, h - group * L), size_t(group) * L * size_t(w)};
      gather_row_lanes(rows, lanes.data(), keep.data());
      filter_row_lanes(lanes.data(), keep.data(), forward.data(), w, a);
      scatter_row_lanes(rows, lanes.data());
    });
    // Columns, in strips; the last iteration's blends the image instead of writing the planes.
    const bool last = k + 1 == settings.iterations;
    changed = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, (w + kSparseStrip - 1) / kSparseStrip), size_t(0),
        [&](const tbb::blocked_range<int>& strips, size_t count) {
          thread_local std::vector<float> forward;
          forward.resize(size_t(h) * C * kSparseStrip);
          for (int strip = strips.begin(); strip != strips.end(); ++strip)
            count += filter_column_strip({planes, n, barrier.data(), w, h, strip * kSparseStrip, a, forward.data(),
                                          last ? image.pixels.data() : nullptr, settings.dense, blend_span(settings)});
          return count;
        },
        std::plus<size_t>());
  }
  return changed;
}

}  // namespace epi::render

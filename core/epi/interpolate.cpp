#include "epi/interpolate.h"

#include <algorithm>
#include <array>
#include <cstring>

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

template <bool kInterior>
float weighted_sum_impl(const EpiRows& rows, int x, int y, uint32_t take, uint16_t need, float rgb[3]) {
  const auto& lut = epi_color8_to_linear();
  const int dx0 = kInterior ? -2 : std::max(-2, -x), dx1 = kInterior ? 2 : std::min(2, rows.width - 1 - x);
  const int dy0 = kInterior ? -2 : std::max(-2, -y), dy1 = kInterior ? 2 : std::min(2, rows.height - 1 - y);
  float sum[3] = {0, 0, 0}, total = 0;
  for (int dy = dy0; dy <= dy1; ++dy) {
    const uint16_t* edge = rows.edge_row(y + dy) + x;
    const uint32_t* color = rows.color_row(y + dy) + x;
    for (int dx = dx0; dx <= dx1; ++dx) {
      const int k = (dy + 2) * 5 + dx + 2;
      const uint32_t use = ((take >> k) & 1u) & uint32_t((edge[dx] & need) == need);
      const float w = kInterpolationWeights[k] * float(use);
      const uint32_t c = color[dx];
      sum[0] += w * lut[c & 255], sum[1] += w * lut[(c >> 8) & 255], sum[2] += w * lut[(c >> 16) & 255];
      total += w;
    }
  }
  if (total > 0)
    for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / total;
  return total;
}

// Kernel-weighted sum over the 5x5, branch-free: pixel k of the window (k = (dy+2)*5 + dx+2)
// counts when bit k of `take` is set and its edge word has all the bits of `need`.
// Interior pixels take a fixed-size loop; both visit the window in the same order.
float weighted_sum(const EpiRows& rows, int x, int y, uint32_t take, uint16_t need, float rgb[3]) {
  const bool interior = x >= 2 && y >= 2 && x + 2 < rows.width && y + 2 < rows.height;
  return interior ? weighted_sum_impl<true>(rows, x, y, take, need, rgb)
                  : weighted_sum_impl<false>(rows, x, y, take, need, rgb);
}

// The 24-bit reach mask spread to the 25 window positions, the centre included.
uint32_t window_mask(uint32_t reach) { return (reach & 0xfffu) | (1u << 12) | ((reach & 0xfff000u) << 1); }

}  // namespace

float simple_estimate(const EpiRows& rows, int x, int y, float rgb[3]) {
  return weighted_sum(rows, x, y, 0x1ffffffu, bits::kHasSample, rgb);
}

int window_average(const EpiRows& rows, int x, int y, int r, float rgb[3]) {
  float sum[3] = {0, 0, 0};
  int count = 0;
  for (int py = y - r; py <= y + r; ++py)
    for (int px = x - r; px <= x + r; ++px) {
      if (!rows.inside(px, py) || !has_sample(rows.edge_at(px, py))) continue;
      float c[3];
      decode_color(rows.color_at(px, py), c);
      sum[0] += c[0], sum[1] += c[1], sum[2] += c[2];
      ++count;
    }
  for (int k = 0; k < 3; ++k) rgb[k] = count ? sum[k] / float(count) : 0.0f;
  return count;
}

namespace {

bool window_holds_edges(TypeRows types, int x, int y, int r) {
  int any = 0;
  for (int py = std::max(0, y - r); py <= std::min(types.height - 1, y + r); ++py)
    for (int px = std::max(0, x - r); px <= std::min(types.width - 1, x + r); ++px)
      any |= types.at(px, py);
  return any != kTypeEmpty;
}

// The fallback's kernel over the 7x7, w(dx, dy) = 1 / (1 + dx^2 + dy^2)^2, at window7_bit.
const std::array<float, 49>& window7_weights() {
  static const std::array<float, 49> weights = [] {
    std::array<float, 49> w{};
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        const float d = float(1 + dx * dx + dy * dy);
        w[size_t(window7_bit(dx, dy))] = 1.0f / (d * d);
      }
    return w;
  }();
  return weights;
}

// The kernel-weighted mean of the usable samples of the 7x7 that `reach` marks (window7_bit),
// into rgb; false when there is none.
bool reachable_mean(const EpiRows& rows, int x, int y, uint64_t reach, float rgb[3]) {
  const auto& lut = epi_color8_to_linear();
  const auto& weights = window7_weights();
  float sum[3] = {0, 0, 0}, total = 0;
  for (int dy = std::max(-3, -y); dy <= std::min(3, rows.height - 1 - y); ++dy)
    for (int dx = std::max(-3, -x); dx <= std::min(3, rows.width - 1 - x); ++dx) {
      if (!((reach >> window7_bit(dx, dy)) & 1) || !usable_sample(rows.edge_at(x + dx, y + dy))) continue;
      const float w = weights[size_t(window7_bit(dx, dy))];
      const uint32_t c = rows.color_at(x + dx, y + dy);
      sum[0] += w * lut[c & 255], sum[1] += w * lut[(c >> 8) & 255], sum[2] += w * lut[(c >> 16) & 255];
      total += w;
    }
  if (total == 0) return false;
  for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / total;
  return true;
}

// fallback_color for pixel (x, y) whose 7x7 lies inside the image, holds a sample and no edge
// (so reaches all of itself: reach_window7's fast path): the weighted mean of the window's usable
// samples, or black (none usable; the last resort needs an edge). In fallback_color's order,
// with fixed bounds and no branch per sample (usable and unusable samples alternate at random
// after motion): a sample left out adds exactly +0 (the colours are finite and not negative, the
// sums start at +0). (Eight pixels' sums interleaved, to overlap their chains of dependent
// additions, measured 1.05-1.12x slower: BM_Fallback, docs/performance.md.)
void whole_window_mean(const EpiRows& rows, int x, int y, float rgb[3]) {
  const auto& lut = epi_color8_to_linear();
  const auto& weights = window7_weights();
  float sum[3] = {0, 0, 0}, total = 0;
  for (int dy = -3; dy <= 3; ++dy) {
    const uint16_t* edge = rows.edge_row(y + dy) + x;
    const uint32_t* colour = rows.color_row(y + dy) + x;
    for (int dx = -3; dx <= 3; ++dx) {
      const float w = usable_sample(edge[dx]) ? weights[size_t(window7_bit(dx, dy))] : 0.0f;
      const uint32_t c = colour[dx];
      sum[0] += w * lut[c & 255], sum[1] += w * lut[(c >> 8) & 255], sum[2] += w * lut[(c >> 16) & 255];
      total += w;
    }
  }
  for (int k = 0; k < 3; ++k) rgb[k] = total > 0 ? sum[k] / total : 0.0f;
}

// Whether a pixel of the (2r+1)^2 window (clipped to the image) holds a sample.
bool window_holds_samples(const EpiRows& rows, int x, int y, int r) {
  uint16_t any = 0;
  for (int py = std::max(0, y - r); py <= std::min(rows.height - 1, y + r); ++py) {
    const uint16_t* edge = rows.edge_row(py);
    for (int px = std::max(0, x - r); px <= std::min(rows.width - 1, x + r); ++px) any |= edge[px];
  }
  return any & bits::kHasSample;
}

}  // namespace

namespace {

// fallback_color's last resort, for a pixel that reaches no usable sample in its 7x7. Only where
// the pixel's own 5x5 holds an edge (so it is at an edge, and its colour unknown either way;
// without blend_near_edges only where an edge crosses the pixel itself) may colour come from
// unreachable samples; elsewhere black.
void last_resort(const EpiRows& rows, int x, int y, float rgb[3], bool blend_near_edges) {
  if (blend_near_edges ? window_holds_edges(rows.type_rows(), x, y, 2) : rows.type_at(x, y) != kTypeEmpty) {
    if (simple_estimate(rows, x, y, rgb) > 0) return;
    if (window_average(rows, x, y, 3, rgb) > 0) return;
  }
  rgb[0] = rgb[1] = rgb[2] = 0.0f;
}

// fallback_color for a pixel whose 7x7 holds a sample, reaching the samples `reach` marks.
void fallback_reaching(const EpiRows& rows, int x, int y, uint64_t reach, float rgb[3], bool blend_near_edges) {
  if (!reachable_mean(rows, x, y, reach, rgb)) last_resort(rows, x, y, rgb, blend_near_edges);
}

}  // namespace

void fallback_color(const EpiRows& rows, int x, int y, float rgb[3], bool blend_near_edges) {
  // Inside a hole (no sample in the 7x7: a usable one has a sample, and every step below reads
  // at most the 7x7) the answer is black, found without the 7x7 reachability.
  if (!window_holds_samples(rows, x, y, 3)) {
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  fallback_reaching(rows, x, y, reach_window7(rows.type_rows(), x, y), rgb, blend_near_edges);
}

int fallback_row(const EpiRows& rows, int y, const uint8_t* found, float* rgb, bool blend_near_edges,
                 FallbackScratch& scratch, bool defer_whole_windows, bool defer_reaching) {
  const int w = rows.width, h = rows.height;
  scratch.span_first = scratch.span_end = scratch.reaching_count = 0;
  const auto* first = static_cast<const uint8_t*>(std::memchr(found, 0, size_t(w)));
  if (!first) return 0;
  const int x_first = int(first - found);
  int x_last = w - 1;
  while (found[x_last]) --x_last;
  // Column ORs over the rows of the 7x7 windows, for the columns those pixels' windows cover.
  const int xa = std::max(0, x_first - 3), xb = std::min(w, x_last + 4);
  scratch.edge_or.resize(size_t(w)), scratch.type_or.resize(size_t(w));
  uint16_t* const edge_or = scratch.edge_or.data();
  uint8_t* const type_or = scratch.type_or.data();
  std::fill(edge_or + xa, edge_or + xb, uint16_t(0));
  std::fill(type_or + xa, type_or + xb, uint8_t(0));
  const TypeRows types = rows.type_rows();
  for (int py = std::max(0, y - 3); py <= std::min(h - 1, y + 3); ++py) {
    const uint16_t* e = rows.edge_row(py);
    const uint8_t* t = types.row(py);
    for (int x = xa; x < xb; ++x) edge_or[x] |= e[x], type_or[x] |= t[x];
  }
  const bool rows_inside = y >= 3 && y + 3 < h;
  auto marks = [&](bool defer, std::vector<uint8_t>& v) -> uint8_t* {
    if (!defer) return nullptr;
    v.resize(size_t(w));
    std::fill(v.begin() + x_first, v.begin() + x_last + 1, uint8_t(0));
    return v.data();
  };
  uint8_t* const whole = marks(defer_whole_windows, scratch.whole_window);
  uint8_t* const reaching = marks(defer_reaching, scratch.reaching);
  scratch.span_first = x_first, scratch.span_end = x_last + 1;
  int deferred = 0;
  for (int x = x_first; x <= x_last; ++x) {
    if (found[x]) continue;
    float* out = rgb + 3 * x;
    uint16_t edges = 0;
    int window_types = 0;
    for (int k = std::max(0, x - 3); k <= std::min(w - 1, x + 3); ++k) edges |= edge_or[k], window_types |= type_or[k];
    if (!(edges & bits::kHasSample))  // a hole: fallback_color's first answer
      out[0] = out[1] = out[2] = 0.0f;
    else if (window_types == kTypeEmpty && rows_inside && x >= 3 && x + 3 < w) {  // (outside counts as complex)
      if (whole) whole[x] = 1, ++deferred;
      else whole_window_mean(rows, x, y, out);
    } else if (reaching) {
      reaching[x] = 1, ++scratch.reaching_count;
    } else {
      fallback_reaching(rows, x, y, reach_window7(types, x, y), out, blend_near_edges);
    }
  }
  return deferred;
}

void fallback_reaching_row(const EpiRows& rows, int y, float* rgb, bool blend_near_edges,
                           const FallbackScratch& scratch, const uint8_t* found) {
  // The marked pixels are few and far apart in most rows: found by memchr, not a branch per pixel.
  const uint8_t* const reaching = scratch.reaching.data();
  const uint8_t* p = reaching + scratch.span_first;
  for (int left = scratch.reaching_count; left > 0; --left, ++p) {
    p = static_cast<const uint8_t*>(std::memchr(p, 1, size_t(reaching + scratch.span_end - p)));
    const int x = int(p - reaching);
    if (!found || x < 3) fallback_reaching(rows, x, y, scratch.reach7[size_t(x)], rgb + 3 * x, blend_near_edges);
    else if (!found[x]) last_resort(rows, x, y, rgb + 3 * x, blend_near_edges);
  }
}

float interpolate_pixel(const EpiRows& rows, int x, int y, uint32_t reach, float rgb[3], bool* found,
                        bool blend_near_edges) {
  const uint16_t e = rows.edge_at(x, y);
  const bool complex = edge_code(e) == kComplexCode;
  const float total = complex ? simple_estimate(rows, x, y, rgb)
                              : weighted_sum(rows, x, y, window_mask(reach), bits::kUsable, rgb);
  if (found) *found = total > 0;
  if (total == 0) {
    fallback_color(rows, x, y, rgb, blend_near_edges);
    return kMaxPriority;
  }
  // A pixel whose own sample is edge-ambiguous is treated as unsampled: weight priority.
  return usable_sample(e) ? age_priority(sample_age(rows.color_at(x, y))) : weight_priority(total);
}

}  // namespace epi

#include "render/sampling.h"

#include "render/point_projection.h"
#include "render/sparse_blend.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <atomic>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace epi::render {

namespace {

uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

float unit_float(uint64_t bits) { return float(bits >> 40) * (1.0f / float(1u << 24)); }  // [0, 1)


// The Hilbert curve over an 8x8 block: cell (x, y) of each step, from (0, 0) to (7, 0), so the
// curves of blocks side by side join into one path along a strip of 8 rows.
constexpr int kBlock = 8;
struct HilbertBlock {
  std::array<uint8_t, kBlock * kBlock> x{}, y{};
  HilbertBlock() {
    for (int d = 0; d < kBlock * kBlock; ++d) {
      int cx = 0, cy = 0;
      for (int s = 1, t = d; s < kBlock; s *= 2, t /= 4) {
        const int rx = 1 & (t / 2), ry = 1 & (t ^ rx);
        if (ry == 0) {
          if (rx == 1) cx = s - 1 - cx, cy = s - 1 - cy;
          std::swap(cx, cy);
        }
        cx += s * rx, cy += s * ry;
      }
      x[size_t(d)] = uint8_t(cx), y[size_t(d)] = uint8_t(cy);
    }
  }
};
const HilbertBlock& hilbert_block() {
  static const HilbertBlock block;
  return block;
}

// One band of at most 64 rows: `priority` and the returned indices are the band's own
// (row-major, from 0). Error diffusion along a space-filling path (Riemersma-style, the whole
// error carried to the next pixel): the band's strips of 8 rows in boustrophedon order, each
// strip block after block, each 8x8 block along its Hilbert curve. Every strip gets its share
// of the picks to within one, the curve's locality spreads them inside the strip, and there is
// no start-up transient (the error starts at a hashed phase), whatever the density.
std::vector<uint32_t> dither_band(const float* priority, bool uniform, int width, int height, size_t count,
                                  uint64_t band_seed, double total) {
  const size_t pixels = size_t(width) * size_t(height);
  count = std::min(count, pixels);
  std::vector<uint32_t> picked;
  if (count == 0 || pixels == 0) return picked;
  uniform = uniform || !(total > 0.0);  // total: the band's priority sum (dither_in_bands made it)
  auto weight = [&](size_t i) { return uniform ? 1.0f : std::max(0.0f, priority[i]); };
  const double scale = double(count) / (uniform ? double(pixels) : total);

  // The value at the decision is kept: it ranks pixels when the count is settled. Every pixel's
  // entries are written below; the storage is the thread's, kept from band to band and frame to frame.
  thread_local std::vector<float> decision;
  thread_local std::vector<uint8_t> chosen;
  decision.resize(pixels), chosen.resize(pixels);
  // Local pointers: through the thread-local vectors, GCC recomputed their address and reloaded
  // their data for every pixel, and kept the carried error on the stack.
  float* const decision_at = decision.data();
  uint8_t* const chosen_at = chosen.data();
  const HilbertBlock& curve = hilbert_block();
  double error = double(unit_float(splitmix64(band_seed))) - 0.5;  // the phase of the first pick
  const int blocks = (width + kBlock - 1) / kBlock;
  for (int strip = 0; strip * kBlock < height; ++strip) {
    const bool forward = (strip & 1) == 0;  // odd strips right to left, their blocks mirrored
    for (int b = 0; b < blocks; ++b) {
      const int bx = (forward ? b : blocks - 1 - b) * kBlock;
      const bool whole = bx + kBlock <= width && (strip + 1) * kBlock <= height;
      for (int d = 0; d < kBlock * kBlock; ++d) {
        const int x = bx + (forward ? curve.x[size_t(d)] : kBlock - 1 - curve.x[size_t(d)]);
        const int y = strip * kBlock + curve.y[size_t(d)];
        if (!whole && (x >= width || y >= height)) continue;
        const size_t i = size_t(y) * size_t(width) + size_t(x);
        const float w = weight(i);
        const double value = double(w) * scale + error;
        decision_at[i] = float(value);
        const bool pick = value >= 0.5 && w > 0.0f;
        chosen_at[i] = pick;
        error = pick ? value - 1.0 : value;
      }
    }
  }
  return settle_picks(uniform ? nullptr : priority, chosen, decision, count);
}

}  // namespace

std::vector<uint32_t> settle_picks(const float* priority, std::span<const uint8_t> chosen, std::span<const float> decision,
                                   size_t count) {
  const size_t pixels = chosen.size();
  auto weight = [&](size_t i) { return priority ? std::max(0.0f, priority[i]) : 1.0f; };
  std::vector<uint32_t> picked;
  for (size_t i = 0; i < pixels; ++i)
    if (chosen[i]) picked.push_back(uint32_t(i));

  // Settle the count by the decision values: positive priority first, then the value nearest the
  // threshold from the other side; ties by index.
  auto before = [&](uint32_t a, uint32_t b) {
    const bool pa = weight(a) > 0.0f, pb = weight(b) > 0.0f;
    if (pa != pb) return pa;
    if (decision[a] != decision[b]) return decision[a] > decision[b];
    return a < b;
  };
  if (picked.size() > count) {
    std::nth_element(picked.begin(), picked.begin() + ptrdiff_t(count), picked.end(), before);
    picked.resize(count);
  } else if (picked.size() < count) {
    // The best unpicked pixels: usually among those that came close to the threshold, so look
    // there first and at all of them only if that is not enough.
    const size_t need = count - picked.size();
    std::vector<uint32_t> rest;
    for (const bool near_only : {true, false}) {
      rest.clear();
      for (size_t i = 0; i < pixels; ++i)
        if (!chosen[i] && (!near_only || (weight(i) > 0.0f && decision[i] >= 0.25f))) rest.push_back(uint32_t(i));
      if (rest.size() >= need) break;  // the best `need` of all rank first among these
    }
    std::nth_element(rest.begin(), rest.begin() + ptrdiff_t(need), rest.end(), before);
    picked.insert(picked.end(), rest.begin(), rest.begin() + ptrdiff_t(need));
  }
  std::sort(picked.begin(), picked.end());
  return picked;
}

std::vector<uint32_t> dither_in_bands(std::span<const float> priority, int width, int height, size_t count,
                                      const BandDither& band_dither) {
  const size_t pixels = size_t(width) * size_t(height);
  count = std::min(count, pixels);
  if (count == 0 || pixels == 0) return {};
  // Bands of rows dithered in parallel. Each gets a share of the count by its priority sum
  // (largest remainders), never more than its positive pixels while other bands have some left.
  const int band_rows = 64;
  const int bands = (height + band_rows - 1) / band_rows;
  struct Band {
    double sum = 0;
    size_t positive = 0, pixels = 0, count = 0;
  };
  std::vector<Band> info(static_cast<size_t>(bands));
  const bool sized = priority.size() >= pixels;  // a shorter priority image is not read: uniform
  tbb::parallel_for(0, bands, [&](int b) {
    Band& band = info[size_t(b)];
    const size_t first = size_t(b) * band_rows * size_t(width);
    band.pixels = size_t(std::min(height, (b + 1) * band_rows) - b * band_rows) * size_t(width);
    for (size_t i = first; i < first + band.pixels && sized; ++i) {
      const float p = std::max(0.0f, priority[i]);
      band.sum += p, band.positive += p > 0.0f;
    }
  });
  // Uniform where no pixel has a positive priority (the sum of non-negative terms is positive
  // exactly when one is): then every pixel weighs 1.
  bool any_positive = false;
  for (const Band& b : info) any_positive = any_positive || b.positive > 0;
  const bool uniform = !sized || !any_positive;
  if (uniform)
    for (Band& b : info) b.sum = double(b.pixels), b.positive = b.pixels;
  double sum = 0.0;
  for (const Band& b : info) sum += b.sum;
  std::vector<std::pair<double, int>> remainders;
  size_t given = 0;
  for (int b = 0; b < bands; ++b) {
    const double exact = double(count) * info[size_t(b)].sum / sum;
    info[size_t(b)].count = std::min(info[size_t(b)].positive, size_t(exact));
    given += info[size_t(b)].count;
    remainders.push_back({exact - double(info[size_t(b)].count), b});
  }
  std::stable_sort(remainders.begin(), remainders.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const bool zeros_too : {false, true})  // positive pixels first, by remainder; then any pixel
    for (size_t pass = 0; given < count && pass < 2; ++pass)
      for (const auto& [remainder, b] : remainders) {
        Band& band = info[size_t(b)];
        const size_t room = (zeros_too ? band.pixels : band.positive) - band.count;
        const size_t add = std::min(room, pass == 0 ? size_t(1) : count - given);
        band.count += add, given += add;
        if (given == count) break;
      }

  std::vector<std::vector<uint32_t>> picks(static_cast<size_t>(bands));
  tbb::parallel_for(0, bands, [&](int b) {
    const size_t first = size_t(b) * band_rows * size_t(width);
    const int rows = int(info[size_t(b)].pixels / size_t(width));
    picks[size_t(b)] =
        band_dither(uniform ? nullptr : priority.data() + first, uniform, width, rows, info[size_t(b)].count, uint64_t(b),
                    info[size_t(b)].sum);
    for (uint32_t& i : picks[size_t(b)]) i += uint32_t(first);
  });
  std::vector<uint32_t> picked;
  picked.reserve(count);
  for (const auto& p : picks) picked.insert(picked.end(), p.begin(), p.end());
  return picked;
}

std::vector<uint32_t> dither_pixels(std::span<const float> priority, int width, int height, size_t count) {
  return dither_in_bands(priority, width, height, count, dither_band);
}

void make_requests(std::span<const uint32_t> pixels, int width, uint64_t seed, uint64_t frame, uint32_t first_id,
                   std::vector<ShadeRequest>& out) {
  const uint64_t stream = splitmix64(seed ^ splitmix64(frame + 0x5851f42d4c957f2dull));
  for (size_t k = 0; k < pixels.size(); ++k) {
    const uint32_t p = pixels[k];
    const uint64_t bits = splitmix64(stream ^ p);
    ShadeRequest r;
    r.id = first_id + uint32_t(k);
    r.x = float(p % uint32_t(width)) + unit_float(bits);
    r.y = float(p / uint32_t(width)) + unit_float(splitmix64(bits));
    out.push_back(r);
  }
}

void set_sparse_effort(std::span<ShadeRequest> requests, const EpiImage& epi, float dense, int most,
                       std::vector<uint32_t>& counts) {
  for (ShadeRequest& r : requests) r.effort = 1;
  if (most <= 1 || requests.empty() || epi.width <= 0 || epi.height <= 0) return;
  constexpr int B = kSparseBlendBlock;
  const int w = epi.width, h = epi.height, bw = (w + B - 1) / B, bh = (h + B - 1) / B;
  counts.resize(size_t(bw) * size_t(bh));
  tbb::parallel_for(0, bh, [&](int by) { count_block_samples(epi, by, counts.data() + size_t(by) * size_t(bw)); });
  const uint8_t most8 = uint8_t(std::min(most, 255));
  for (ShadeRequest& r : requests) {
    if (!std::isfinite(r.x) || !std::isfinite(r.y)) continue;
    const int bx = std::clamp(int(r.x) / B, 0, bw - 1), by = std::clamp(int(r.y) / B, 0, bh - 1);
    uint64_t samples = 0, pixels = 0;
    for (int y = std::max(0, by - 1); y <= std::min(bh - 1, by + 1); ++y)
      for (int x = std::max(0, bx - 1); x <= std::min(bw - 1, bx + 1); ++x) {
        samples += counts[size_t(y) * size_t(bw) + size_t(x)];
        pixels += uint64_t(std::min(w, (x + 1) * B) - x * B) * uint64_t(std::min(h, (y + 1) * B) - y * B);
      }
    const double share = double(samples) / double(pixels);
    const double effort = share > 0.0 ? std::round(std::sqrt(double(dense) / share)) : double(most8);
    r.effort = uint8_t(std::clamp(effort, 1.0, double(most8)));
  }
}

void shuffle_requests(std::vector<ShadeRequest>& requests, uint64_t seed, uint64_t frame) {
  uint64_t state = splitmix64(seed ^ splitmix64(frame ^ 0x243f6a8885a308d3ull));
  for (size_t k = requests.size(); k > 1; --k) {
    state = splitmix64(state);
    const size_t j = size_t((unsigned __int128)state * k >> 64);  // uniform in [0, k)
    std::swap(requests[k - 1], requests[j]);
  }
}

std::vector<SubmissionPart> interleave_shots(std::span<const size_t> shot_sizes, size_t round_size) {
  size_t total = 0;
  for (size_t n : shot_sizes) total += n;
  const size_t rounds = std::max<size_t>(1, (total + std::max<size_t>(1, round_size) - 1) / std::max<size_t>(1, round_size));
  std::vector<SubmissionPart> parts;
  for (size_t r = 0; r < rounds; ++r)
    for (size_t s = 0; s < shot_sizes.size(); ++s) {
      const size_t begin = shot_sizes[s] * r / rounds, end = shot_sizes[s] * (r + 1) / rounds;
      if (end > begin) parts.push_back({s, begin, end});
    }
  return parts;
}

Camera extrapolate_camera(const Camera& previous, const Camera& current, float ahead) {
  Camera c = current;
  c.eye = current.eye + ahead * (current.eye - previous.eye);
  c.target = current.target + ahead * (current.target - previous.target);
  if (!(glm::length(c.target - c.eye) > 1e-6f)) c = current;  // degenerate: no prediction
  // Beyond the ray tracer's range (or overflowed): ViewFrame would refuse it; no prediction.
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(c.eye[k]) <= kMaxRayCoordinate && std::abs(c.target[k]) <= kMaxRayCoordinate)) return current;
  return c;
}

std::vector<uint8_t> predicted_occupancy(const PointCache& cache, const ViewFrame& frame,
                                         std::span<const glm::mat4> object_to_world, int stride, int phase, int splat) {
  std::vector<uint8_t> occupied;
  predicted_occupancy(cache, frame, object_to_world, stride, phase, splat, occupied);
  return occupied;
}

void predicted_occupancy(const PointCache& cache, const ViewFrame& frame, std::span<const glm::mat4> object_to_world,
                         int stride, int phase, int splat, std::vector<uint8_t>& occupied) {
  const int w = frame.view().width, h = frame.view().height;
  occupied.resize(size_t(w) * size_t(h));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, occupied.size(), 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
    std::fill(occupied.begin() + ptrdiff_t(r.begin()), occupied.begin() + ptrdiff_t(r.end()), uint8_t(0));
  });
  const auto& points = cache.points();
  stride = std::max(1, stride);
  const float znear = std::max(frame.view().camera.znear, 0.0f);
  // Points in parallel; a pixel is only ever set to 1, through an atomic reference. The subset is
  // chosen before a point is read; the chosen ones are projected in batches (project_batch, the
  // point cache's kernel: ViewFrame::project's bits).
  const uint64_t subset = uint64_t(std::max(0, phase) % stride);
  const bool power_of_two = (stride & (stride - 1)) == 0;
  uint8_t* const occupancy = occupied.data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 8192), [&](const tbb::blocked_range<size_t>& r) {
    // Locals, not the closure's references: the compiler reloads those after every atomic store.
    const int sw = w, sh = h, sp = splat;
    const float near = znear;
    ProjectionBatch batch;
    for (auto* in : {batch.eye_x, batch.eye_y, batch.eye_z}) std::fill_n(in, ProjectionBatch::kSize, 0.0f);
    std::fill_n(batch.normal, ProjectionBatch::kSize, 0u);  // no back-face test (its result is not read here)
    size_t count = 0;
    auto splat_batch = [&] {
      for (size_t k = count; k < std::min(ProjectionBatch::kSize, count + 16); ++k)  // the last vector's lanes
        batch.x[k] = batch.y[k] = batch.z[k] = 0.0f, batch.view[k] = 0, batch.lobe_width[k] = 1.0f;
      project_batch(frame, batch, count);
      for (size_t k = 0; k < count; ++k) {
        if (!(batch.depth[k] > near)) continue;
        const float fx = std::floor(batch.pixel_x[k] - 0.5f * float(sp) + 0.5f);
        const float fy = std::floor(batch.pixel_y[k] - 0.5f * float(sp) + 0.5f);
        if (!(fx > -float(sp) && fy > -float(sp) && fx < float(sw) && fy < float(sh))) continue;
        const int x0 = int(fx), y0 = int(fy);
        const int xa = std::max(0, x0), xb = std::min(sw, x0 + sp), ya = std::max(0, y0), yb = std::min(sh, y0 + sp);
        for (int y = ya; y < yb; ++y) {
          uint8_t* row = occupancy + size_t(y) * size_t(sw);
          for (int x = xa; x < xb; ++x) std::atomic_ref<uint8_t>(row[x]).store(1, std::memory_order_relaxed);
        }
      }
      count = 0;
    };
    // The subset a chunk of slots at a time, without a branch per slot (the hash picks 1 of
    // `stride` at random: a branch on it mispredicts every other slot at stride 2; a power of two
    // takes a mask, not a division); then the chosen slots in order, each prefetching the slot two
    // chunks ahead (the hardware prefetch did not keep ahead of this gappy stream: 27.1 -> 21.3 ms
    // on one thread at 1080p, docs/performance.md "Predictive sampling's occupancy").
    constexpr size_t kChunk = 256;
    uint32_t chosen[kChunk];
    for (size_t c0 = r.begin(); c0 < r.end(); c0 += kChunk) {
      const size_t c1 = std::min(r.end(), c0 + kChunk);
      size_t n = 0;
      for (size_t i = c0; i < c1; ++i) {
        const uint64_t hash = splitmix64(i);
        chosen[n] = uint32_t(i - c0);
        n += (power_of_two ? hash & uint64_t(stride - 1) : hash % uint64_t(stride)) == subset;
      }
      for (size_t k = 0; k < n; ++k) {
        __builtin_prefetch(&points[std::min(c0 + chosen[k] + 2 * kChunk, points.size() - 1)]);
        const CachePoint& p = points[c0 + chosen[k]];
        if (!p.valid) continue;
        const glm::vec3 world = cache.world_position(p, frame, object_to_world);
        batch.x[count] = world.x, batch.y[count] = world.y, batch.z[count] = world.z;
        batch.view[count] = 0, batch.lobe_width[count] = 1.0f;  // no staleness
        if (++count == ProjectionBatch::kSize) splat_batch();
      }
    }
    if (count > 0) splat_batch();
  });
}

}  // namespace epi::render

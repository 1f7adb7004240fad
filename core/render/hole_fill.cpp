#include "render/hole_fill.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "epi/interpolate.h"
#include "target_clones.h"

namespace epi::render {

size_t fill_holes(RgbImage& image, std::span<const uint8_t> holes, std::span<const uint8_t> barrier) {
  HoleFillScratch scratch;
  return fill_holes(image, holes, barrier, scratch);
}

size_t fill_holes(RgbImage& image, std::span<const uint8_t> holes, std::span<const uint8_t> barrier,
                  HoleFillScratch& scratch) {
  const size_t n = size_t(image.width) * size_t(image.height);
  if (holes.size() != n || barrier.size() != n) throw std::invalid_argument("fill_holes: mask size differs from the image");
  // The passes visit the holes only (a few per mille of a frame's pixels after motion, in
  // ascending order, as a scan of the image would): listed once, 64 pixels at a time (most such
  // chunks hold none).
  std::vector<uint8_t>& state = scratch.state;
  std::vector<uint32_t>& hole_list = scratch.holes;
  state.resize(n), hole_list.clear();
  for (size_t i = 0; i < n; i += 64) {
    const size_t end = std::min(n, i + 64);
    uint8_t any = 0;
    for (size_t k = i; k < end; ++k) state[k] = hole_state(holes[k] != 0, barrier[k] != 0), any |= state[k];
    if (any)
      for (size_t k = i; k < end; ++k)
        if (state[k]) hole_list.push_back(uint32_t(k));
  }
  return fill_listed_holes(image, barrier, scratch);
}

size_t fill_listed_holes(RgbImage& image, std::span<const uint8_t> barrier, HoleFillScratch& scratch) {
  const int w = image.width, h = image.height;
  const size_t n = size_t(w) * size_t(h);
  if (scratch.state.size() != n || barrier.size() != n) throw std::invalid_argument("fill_holes: mask size differs from the image");
  // state: 0 filled (a source), 1 hole, 2 hole on a barrier (filled last).
  std::vector<uint8_t>& state = scratch.state;
  std::vector<uint32_t> &front = scratch.front, &next = scratch.next, &ring = scratch.ring, &last = scratch.last;
  const std::vector<uint32_t>& hole_list = scratch.holes;
  front.clear(), last.clear();
  auto fill_from_neighbours = [&](int x, int y, bool through_barriers) {
    float sum[3] = {0, 0, 0};
    int count = 0;
    for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
      for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) {
        const size_t q = size_t(qy) * size_t(w) + size_t(qx);
        if (state[q] != 0 || (!through_barriers && barrier[q])) continue;
        for (int c = 0; c < 3; ++c) sum[c] += image.pixels[q * 3 + size_t(c)];
        ++count;
      }
    if (count == 0) return false;
    const size_t i = size_t(y) * size_t(w) + size_t(x);
    for (int c = 0; c < 3; ++c) image.pixels[i * 3 + size_t(c)] = sum[c] / float(count);
    return true;
  };
  auto has_source_neighbour = [&](int x, int y) {
    for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
      for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) {
        const size_t q = size_t(qy) * size_t(w) + size_t(qx);
        if (state[q] == 0 && !barrier[q]) return true;
      }
    return false;
  };
  // The first ring: holes off barriers next to a filled pixel off a barrier.
  for (const uint32_t i : hole_list)
    if (state[i] == 1 && has_source_neighbour(int(i % uint32_t(w)), int(i / uint32_t(w)))) front.push_back(i);
  size_t filled = 0;
  while (!front.empty()) {
    // Each ring is coloured from the rings before it only, then becomes a source.
    ring.clear();
    for (const uint32_t i : front)
      if (state[i] == 1 && fill_from_neighbours(int(i % uint32_t(w)), int(i / uint32_t(w)), false)) ring.push_back(i);
    for (const uint32_t i : ring) state[i] = 0;
    filled += ring.size();
    next.clear();
    for (const uint32_t i : ring) {
      const int x = int(i % uint32_t(w)), y = int(i / uint32_t(w));
      for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
        for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) {
          const size_t q = size_t(qy) * size_t(w) + size_t(qx);
          if (state[q] == 1) state[q] = 3, next.push_back(uint32_t(q));  // 3: queued
        }
    }
    for (const uint32_t i : next) state[i] = 1;
    front.swap(next);
  }
  // Holes on barriers: from any filled neighbour.
  for (const uint32_t i : hole_list)
    if (state[i] == 2 && fill_from_neighbours(int(i % uint32_t(w)), int(i / uint32_t(w)), true)) last.push_back(i);
  for (const uint32_t i : last) state[i] = 0;
  filled += last.size();
  // Holes still unfilled lie in a region the edges enclose that holds no source of its own:
  // rings from any filled neighbour, barriers included (the nearest colours, whatever side).
  front.clear();
  for (const uint32_t i : hole_list) {
    if (state[i] == 0) continue;
    state[i] = 1;
    const int x = int(i % uint32_t(w)), y = int(i / uint32_t(w));
    bool touches = false;
    for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
      for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) touches |= state[size_t(qy) * size_t(w) + size_t(qx)] == 0;
    if (touches) front.push_back(i);
  }
  while (!front.empty()) {
    ring.clear();
    for (const uint32_t i : front)
      if (fill_from_neighbours(int(i % uint32_t(w)), int(i / uint32_t(w)), true)) ring.push_back(i);
    for (const uint32_t i : ring) state[i] = 0;
    filled += ring.size();
    next.clear();
    for (const uint32_t i : ring) {
      const int x = int(i % uint32_t(w)), y = int(i / uint32_t(w));
      for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 1); ++qy)
        for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 1); ++qx) {
          const size_t q = size_t(qy) * size_t(w) + size_t(qx);
          if (state[q] == 1) state[q] = 3, next.push_back(uint32_t(q));
        }
    }
    for (const uint32_t i : next) state[i] = 1;
    front.swap(next);
  }
  return filled;
}

namespace {

// list_holes' plain loops, compiled for every target (target_clones.h).
EPI_TARGET_CLONES void barrier_flags(const uint8_t* __restrict edges, uint8_t bits, uint8_t* __restrict out, size_t n) {
  for (size_t i = 0; i < n; ++i) out[i] = (edges[i] & bits) != 0;
}
EPI_TARGET_CLONES int count_at_top(const float* __restrict top, size_t n) {
  int at_top = 0;
  for (size_t i = 0; i < n; ++i) at_top += top[i] >= kMaxPriority;
  return at_top;
}

}  // namespace

void list_holes(const RgbImage& image, std::span<const float> priority, std::span<const uint8_t> edge_flags,
                uint8_t barrier_bits, std::vector<uint8_t>& barrier, HoleFillScratch& scratch) {
  const int w = image.width, h = image.height;
  const size_t n = size_t(w) * size_t(h);
  if (priority.size() != n || edge_flags.size() != n) throw std::invalid_argument("list_holes: mask size differs from the image");
  constexpr int kBandRows = 16;
  const int bands = (h + kBandRows - 1) / kBandRows;
  barrier.resize(n), scratch.state.resize(n), scratch.band_holes.resize(size_t(bands));
  tbb::parallel_for(0, bands, [&](int band) {
    // Local pointers: the byte stores below may alias anything, members would be reloaded.
    const float* const top = priority.data();
    const float* const rgb = image.pixels.data();
    const uint8_t* const edges = edge_flags.data();
    uint8_t* const barrier_out = barrier.data();
    uint8_t* const state = scratch.state.data();
    std::vector<uint32_t>& list = scratch.band_holes[size_t(band)];
    list.clear();
    const size_t begin = size_t(band) * kBandRows * size_t(w), end = std::min(n, begin + kBandRows * size_t(w));
    // Plain loops the compiler vectorizes (for every target); only chunks with a top-priority
    // pixel are looked at further (at rest, holes alone are at the top, and rare).
    barrier_flags(edges + begin, barrier_bits, barrier_out + begin, end - begin);
    std::fill(state + begin, state + end, hole_state(false, false));
    constexpr size_t kChunk = 64;  // one bit a pixel in the mask below
    for (size_t c = begin; c < end; c += kChunk) {
      const size_t c_end = std::min(end, c + kChunk);
      if (count_at_top(top + c, c_end - c) == 0) continue;
      // The chunk's holes as a bit mask (a vector kernel: in motion many pixels are at the top,
      // most of them the fallback's, not holes, and a branch per pixel mispredicted), then in order.
      uint64_t holes = hole_mask(top + c, rgb + 3 * c, c_end - c);
      for (; holes != 0; holes &= holes - 1) {
        const size_t i = c + size_t(std::countr_zero(holes));
        state[i] = hole_state(true, barrier_out[i] != 0), list.push_back(uint32_t(i));
      }
    }
  });
  scratch.holes.clear();
  for (const std::vector<uint32_t>& list : scratch.band_holes) scratch.holes.insert(scratch.holes.end(), list.begin(), list.end());
}

}  // namespace epi::render

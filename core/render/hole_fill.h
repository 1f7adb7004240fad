// Holes become blur, not black (docs/render.md, "Holes"): after fast motion some pixels reach no
// sample (the filters leave them black at top priority). They are filled from the nearest filled
// pixels of their own region: a breadth-first fill that never passes a geometric edge.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "epi/interpolate.h"
#include "image/image.h"

namespace epi::render {

// Fills the pixels flagged in `holes` (non-zero) of `image`, ring by ring outwards from the
// filled pixels: a hole pixel takes the mean of its already filled 8-neighbours. Pixels flagged in
// `barrier` (non-zero; geometric edges) neither pass colour on nor take it until every other hole
// is filled; they then take the mean of their filled neighbours. Holes still unfilled then (a
// region the barriers enclose that held no filled pixel) are filled ring by ring from any filled
// neighbour, barriers included. Only holes no filled pixel reaches at all stay as they are.
// Returns the number of pixels filled.
// `scratch` keeps the fill's working storage between calls (the renderer's, per frame).
struct HoleFillScratch {
  std::vector<uint8_t> state;
  std::vector<uint32_t> front, next, ring, last, holes;
  std::vector<std::vector<uint32_t>> band_holes;  // list_holes: each band's holes
};
size_t fill_holes(RgbImage& image, std::span<const uint8_t> holes, std::span<const uint8_t> barrier,
                  HoleFillScratch& scratch);
size_t fill_holes(RgbImage& image, std::span<const uint8_t> holes, std::span<const uint8_t> barrier);

// fill_holes with its set-up made by the caller, in the pass that finds the holes anyway (the
// renderer): scratch.state[i] = hole_state(hole, barrier) for every pixel, scratch.holes the pixels
// whose state is not 0, ascending. The same image as fill_holes.
inline uint8_t hole_state(bool hole, bool on_barrier) { return uint8_t(uint32_t(hole) * (1u + uint32_t(on_barrier))); }
size_t fill_listed_holes(RgbImage& image, std::span<const uint8_t> barrier, HoleFillScratch& scratch);

// A hole: a pixel at top priority (no sample reached) that is black.
inline bool is_hole(float priority, const float* rgb) {
  return (priority >= kMaxPriority) & (rgb[0] == 0.0f) & (rgb[1] == 0.0f) & (rgb[2] == 0.0f);
}
// Bit k: whether pixel k of `count` (at most 64) is a hole, from its priority top[k] and colour
// rgb[3k, 3k + 3). A Highway kernel (hole_mask.cpp); every target gives is_hole's bits.
uint64_t hole_mask(const float* top, const float* rgb, size_t count);

// The renderer's set-up of fill_listed_holes, in one pass over bands of rows in parallel. A hole
// is a pixel of `image` at top priority (`priority` >= kMaxPriority: no sample reached) that is
// black; a barrier, a pixel whose `edge_flags` has a bit of `barrier_bits`. Writes `barrier`
// (0 or 1 per pixel), scratch.state and scratch.holes (ascending: the bands' lists joined in order).
void list_holes(const RgbImage& image, std::span<const float> priority, std::span<const uint8_t> edge_flags,
                uint8_t barrier_bits, std::vector<uint8_t>& barrier, HoleFillScratch& scratch);

}  // namespace epi::render

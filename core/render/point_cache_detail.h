// Internal to point_cache*.cpp: the z-buffer key and the packings shared by the fast path and the
// reference path (point_cache_reference.cpp).
#pragma once

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace epi::render::detail {

inline constexpr size_t kAgeBins = 258;  // ages 0..255 (capped), then off screen
inline constexpr uint64_t kEmptyKey = ~uint64_t(0);
inline constexpr uint32_t kIndexMask = 0x0fffffffu;  // point index; bits 28-31 hold the sub-pixel region

// Z-buffer key: depth first (positive floats order like their bits), then region and index.
inline uint64_t zkey(float depth, int region, uint32_t index) {
  return uint64_t(std::bit_cast<uint32_t>(depth)) << 32 | uint64_t(region) << 28 | index;
}

inline void atomic_min(uint64_t& slot, uint64_t value) {
  std::atomic_ref<uint64_t> ref(slot);
  uint64_t current = ref.load(std::memory_order_relaxed);
  while (value < current && !ref.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
  }
}

inline glm::vec3 unpack_unit(uint32_t packed) {
  glm::vec2 e(float(packed & 0xffffu) / 65535.0f * 2.0f - 1.0f, float(packed >> 16) / 65535.0f * 2.0f - 1.0f);
  glm::vec3 n(e.x, e.y, 1.0f - std::abs(e.x) - std::abs(e.y));
  if (n.z < 0.0f) {
    const glm::vec2 f = (1.0f - glm::abs(glm::vec2(e.y, e.x))) * glm::vec2(e.x >= 0.0f ? 1.0f : -1.0f, e.y >= 0.0f ? 1.0f : -1.0f);
    n.x = f.x, n.y = f.y;
  }
  return glm::normalize(n);
}

// Whether a surface of the given packed normal (0: none) faces away from the eye (to_eye: from the
// point to the eye, in the normal's space).
inline bool faces_away(uint32_t normal, const glm::vec3& to_eye) {
  return normal != 0 && glm::dot(unpack_unit(normal), to_eye) < 0.0f;
}

// The cosine between a packed normal and the direction to the eye (to_eye: from the point to the
// eye, in the normal's space, not normalized), in project_batch's order of operations.
inline float facing_cosine(uint32_t normal, const glm::vec3& to_eye) {
  return glm::dot(unpack_unit(normal), to_eye) / std::sqrt(glm::dot(to_eye, to_eye));
}

// lround(min(16 acos(cosine) / width, 255)): a view's turn in 1/16 lobe widths (the staleness of
// view-dependent shading), without acos where a polynomial settles it. acos(|x|) =
// sqrt(1 - |x|) (a0 + a1 |x| + a2 |x|^2 + a3 |x|^3) within 5e-5 (Abramowitz and Stegun 4.4.45;
// pi - that for x < 0); with 1e-4 for it and for float rounding, the estimate decides whenever no
// rounding boundary (k + 1/2, or the cap) lies within that error of it, and std::acos the rest.
// Equal to the direct formula for every input (tests/render/point_cache_fast_test.cpp).
inline uint8_t staleness_steps(float cosine, float width) {
  const float x = std::abs(cosine);
  float turned = std::sqrt(1.0f - x) * (1.5707288f + x * (-0.2121144f + x * (0.0742610f + x * -0.0187293f)));
  if (cosine < 0.0f) turned = 3.14159265f - turned;
  const float steps = 16.0f * turned / width, error = 16.0f * 1e-4f / width + 1e-5f * steps + 1e-5f;
  if (steps - error >= 255.0f) return 255;
  const float low = std::floor(steps - error + 0.5f), high = std::floor(steps + error + 0.5f);
  if (low == high && high <= 255.0f) return uint8_t(high);
  return uint8_t(std::lround(std::min(16.0f * std::acos(cosine) / width, 255.0f)));
}

}  // namespace epi::render::detail

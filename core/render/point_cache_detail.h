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

}  // namespace epi::render::detail

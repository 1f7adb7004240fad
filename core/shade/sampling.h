// Random numbers and warps for Monte-Carlo shading. Streams are keyed by what is being
// computed (seed, pixel position bits, sample index), never by thread, so results do not
// depend on the thread count or on how requests are batched.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace epi {

// SplitMix64 finaliser: a good 64-bit mix.
inline uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
inline uint64_t hash_combine(uint64_t a, uint64_t b) { return mix64(a ^ (b + 0x9e3779b97f4a7c15ull + (a << 6) + (a >> 2))); }

// Key of a shading request: the seed and the exact bits of its pixel position.
inline uint64_t request_key(uint64_t seed, float x, float y) {
  return hash_combine(hash_combine(mix64(seed), std::bit_cast<uint32_t>(x)), std::bit_cast<uint32_t>(y));
}

// PCG32 (XSH-RR), seeded by a key.
class Rng {
 public:
  explicit Rng(uint64_t key) : state_(mix64(key) + 0x853c49e6748fea9bull) { next(); }
  Rng(uint64_t key, uint64_t stream, uint64_t index) : Rng(hash_combine(hash_combine(key, stream), index)) {}
  uint32_t next() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ull + 1442695040888963407ull;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  float uniform() { return float(next() >> 8) * 0x1p-24f; }  // [0, 1)

 private:
  uint64_t state_;
};

// An orthonormal basis around a unit normal (Duff et al. 2017).
struct Frame {
  glm::vec3 t, b, n;
  explicit Frame(const glm::vec3& normal) : n(normal) {
    float sign = std::copysign(1.0f, normal.z);
    float a = -1.0f / (sign + normal.z);
    float c = normal.x * normal.y * a;
    t = glm::vec3(1.0f + sign * normal.x * normal.x * a, sign * c, -sign * normal.x);
    b = glm::vec3(c, sign + normal.y * normal.y * a, -normal.y);
  }
  glm::vec3 to_world(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

// Cosine-weighted direction in the local frame (z up); pdf = cos / pi.
inline glm::vec3 sample_cosine_hemisphere(float u1, float u2) {
  float r = std::sqrt(u1), phi = 2.0f * float(M_PI) * u2;
  return glm::vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1)));
}

// Uniform point on a triangle as barycentric weights of (v0, v1, v2).
inline glm::vec3 sample_triangle(float u1, float u2) {
  float s = std::sqrt(u1);
  return glm::vec3(1.0f - s, s * (1.0f - u2), s * u2);
}

}  // namespace epi

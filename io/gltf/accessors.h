// Bounds-checked reading of glTF accessors: every byte read is proven to lie inside its buffer.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <tiny_gltf.h>

namespace epi::gltf {

// Each throws std::runtime_error("accessor N: <problem>") when the accessor, its buffer view or
// its buffer is out of range, too short, of the wrong type, sparse, or holds non-finite values.
std::vector<glm::vec3> read_vec3(const tinygltf::Model& model, int accessor);    // VEC3 of FLOAT
std::vector<uint32_t> read_indices(const tinygltf::Model& model, int accessor);  // SCALAR, unsigned byte/short/int

// Checks one buffer view against its buffer (index, offset, length, stride).
void check_buffer_view(const tinygltf::Model& model, int buffer_view);

}  // namespace epi::gltf

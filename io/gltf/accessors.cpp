#include "accessors.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace epi::gltf {

namespace {

[[noreturn]] void fail(int accessor, const std::string& problem) {
  throw std::runtime_error("accessor " + std::to_string(accessor) + ": " + problem);
}

// Where an accessor's elements are.
struct ElementView {
  const unsigned char* data = nullptr;
  size_t stride = 0;
  size_t count = 0;
};

ElementView view_accessor(const tinygltf::Model& model, int index, int expected_type, size_t element_bytes) {
  if (index < 0 || size_t(index) >= model.accessors.size())
    throw std::runtime_error("accessor index " + std::to_string(index) + " out of range (" +
                             std::to_string(model.accessors.size()) + " accessors)");
  const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
  if (accessor.sparse.isSparse) fail(index, "sparse accessors are not supported");
  if (accessor.type != expected_type) fail(index, "wrong element type");
  ElementView view;
  view.count = accessor.count;
  // glTF allows an accessor without buffer view (all zeros, for sparse data); with sparse
  // unsupported it would only be a large block of zeros, so it is refused.
  if (accessor.bufferView < 0) fail(index, "has no buffer view (zero-filled accessors are not supported)");
  check_buffer_view(model, accessor.bufferView);
  const tinygltf::BufferView& buffer_view = model.bufferViews[size_t(accessor.bufferView)];
  view.stride = buffer_view.byteStride != 0 ? buffer_view.byteStride : element_bytes;
  if (view.stride < element_bytes)
    fail(index, "byteStride " + std::to_string(view.stride) + " is smaller than an element (" +
                    std::to_string(element_bytes) + " bytes)");
  if (view.count > 0) {
    // All terms are below 2^31 (checked JSON), so the products fit in 64 bits.
    const uint64_t end = uint64_t(accessor.byteOffset) + uint64_t(view.count - 1) * view.stride + element_bytes;
    if (end > buffer_view.byteLength)
      fail(index, "reads " + std::to_string(end) + " bytes, past the end of buffer view " +
                      std::to_string(accessor.bufferView) + " (" + std::to_string(buffer_view.byteLength) + " bytes)");
  }
  const tinygltf::Buffer& buffer = model.buffers[size_t(buffer_view.buffer)];
  view.data = buffer.data.data() + buffer_view.byteOffset + accessor.byteOffset;
  return view;
}

}  // namespace

void check_buffer_view(const tinygltf::Model& model, int index) {
  const std::string name = "buffer view " + std::to_string(index);
  if (index < 0 || size_t(index) >= model.bufferViews.size())
    throw std::runtime_error("buffer view index " + std::to_string(index) + " out of range (" +
                             std::to_string(model.bufferViews.size()) + " buffer views)");
  const tinygltf::BufferView& view = model.bufferViews[size_t(index)];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    throw std::runtime_error(name + ": buffer index " + std::to_string(view.buffer) + " out of range (" +
                             std::to_string(model.buffers.size()) + " buffers)");
  const size_t buffer_bytes = model.buffers[size_t(view.buffer)].data.size();
  if (uint64_t(view.byteOffset) + view.byteLength > buffer_bytes)
    throw std::runtime_error(name + ": bytes " + std::to_string(view.byteOffset) + ".." +
                             std::to_string(uint64_t(view.byteOffset) + view.byteLength) +
                             " lie past the end of buffer " + std::to_string(view.buffer) + " (" +
                             std::to_string(buffer_bytes) + " bytes)");
  if (view.byteStride != 0 && (view.byteStride < 4 || view.byteStride > 252 || view.byteStride % 4 != 0))
    throw std::runtime_error(name + ": byteStride " + std::to_string(view.byteStride) +
                             " must be a multiple of 4 in [4, 252]");
}

std::vector<glm::vec3> read_vec3(const tinygltf::Model& model, int index) {
  const ElementView view = view_accessor(model, index, TINYGLTF_TYPE_VEC3, 12);
  if (model.accessors[size_t(index)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
    fail(index, "expected VEC3 of FLOAT components");
  std::vector<glm::vec3> values(view.count);
  for (size_t i = 0; i < view.count; ++i) {
    float xyz[3];
    std::memcpy(xyz, view.data + i * view.stride, sizeof xyz);
    if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
      fail(index, "element " + std::to_string(i) + " is not finite");
    values[i] = glm::vec3(xyz[0], xyz[1], xyz[2]);
  }
  return values;
}

std::vector<uint32_t> read_indices(const tinygltf::Model& model, int index) {
  const int component = index >= 0 && size_t(index) < model.accessors.size()
                            ? model.accessors[size_t(index)].componentType
                            : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  size_t bytes = 0;
  if (component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE)
    bytes = 1;
  else if (component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
    bytes = 2;
  else if (component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    bytes = 4;
  else
    fail(index, "indices must be unsigned byte, short or int (componentType " + std::to_string(component) + ")");
  const ElementView view = view_accessor(model, index, TINYGLTF_TYPE_SCALAR, bytes);
  std::vector<uint32_t> values(view.count);
  for (size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    if (bytes == 1) {
      values[i] = p[0];
    } else if (bytes == 2) {
      uint16_t v;
      std::memcpy(&v, p, 2);
      values[i] = v;
    } else {
      std::memcpy(&values[i], p, 4);
    }
  }
  return values;
}

}  // namespace epi::gltf

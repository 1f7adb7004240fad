// libFuzzer target: the GLB container (io/gltf): the input is a .glb file after its 4-byte
// magic "glTF", which the target puts back, so every input exercises the header and chunk
// checks and then the JSON and buffers inside. docs/reliability.md.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_file.h"
#include "load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes = {'g', 'l', 'T', 'F'};
  bytes.insert(bytes.end(), data, data + size);
  const epi::fuzz::ScratchFile file("glb", bytes.data(), bytes.size());
  epi::LoadOptions options;
  options.memory_limit = uint64_t(256) << 20;
  try {
    epi::load_scene(file.path(), options);
  } catch (const epi::SceneLoadError&) {
  }
  return 0;
}

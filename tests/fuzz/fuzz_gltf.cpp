// libFuzzer target: the glTF loader and its validation (io/gltf) on arbitrary bytes as a .gltf
// file. Any outcome but a scene or a SceneLoadError (another exception, a crash, a sanitizer
// report, a hang) is a finding. docs/reliability.md.
#include <cstddef>
#include <cstdint>

#include "fuzz_file.h"
#include "load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const epi::fuzz::ScratchFile file("gltf", data, size);
  epi::LoadOptions options;
  options.memory_limit = uint64_t(256) << 20;  // subdivision beyond ~450k triangles is refused
  try {
    epi::load_scene(file.path(), options);
  } catch (const epi::SceneLoadError&) {
  }
  return 0;
}

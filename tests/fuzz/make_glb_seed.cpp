// Seeds for fuzz_glb: a .gltf whose buffers are data: URIs rewritten as a .glb (first buffer in
// the BIN chunk), written without its 4-byte magic (fuzz_glb puts it back).
//   make_glb_seed IN.gltf OUT
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace {

std::vector<uint8_t> base64_decode(const std::string& text) {
  std::vector<uint8_t> out;
  uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    int v = c >= 'A' && c <= 'Z' ? c - 'A' : c >= 'a' && c <= 'z' ? c - 'a' + 26 : c >= '0' && c <= '9' ? c - '0' + 52
          : c == '+' ? 62 : c == '/' ? 63 : -1;
    if (v < 0) continue;
    bits = (bits << 6) | uint32_t(v);
    if ((count += 6) >= 8) out.push_back(uint8_t(bits >> (count -= 8)));
  }
  return out;
}

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(uint8_t(v >> (8 * k)));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) return std::fprintf(stderr, "usage: make_glb_seed IN.gltf OUT\n"), 2;
  std::ifstream in(argv[1]);
  nlohmann::json doc = nlohmann::json::parse(in);
  std::vector<uint8_t> bin;
  if (doc.contains("buffers") && !doc["buffers"].empty()) {
    const std::string uri = doc["buffers"][0].value("uri", "");
    bin = base64_decode(uri.substr(uri.find(',') + 1));
    doc["buffers"][0].erase("uri");
  }
  std::string text = doc.dump();
  while (text.size() % 4) text += ' ';
  while (bin.size() % 4) bin.push_back(0);
  std::vector<uint8_t> glb;
  put_u32(glb, 2);
  put_u32(glb, uint32_t(12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size())));
  put_u32(glb, uint32_t(text.size()));
  put_u32(glb, 0x4E4F534Au);
  glb.insert(glb.end(), text.begin(), text.end());
  if (!bin.empty()) {
    put_u32(glb, uint32_t(bin.size()));
    put_u32(glb, 0x004E4942u);
    glb.insert(glb.end(), bin.begin(), bin.end());
  }
  std::ofstream(argv[2], std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
  return 0;
}

#include "gif.h"

#include <gif_lib.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <stdexcept>

namespace epi::vis {

namespace {

int bin(const uint8_t* p) { return (p[0] >> 3) << 10 | (p[1] >> 3) << 5 | (p[2] >> 3); }

struct GifFile {
  GifFileType* gif = nullptr;
  ~GifFile() {
    int error = 0;
    if (gif) EGifCloseFile(gif, &error);
  }
};

}  // namespace

void write_gif(const std::string& file, const std::vector<std::vector<uint8_t>>& frames, int width, int height,
               int delay_centiseconds) {
  // Palette: the most frequent 15-bit colours; the lookup maps every bin to the nearest entry.
  std::vector<uint64_t> count(32768, 0);
  for (const auto& f : frames)
    for (size_t i = 0; i < f.size(); i += 3) ++count[size_t(bin(&f[i]))];
  std::vector<int> order(32768);
  std::iota(order.begin(), order.end(), 0);
  std::partial_sort(order.begin(), order.begin() + 256, order.end(), [&](int a, int b) { return count[size_t(a)] > count[size_t(b)]; });
  std::array<GifColorType, 256> colors{};
  int used = 0;
  for (int k = 0; k < 256 && count[size_t(order[size_t(k)])] > 0; ++k, ++used) {
    const int b = order[size_t(k)];
    colors[size_t(k)] = {GifByteType(((b >> 10) & 31) * 255 / 31), GifByteType(((b >> 5) & 31) * 255 / 31), GifByteType((b & 31) * 255 / 31)};
  }
  used = std::max(used, 2);
  std::vector<uint8_t> lookup(32768);
  for (int b = 0; b < 32768; ++b) {
    const int r = ((b >> 10) & 31) * 255 / 31, g = ((b >> 5) & 31) * 255 / 31, bl = (b & 31) * 255 / 31;
    int best = 0, best_d = 1 << 30;
    for (int k = 0; k < used; ++k) {
      const int dr = r - colors[size_t(k)].Red, dg = g - colors[size_t(k)].Green, db = bl - colors[size_t(k)].Blue;
      const int d = 3 * dr * dr + 4 * dg * dg + 2 * db * db;
      if (d < best_d) best_d = d, best = k;
    }
    lookup[size_t(b)] = uint8_t(best);
  }

  int error = 0;
  GifFile out;
  out.gif = EGifOpenFileName(file.c_str(), false, &error);
  if (!out.gif) throw std::runtime_error(file + ": " + GifErrorString(error));
  auto fail = [&] { throw std::runtime_error(file + ": " + GifErrorString(out.gif->Error)); };
  ColorMapObject* map = GifMakeMapObject(256, colors.data());
  EGifSetGifVersion(out.gif, true);
  const int put = EGifPutScreenDesc(out.gif, width, height, 8, 0, map);
  GifFreeMapObject(map);
  if (put == GIF_ERROR) fail();
  // Loop forever (NETSCAPE2.0 application extension).
  const GifByteType loop[3] = {1, 0, 0};
  if (EGifPutExtensionLeader(out.gif, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
      EGifPutExtensionBlock(out.gif, 11, "NETSCAPE2.0") == GIF_ERROR || EGifPutExtensionBlock(out.gif, 3, loop) == GIF_ERROR ||
      EGifPutExtensionTrailer(out.gif) == GIF_ERROR)
    fail();
  std::vector<GifPixelType> line(static_cast<size_t>(width));
  for (const auto& f : frames) {
    GraphicsControlBlock gcb{DISPOSAL_UNSPECIFIED, false, delay_centiseconds, NO_TRANSPARENT_COLOR};
    GifByteType ext[4];
    const size_t n = EGifGCBToExtension(&gcb, ext);
    if (EGifPutExtension(out.gif, GRAPHICS_EXT_FUNC_CODE, int(n), ext) == GIF_ERROR) fail();
    if (EGifPutImageDesc(out.gif, 0, 0, width, height, false, nullptr) == GIF_ERROR) fail();
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) line[size_t(x)] = lookup[size_t(bin(&f[(size_t(y) * size_t(width) + size_t(x)) * 3]))];
      if (EGifPutLine(out.gif, line.data(), width) == GIF_ERROR) fail();
    }
  }
  const int closed = EGifCloseFile(out.gif, &error);
  out.gif = nullptr;
  if (closed == GIF_ERROR) throw std::runtime_error(file + ": " + GifErrorString(error));
}

}  // namespace epi::vis

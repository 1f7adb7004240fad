#include "image_io.h"

#include <gtest/gtest.h>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <ctime>
#include <filesystem>
#include <fstream>

#include <glm/glm.hpp>

namespace fs = std::filesystem;
using namespace epi;

namespace {

fs::path temp_dir() {
  fs::path dir = fs::temp_directory_path() / ("epi-image-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

RgbImage gradient(int w, int h) {
  RgbImage image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = image.at(x, y);
      p[0] = float(x) / w * 4.0f;  // HDR values above 1
      p[1] = float(y) / h;
      p[2] = 1e-4f * float(x + y);
    }
  return image;
}

}  // namespace

TEST(ImageIO, ExrRoundTripKeepsLinearFloatsExactly) {
  const fs::path file = temp_dir() / "round.exr";
  const RgbImage image = gradient(37, 19);
  write_image(file, image);
  const RgbImage back = read_image(file);
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 19);
  EXPECT_EQ(back.pixels, image.pixels);
}

TEST(ImageIO, PngIsSrgbEncodedAfterTheToneMap) {
  const fs::path file = temp_dir() / "round.png";
  RgbImage image(4, 1);
  image.at(0, 0)[0] = 0.5f;   // below the knee: unchanged, linear 0.5 -> sRGB 188
  image.at(1, 0)[0] = 7.0f;   // x = 31: 0.8 + 0.2 * 31/32
  image.at(2, 0)[0] = -1.0f;  // negative: 0
  image.at(3, 0)[0] = 1.0f;   // x = 1: 0.9
  write_image(file, image);
  const RgbImage back = read_image(file);
  EXPECT_NEAR(back.at(0, 0)[0], 0.5f, 0.004f);
  EXPECT_NEAR(back.at(1, 0)[0], 0.99375f, 0.006f);
  EXPECT_FLOAT_EQ(back.at(2, 0)[0], 0.0f);
  EXPECT_NEAR(back.at(3, 0)[0], 0.9f, 0.006f);
}

TEST(ToneMap, KnownValues) {
  auto map = [](glm::vec3 in, float stops) {
    glm::vec3 out;
    tone_map(&in.x, stops, &out.x);
    return out;
  };
  // Identity up to the knee, whatever the channel.
  EXPECT_EQ(map({0.1f, 0.5f, 0.8f}, 0.0f), glm::vec3(0.1f, 0.5f, 0.8f));
  // Exposure: one stop doubles, minus one halves.
  EXPECT_EQ(map({0.1f, 0.2f, 0.3f}, 1.0f), glm::vec3(0.2f, 0.4f, 0.6f));
  EXPECT_EQ(map({0.4f, 0.2f, 0.0f}, -1.0f), glm::vec3(0.2f, 0.1f, 0.0f));
  // The shoulder on the largest channel: 1 -> 0.9, 1.8 -> 0.8 + 0.2 * 5/6, and the channels keep their ratios.
  const glm::vec3 one = map({1.0f, 0.5f, 0.25f}, 0.0f);
  EXPECT_NEAR(one.x, 0.9f, 1e-6f);
  EXPECT_NEAR(one.y / one.x, 0.5f, 1e-6f);
  EXPECT_NEAR(one.z / one.x, 0.25f, 1e-6f);
  EXPECT_NEAR(map({0.0f, 1.8f, 0.0f}, 0.0f).y, 0.8f + 0.2f * 5.0f / 6.0f, 1e-6f);
  // Continuous with slope 1 at the knee; monotonic; at most 1; +inf maps to 1.
  const float k = kShoulderKnee;
  EXPECT_NEAR((map({k + 1e-3f, 0, 0}, 0).x - map({k, 0, 0}, 0).x) / 1e-3f, 1.0f, 1e-2f);
  float previous = 0.0f;
  for (float v = 0.0f; v < 1000.0f; v = v * 1.3f + 0.01f) {
    const float m = map({v, 0, 0}, 0).x;
    EXPECT_GE(m, previous) << v;
    EXPECT_LE(m, 1.0f) << v;
    previous = m;
  }
  EXPECT_NEAR(map({INFINITY, 0.0f, 0.0f}, 0.0f).x, 1.0f, 1e-6f);
  // Negative and NaN channels become 0.
  EXPECT_EQ(map({-2.0f, NAN, 0.5f}, 0.0f), glm::vec3(0.0f, 0.0f, 0.5f));
}

// The largest finite and infinite colours map to white whether or not the thread flushes
// denormals to zero (oneTBB's tasks here do): their shoulder gain is below the least normal
// float. tone_map_pixels gives tone_map's bits.
TEST(ToneMap, HugeColoursAreWhiteOnAThreadThatFlushesDenormals) {
  const float max = std::numeric_limits<float>::max();
  const float in[] = {max, 0.5f, 0.0f, INFINITY, INFINITY, 1e38f, 0.3f, 2.0f, NAN};
  auto check = [&](const char* mode) {
    float one[9], run[9];
    for (int p = 0; p < 3; ++p) tone_map(in + 3 * p, 0.0f, one + 3 * p);
    tone_map_pixels(in, 3, 0.0f, run);
    EXPECT_EQ(one[0], 1.0f) << mode;
    EXPECT_EQ(one[3], 1.0f) << mode;
    EXPECT_EQ(one[4], 1.0f) << mode;
    EXPECT_NEAR(one[5], 1e38f / max, 1e-6f) << mode;
    for (int c = 0; c < 9; ++c) EXPECT_EQ(std::bit_cast<uint32_t>(run[c]), std::bit_cast<uint32_t>(one[c])) << mode << " " << c;
  };
  check("denormals kept");
#if defined(__SSE__)
  const unsigned int csr = _mm_getcsr();
  _mm_setcsr(csr | 0x8040u);  // FTZ and DAZ
  check("denormals flushed");
  _mm_setcsr(csr);
#endif
}

TEST(ImageIO, ExposureAppliesToPngOnlyNotExr) {
  const fs::path dir = temp_dir();
  RgbImage image(1, 1);
  image.at(0, 0)[0] = 0.1f, image.at(0, 0)[1] = 0.2f, image.at(0, 0)[2] = 0.3f;
  ImageWriteOptions two_stops;
  two_stops.exposure = 2.0f;
  write_image(dir / "e.exr", image, two_stops);
  write_image(dir / "e.png", image, two_stops);
  EXPECT_EQ(read_image(dir / "e.exr").pixels, image.pixels);
  // (0.4, 0.8, 1.2): the largest, 1.2, has x = 2 and maps to 0.8 + 0.2 * 2/3; all three scaled by that gain.
  const float gain = (0.8f + 0.2f * 2.0f / 3.0f) / 1.2f;
  const RgbImage png = read_image(dir / "e.png");
  EXPECT_NEAR(png.at(0, 0)[0], 0.4f * gain, 0.004f);
  EXPECT_NEAR(png.at(0, 0)[1], 0.8f * gain, 0.006f);
  EXPECT_NEAR(png.at(0, 0)[2], 1.2f * gain, 0.006f);
}

TEST(ImageIO, BadPathsFailBeforeWritingAndNameTheFile) {
  const RgbImage image = gradient(4, 4);
  const fs::path unknown = temp_dir() / "out.xyz";
  try {
    write_image(unknown, image);
    FAIL() << "expected ImageIOError";
  } catch (const ImageIOError& e) {
    EXPECT_NE(std::string(e.what()).find(unknown.string()), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("unsupported image extension"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(unknown));
  EXPECT_THROW(write_image(temp_dir() / "no" / "such" / "dir.png", image), ImageIOError);
  EXPECT_THROW(read_image(temp_dir() / "missing.exr"), ImageIOError);
}

TEST(ImageIO, NoTemporaryFilesLeftBehind) {
  const fs::path dir = temp_dir() / "clean";
  fs::create_directories(dir);
  write_image(dir / "a.exr", gradient(8, 8));
  write_image(dir / "a.png", gradient(8, 8));
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(entry.path().filename().string().rfind(".tmp-", 0), std::string::npos);
  }
  EXPECT_EQ(files, 2);
}

TEST(ImageIO, EqualImagesGiveEqualFilesWithoutTimestamps) {
  const fs::path dir = temp_dir();
  char today[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(today, sizeof today, "%Y:%m:%d", std::localtime(&now));
  for (const char* ext : {".exr", ".png"}) {
    write_image(dir / (std::string("first") + ext), gradient(16, 9));
    write_image(dir / (std::string("second") + ext), gradient(16, 9));
    std::ifstream a(dir / (std::string("first") + ext), std::ios::binary), b(dir / (std::string("second") + ext), std::ios::binary);
    const std::string bytes_a((std::istreambuf_iterator<char>(a)), {}), bytes_b((std::istreambuf_iterator<char>(b)), {});
    EXPECT_FALSE(bytes_a.empty());
    EXPECT_TRUE(bytes_a == bytes_b) << ext;
    EXPECT_EQ(bytes_a.find(today), std::string::npos) << ext << " carries a timestamp";
  }
}

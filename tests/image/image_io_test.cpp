#include "image_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>

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

TEST(ImageIO, PngIsSrgbEncodedAndClamped) {
  const fs::path file = temp_dir() / "round.png";
  RgbImage image(3, 1);
  image.at(0, 0)[0] = 0.5f;   // linear 0.5 -> sRGB 188
  image.at(1, 0)[0] = 7.0f;   // clamped to 1
  image.at(2, 0)[0] = -1.0f;  // clamped to 0
  write_image(file, image);
  const RgbImage back = read_image(file);
  EXPECT_NEAR(back.at(0, 0)[0], 0.5f, 0.004f);
  EXPECT_FLOAT_EQ(back.at(1, 0)[0], 1.0f);
  EXPECT_FLOAT_EQ(back.at(2, 0)[0], 0.0f);
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

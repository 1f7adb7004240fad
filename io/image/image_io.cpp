#include "image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unistd.h>

namespace epi {
namespace {

namespace fs = std::filesystem;

std::string lower_extension(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

constexpr std::array kLinearExtensions = {".exr", ".hdr"};
constexpr std::array kEightBitExtensions = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".ppm", ".bmp", ".tga"};

[[noreturn]] void fail(const fs::path& file, const std::string& problem) {
  throw ImageIOError(file.string() + ": " + problem);
}

}  // namespace

float linear_to_srgb(float v) {
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgb_to_linear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

namespace {

// One pixel of tone_map, the exposure's factor given.
inline void tone_map_scaled(const float* linear, float scale, float* display) {
  float rgb[3];
  for (int c = 0; c < 3; ++c) {
    const float v = linear[c] * scale;
    // Negative, NaN and -inf to 0; +inf to the largest float.
    rgb[c] = v > 0.0f ? std::min(v, std::numeric_limits<float>::max()) : 0.0f;
  }
  const float m = std::max({rgb[0], rgb[1], rgb[2]});
  float gain = 1.0f;
  if (m > kShoulderKnee) {
    const double x = (double(m) - kShoulderKnee) / (1.0 - kShoulderKnee);
    const double shoulder = kShoulderKnee + (1.0 - kShoulderKnee) * (x / (1.0 + x));
    const double g = shoulder / double(m);
    if (g < double(std::numeric_limits<float>::min())) {
      // m above about 3e37: the gain is no normal float, and where a thread flushes denormals
      // to zero (oneTBB's tasks here do: docs/performance.md, "Hole fill") the pixel turned
      // black instead of white; in double it does not depend on the thread.
      for (int c = 0; c < 3; ++c) display[c] = std::clamp(float(double(rgb[c]) * g), 0.0f, 1.0f);
      return;
    }
    gain = float(g);
  }
  for (int c = 0; c < 3; ++c) display[c] = std::clamp(rgb[c] * gain, 0.0f, 1.0f);
}

}  // namespace

void tone_map(const float* linear, float exposure_stops, float* display) {
  tone_map_scaled(linear, std::exp2(exposure_stops), display);
}

void tone_map_pixels(const float* linear, size_t pixels, float exposure_stops, float* display) {
  const float scale = std::exp2(exposure_stops);
  for (size_t i = 0; i < pixels; ++i) tone_map_scaled(linear + 3 * i, scale, display + 3 * i);
}

void inverse_tone_map(const float* display, float* linear) {
  const float m = std::max({display[0], display[1], display[2]});
  float gain = 1.0f;
  if (m > kShoulderKnee) {
    // shoulder = k + (1 - k) x / (1 + x) with x = (m_linear - k) / (1 - k), solved for m_linear.
    const double y = std::min((double(m) - kShoulderKnee) / (1.0 - kShoulderKnee), 1.0 - 1e-7);
    const double x = y / (1.0 - y);
    gain = float((kShoulderKnee + (1.0 - kShoulderKnee) * x) / double(m));
  }
  for (int c = 0; c < 3; ++c) linear[c] = std::max(display[c], 0.0f) * gain;
}

bool is_linear_format(const fs::path& file) {
  const std::string ext = lower_extension(file);
  return std::find(kLinearExtensions.begin(), kLinearExtensions.end(), ext) != kLinearExtensions.end();
}

void check_output_path(const fs::path& file) {
  const std::string ext = lower_extension(file);
  const bool known = is_linear_format(file) ||
                     std::find(kEightBitExtensions.begin(), kEightBitExtensions.end(), ext) != kEightBitExtensions.end();
  if (!known) fail(file, "unsupported image extension '" + ext + "' (use .exr for linear HDR, .png for 8-bit sRGB)");
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) fail(file, "output folder '" + folder.string() + "' does not exist");
  if (fs::is_directory(file, ec)) fail(file, "is a folder");
}

void write_image(const fs::path& file, const RgbImage& image, const ImageWriteOptions& options) {
  check_output_path(file);
  if (image.width <= 0 || image.height <= 0) fail(file, "empty image");
  const bool linear = is_linear_format(file);
  // Temporary name keeps the extension, so OpenImageIO picks the right writer.
  const fs::path temporary = file.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" + file.filename().string());
  auto out = OIIO::ImageOutput::create(file.string());
  if (!out) fail(file, "no writer for this format: " + OIIO::geterror());
  OIIO::ImageSpec spec(image.width, image.height, 3, linear ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!linear) spec.attribute("oiio:ColorSpace", "sRGB");
  spec.attribute("DateTime", "");  // no timestamp: the same image always gives the same bytes
  bool ok = out->open(temporary.string(), spec);
  if (ok) {
    if (linear) {
      ok = out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
    } else {
      std::vector<uint8_t> bytes(image.pixels.size());
      for (size_t i = 0; i < bytes.size(); i += 3) {
        float display[3];
        tone_map(&image.pixels[i], options.exposure, display);
        for (int c = 0; c < 3; ++c) bytes[i + c] = uint8_t(std::lround(linear_to_srgb(display[c]) * 255.0f));
      }
      ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    }
    ok = out->close() && ok;
  }
  if (!ok) {
    std::error_code ec;
    fs::remove(temporary, ec);
    fail(file, "could not write: " + out->geterror());
  }
  std::error_code ec;
  fs::rename(temporary, file, ec);
  if (ec) {
    fs::remove(temporary, ec);
    fail(file, "could not move the finished image into place: " + ec.message());
  }
}

RgbImage read_image(const fs::path& file) {
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) fail(file, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1) fail(file, "empty image");
  const bool eight_bit = spec.format.basesize() == 1;
  std::vector<float> all(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data())) fail(file, in->geterror());
  RgbImage image(spec.width, spec.height);
  for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
    for (int c = 0; c < 3; ++c) {
      float v = all[p * spec.nchannels + std::min(c, spec.nchannels - 1)];
      image.pixels[p * 3 + c] = eight_bit ? srgb_to_linear(v) : v;
    }
  return image;
}

}  // namespace epi

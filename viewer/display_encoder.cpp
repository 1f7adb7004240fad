// display_encoder.h: the encoding for every Highway target (foreach_target.h compiles this file
// once per target), the table and the parallel runs once.
#include "display_encoder.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "image_io.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "display_encoder.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace epi::viewer {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// A vector of pixels at a time. The tone map in lanes: below the shoulder's knee the gain is 1, so
// the channels cleaned of negatives, NaNs and infinities are the display values; a pixel above
// it goes through tone_map_pixels (the shoulder in double), as does the tail. The level's index
// as display_level computes it: a product, then a sum (this file is compiled without
// contraction), truncated to int32.
void EncodeDisplayPixels(const float* HWY_RESTRICT linear, size_t pixels, float exposure_stops,
                         const uint32_t* HWY_RESTRICT levels, uint32_t* HWY_RESTRICT rgba) {
  const hn::ScalableTag<float> d;
  const hn::RebindToSigned<decltype(d)> di;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  const size_t N = hn::Lanes(d);
  const V scale = hn::Set(d, std::exp2(exposure_stops)), zero = hn::Zero(d), largest = hn::Set(d, FLT_MAX);
  const V knee = hn::Set(d, kShoulderKnee), top = hn::Set(d, float(kDisplayLevels - 1)), half = hn::Set(d, 0.5f);
  const auto alpha = hn::Set(du, 0xff000000u);
  HWY_ALIGN float display[3 * hn::MaxLanes(d)];
  auto level = [&](V v) { return hn::GatherIndex(du, levels, hn::ConvertTo(di, hn::Add(hn::Mul(v, top), half))); };
  auto clean = [&](V v) {
    v = hn::Mul(v, scale);
    return hn::IfThenElse(hn::Gt(v, zero), hn::Min(v, largest), zero);
  };
  size_t i = 0;
  for (; i + N <= pixels; i += N) {
    V r, g, b;
    hn::LoadInterleaved3(d, linear + 3 * i, r, g, b);
    r = clean(r), g = clean(g), b = clean(b);
    if (!hn::AllFalse(d, hn::Gt(hn::Max(hn::Max(r, g), b), knee))) {
      hn::StoreInterleaved3(r, g, b, d, display);
      for (size_t k = 0; k < N; ++k)
        if (std::max({display[3 * k], display[3 * k + 1], display[3 * k + 2]}) > kShoulderKnee)
          tone_map_pixels(linear + 3 * (i + k), 1, exposure_stops, display + 3 * k);
      hn::LoadInterleaved3(d, display, r, g, b);
    }
    const auto word = hn::Or(hn::Or(level(r), hn::ShiftLeft<8>(level(g))), hn::Or(hn::ShiftLeft<16>(level(b)), alpha));
    hn::StoreU(word, du, rgba + i);
  }
  for (; i < pixels; ++i) {
    float one[3];
    tone_map_pixels(linear + 3 * i, 1, exposure_stops, one);
    rgba[i] = display_level(levels, one[0]) | display_level(levels, one[1]) << 8 | display_level(levels, one[2]) << 16 | 0xff000000u;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::viewer
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace epi::viewer {

HWY_EXPORT(EncodeDisplayPixels);

void encode_display_pixels(const float* linear, size_t pixels, float exposure_stops, const uint32_t* levels, uint32_t* rgba) {
  HWY_DYNAMIC_DISPATCH(EncodeDisplayPixels)(linear, pixels, exposure_stops, levels, rgba);
}

DisplayEncoder::DisplayEncoder() : levels_(kDisplayLevels) {
  for (size_t i = 0; i < levels_.size(); ++i) {
    const float v = float(i) / float(levels_.size() - 1);
    levels_[i] = uint32_t(std::lround(std::clamp(linear_to_srgb(v), 0.0f, 1.0f) * 255.0f));
  }
}

void DisplayEncoder::encode(const RgbImage& image, uint32_t* rgba) const {
  const size_t pixels = size_t(image.width) * size_t(image.height);
  const float stops = exposure_.load();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 4096), [&](const tbb::blocked_range<size_t>& r) {
    encode_display_pixels(&image.pixels[3 * r.begin()], r.size(), stops, levels_.data(), rgba + r.begin());
  });
}

}  // namespace epi::viewer
#endif  // HWY_ONCE

#include "render/staged_reconstruct.h"

#include <chrono>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "epi/antialias.h"
#include "epi/complex_filter.h"
#include "epi/fill.h"
#include "epi/geometry.h"
#include "epi/interpolate.h"
#include "epi/reachability.h"
#include "epi/rendercache.h"

namespace epi::render {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Rows in parallel, a few rows per task.
template <class RowFunction>
void for_rows(int height, RowFunction&& row) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) row(y);
  });
}

}  // namespace

void StagedReconstructor::run(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                              Reconstruction& out, ReconstructTimes& times) {
  if (epi.width != masks.width || epi.height != masks.height)
    throw std::invalid_argument("EPI and boundary masks differ in size");
  const int w = epi.width, h = epi.height;
  const size_t pixels = size_t(w) * size_t(h);
  if (out.image.width != w || out.image.height != h) out.image = RgbImage(w, h);
  out.priority.resize(pixels);
  if (interpolated_.width != w || interpolated_.height != h) interpolated_ = RgbImage(w, h);
  reach_.assign(pixels, 0);
  const bool epi_filter = s.filter == Filter::epi;
  const bool complex_on = epi_filter && s.complex_filter && masks.centre_lines;

  // Classification.
  auto t = Clock::now();
  tbb::combinable<ClassCounts> counts;
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
    const ClassCounts c = classify_rows(epi, masks, r.begin(), r.end());
    ClassCounts& local = counts.local();
    local.empty += c.empty, local.simple += c.simple, local.complex += c.complex;
    local.samples += c.samples, local.ambiguous += c.ambiguous;
  });
  out.counts = counts.combine([](ClassCounts a, const ClassCounts& b) {
    a.empty += b.empty, a.simple += b.simple, a.complex += b.complex, a.samples += b.samples, a.ambiguous += b.ambiguous;
    return a;
  });
  times.classify = ms_since(t);

  // Reachability, row by row in parallel over a read-only copy of the types (core/epi's reach_row:
  // windows of empty pixels take the fast path, the rest the full 24-offset computation).
  t = Clock::now();
  types_.resize(pixels);
  const TypeRows plane{types_.data(), w, h};  // filled below (epi only); interpolation's fallback reads it
  const EpiRows rows = whole_image_rows(epi, types_.data());
  if (epi_filter) {
    for_rows(h, [&](int y) {
      for (size_t i = epi.index(0, y); i < epi.index(0, y) + size_t(w); ++i) types_[i] = uint8_t(pixel_type(epi.cache[i]));
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& r) {
      std::vector<uint8_t> scratch(size_t(w) + 4);
      for (int y = r.begin(); y != r.end(); ++y) reach_row(plane, y, nullptr, nullptr, &reach_[epi.index(0, y)], scratch.data());
    });
    for_rows(h, [&](int y) {
      for (size_t i = epi.index(0, y); i < epi.index(0, y) + size_t(w); ++i) epi.cache[i] |= reach_[i];
    });
  }
  times.reachability = ms_since(t);

  // Interpolation and priority, then (epi) the fill step for pixels that reached no sample.
  t = Clock::now();
  found_.resize(pixels);
  for_rows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = epi.index(x, y);
      bool found = true;
      out.priority[i] = epi_filter ? interpolate_pixel(rows, x, y, reach_[i], interpolated_.at(x, y), &found)
                                   : rendercache_pixel(rows, x, y, interpolated_.at(x, y));
      found_[i] = found;
    }
  });
  const RgbImage* primary = &interpolated_;
  if (epi_filter && s.fill) {
    if (filled_.width != w || filled_.height != h) filled_ = RgbImage(w, h);
    for_rows(h, [&](int y) {
      const float* rows[5];
      const uint8_t* found_rows[5];
      for (int k = 0; k < 5; ++k) {
        const int ry = y - 2 + k;
        rows[k] = ry >= 0 && ry < h ? interpolated_.at(0, ry) : nullptr;
        found_rows[k] = ry >= 0 && ry < h ? &found_[epi.index(0, ry)] : nullptr;
      }
      for (int x = 0; x < w; ++x) fill_pixel(x, w, reach_[epi.index(x, y)], rows, found_rows, filled_.at(x, y));
    });
    primary = &filled_;
  }
  times.interpolate = ms_since(t);

  // Anti-aliasing of simple pixels (and the pass-through of the others).
  t = Clock::now();
  for_rows(h, [&](int y) {
    const float* primary_rows[3] = {y > 0 ? primary->at(0, y - 1) : nullptr, primary->at(0, y),
                                    y + 1 < h ? primary->at(0, y + 1) : nullptr};
    for (int x = 0; x < w; ++x) {
      const int type = pixel_type(epi.cache[epi.index(x, y)]);
      float* o = out.image.at(x, y);
      if (epi_filter && s.antialias && type_is_simple(type)) {
        antialias_pixel(rows, x, y, primary_rows, o);
      } else {
        const float* own = primary_rows[1] + 3 * x;
        o[0] = own[0], o[1] = own[1], o[2] = own[2];
      }
    }
  });
  times.antialias = ms_since(t);

  // Complex pixels.
  t = Clock::now();
  if (complex_on) {
    for_rows(h, [&](int y) {
      for (int x = 0; x < w; ++x)
        if (pixel_type(epi.cache[epi.index(x, y)]) == kTypeComplex)
          complex_pixel(rows, masks, x, y, primary->at(x, y), out.image.at(x, y));
    });
  }
  times.complex = ms_since(t);
}

}  // namespace epi::render

#include "epi/reconstruct.h"

#include <algorithm>
#include <memory>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "epi/antialias.h"
#include "epi/complex_filter.h"
#include "epi/fill.h"
#include "epi/geometry.h"
#include "epi/interpolate.h"
#include "epi/reachability.h"
#include "epi/rendercache.h"

namespace epi {

namespace {

void check_sizes(const EpiImage& epi, const BoundaryMasks& masks) {
  if (epi.width != masks.width || epi.height != masks.height)
    throw std::invalid_argument("EPI and boundary masks differ in size");
}

bool use_complex_filter(const ReconstructSettings& s, const BoundaryMasks& masks) {
  return s.filter == Filter::epi && s.complex_filter && masks.centre_lines;
}

// The final colour of pixel (x, y) from the interpolated rows around it.
void output_pixel(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s, int x, int y,
                  const float* const rows[3], float out[3]) {
  const float* own = rows[1] + 3 * x;
  if (s.filter == Filter::epi) {
    const int type = pixel_type(epi.cache[epi.index(x, y)]);
    if (type == kTypeComplex && use_complex_filter(s, masks)) return complex_pixel(epi, masks, x, y, own, out);
    if (s.antialias && type_is_simple(type)) return antialias_pixel(epi, x, y, rows, out);
  }
  out[0] = own[0], out[1] = own[1], out[2] = own[2];
}

float interpolate(const EpiImage& epi, TypePlane types, const ReconstructSettings& s, int x, int y, uint32_t reach,
                  float rgb[3], uint8_t* found) {
  bool f = true;
  const float p = s.filter == Filter::epi ? interpolate_pixel(epi, types, x, y, reach, rgb, &f)
                                          : rendercache_pixel(epi, x, y, rgb);
  *found = f;
  return p;
}

// The fill step for pixel (x, y): epi only (and when on); the render cache has its own prefilter.
void fill(const ReconstructSettings& s, int x, int width, uint32_t reach, const float* const rows[5],
          const uint8_t* const found[5], float out[3]) {
  if (s.filter == Filter::epi && s.fill) return fill_pixel(x, width, reach, rows, found, out);
  const float* own = rows[2] + 3 * x;
  out[0] = own[0], out[1] = own[1], out[2] = own[2];
}

}  // namespace

Reconstruction reconstruct_oracle(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s) {
  check_sizes(epi, masks);
  const int w = epi.width, h = epi.height;
  Reconstruction r{RgbImage(w, h), std::vector<float>(size_t(w) * size_t(h)), {}};
  std::vector<uint8_t> types(size_t(w) * size_t(h));
  r.counts = classify_rows(epi, masks, 0, h, types.data());
  const TypePlane type_plane{types.data(), w, h};
  if (s.filter == Filter::epi)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) epi.cache[epi.index(x, y)] |= reach_full(epi, x, y);
  RgbImage interpolated(w, h), filled(w, h);
  std::vector<uint8_t> found(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      r.priority[epi.index(x, y)] = interpolate(epi, type_plane, s, x, y, reach_mask(epi.cache[epi.index(x, y)]),
                                                interpolated.at(x, y), &found[epi.index(x, y)]);
  for (int y = 0; y < h; ++y) {
    const float* rows[5];
    const uint8_t* found_rows[5];
    for (int k = 0; k < 5; ++k) {
      const int ry = y - 2 + k;
      rows[k] = ry >= 0 && ry < h ? interpolated.at(0, ry) : nullptr;
      found_rows[k] = ry >= 0 && ry < h ? &found[epi.index(0, ry)] : nullptr;
    }
    for (int x = 0; x < w; ++x) fill(s, x, w, reach_mask(epi.cache[epi.index(x, y)]), rows, found_rows, filled.at(x, y));
  }
  for (int y = 0; y < h; ++y) {
    const float* rows[3] = {y > 0 ? filled.at(0, y - 1) : nullptr, filled.at(0, y),
                            y + 1 < h ? filled.at(0, y + 1) : nullptr};
    for (int x = 0; x < w; ++x) output_pixel(epi, masks, s, x, y, rows, r.image.at(x, y));
  }
  return r;
}

Reconstruction reconstruct_tiled(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                                 const Schedule& schedule) {
  Reconstruction r;
  reconstruct_tiled(epi, masks, s, schedule, r);
  return r;
}

void reconstruct_tiled(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                       const Schedule& schedule, Reconstruction& r) {
  check_sizes(epi, masks);
  const int w = epi.width, h = epi.height;
  if (r.image.width != w || r.image.height != h) r.image = RgbImage(w, h);
  r.priority.resize(size_t(w) * size_t(h));
  r.counts = {};
  if (w == 0 || h == 0) return;
  const int band_rows = std::max(1, schedule.rows_per_band);
  const int bands = (h + band_rows - 1) / band_rows;
  std::vector<ClassCounts> band_counts(static_cast<size_t>(bands));
  const std::unique_ptr<uint8_t[]> types(new uint8_t[size_t(w) * size_t(h)]);  // read-only in pass 2
  const TypePlane type_plane{types.get(), w, h};
  tbb::task_arena arena(schedule.threads > 0 ? schedule.threads : tbb::task_arena::automatic);

  // Pass 1: classification (1x1 footprint), every band writes only its own rows.
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const tbb::blocked_range<int>& range) {
      for (int b = range.begin(); b != range.end(); ++b)
        band_counts[size_t(b)] =
            classify_rows(epi, masks, b * band_rows, std::min(h, (b + 1) * band_rows), types.get());
    }, tbb::simple_partitioner());
  });
  for (const ClassCounts& c : band_counts) {
    r.counts.empty += c.empty, r.counts.simple += c.simple, r.counts.complex += c.complex;
    r.counts.samples += c.samples, r.counts.ambiguous += c.ambiguous;
  }

  // Pass 2: per band, rows stream through reachability -> interpolation -> fill -> output
  // with a few live rows of each (power-of-two rings); fill lags interpolation by two rows
  // and output lags fill by one. The band recomputes the halo rows it needs: three above and
  // three below for interpolation, one for fill.
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const tbb::blocked_range<int>& range) {
      std::vector<uint32_t> reach_ring(size_t(w) * 4);
      std::vector<float> interp_ring(size_t(w) * 3 * 8), fill_ring(size_t(w) * 3 * 4);
      std::vector<uint8_t> found_ring(size_t(w) * 8);
      std::vector<uint8_t> scratch(size_t(w) + 4);
      auto reach_row_ptr = [&](int y) { return &reach_ring[size_t(y & 3) * size_t(w)]; };
      auto interp_row = [&](int y) { return &interp_ring[size_t(y & 7) * size_t(w) * 3]; };
      auto found_row = [&](int y) { return &found_ring[size_t(y & 7) * size_t(w)]; };
      auto fill_row = [&](int y) { return &fill_ring[size_t(y & 3) * size_t(w) * 3]; };
      auto inside = [&](int y) { return y >= 0 && y < h; };
      for (int b = range.begin(); b != range.end(); ++b) {
        const int y0 = b * band_rows, y1 = std::min(h, y0 + band_rows);
        const int first = std::max(0, y0 - 3), last = std::min(h - 1, y1 + 2);
        const int fill_first = std::max(0, y0 - 1), fill_last = std::min(h - 1, y1);
        for (int y = first; y <= last + 3; ++y) {
          if (y <= last) {  // reachability and interpolation of row y
            uint32_t* reach = reach_row_ptr(y);
            const bool owned = y >= y0 && y < y1;
            if (s.filter == Filter::epi) {  // rows after the band's first two reuse the rows above
              const bool reuse = y >= first + 2;
              reach_row(type_plane, y, reuse ? reach_row_ptr(y - 1) : nullptr, reuse ? reach_row_ptr(y - 2) : nullptr,
                        reach, scratch.data());
              if (owned)
                for (int x = 0; x < w; ++x) epi.cache[epi.index(x, y)] |= reach[x];
            }
            float* colors = interp_row(y);
            uint8_t* found = found_row(y);
            for (int x = 0; x < w; ++x) {
              const float p = interpolate(epi, type_plane, s, x, y, reach[x], colors + 3 * x, found + x);
              if (owned) r.priority[epi.index(x, y)] = p;
            }
          }
          const int fy = y - 2;  // fill of row fy, once rows fy-2..fy+2 are interpolated
          if (fy >= fill_first && fy <= fill_last) {
            const float* rows[5];
            const uint8_t* found_rows[5];
            for (int k = 0; k < 5; ++k) {
              rows[k] = inside(fy - 2 + k) ? interp_row(fy - 2 + k) : nullptr;
              found_rows[k] = inside(fy - 2 + k) ? found_row(fy - 2 + k) : nullptr;
            }
            const uint32_t* reach = reach_row_ptr(fy);
            float* out = fill_row(fy);
            for (int x = 0; x < w; ++x) fill(s, x, w, reach[x], rows, found_rows, out + 3 * x);
          }
          const int oy = y - 3;  // output of row oy, once rows oy-1..oy+1 are filled
          if (oy >= y0 && oy < y1) {
            const float* rows[3] = {inside(oy - 1) ? fill_row(oy - 1) : nullptr, fill_row(oy),
                                    inside(oy + 1) ? fill_row(oy + 1) : nullptr};
            for (int x = 0; x < w; ++x) output_pixel(epi, masks, s, x, oy, rows, r.image.at(x, oy));
          }
        }
      }
    }, tbb::simple_partitioner());
  });
}

}  // namespace epi

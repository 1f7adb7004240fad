#include "epi/reconstruct.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
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

// The final colour of pixel (x, y) from the filled rows around it.
void output_pixel(const EpiRows& epi, const BoundaryMasks& masks, const ReconstructSettings& s, int x, int y,
                  const float* const rows[3], float out[3]) {
  const float* own = rows[1] + 3 * x;
  if (s.filter == Filter::epi) {
    const int type = epi.type_at(x, y);
    if (type == kTypeComplex && use_complex_filter(s, masks)) return complex_pixel(epi, masks, x, y, own, out);
    if (s.antialias && type_is_simple(type)) return antialias_pixel(epi, x, y, rows, out);
  }
  out[0] = own[0], out[1] = own[1], out[2] = own[2];
}

float interpolate(const EpiRows& epi, const ReconstructSettings& s, int x, int y, uint32_t reach, float rgb[3],
                  uint8_t* found) {
  bool f = true;
  const float p = s.filter == Filter::epi ? interpolate_pixel(epi, x, y, reach, rgb, &f) : rendercache_pixel(epi, x, y, rgb);
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

// The row stream of reconstruct_tiled: the row each stage produces lags the classified row by
// its lag; the footprint (rows around its own) fixes the lag (docs/epi.md, "Schedule").
//   stage            lag  footprint
//   classification   0    0: masks, input edge words (sample bits)
//   reach + interp   3    +-3: types, classified edge words (5x5 reach, 7x7 fallback)
//   fill             5    +-2: interpolated colours and found flags; own reach mask
//   output           6    +-1: filled colours, edge words (complex filter); own type, edge code
constexpr int kInterpLag = 3, kFillLag = 5, kOutputLag = 6;
constexpr int kHalo = kOutputLag;  // classified rows a band needs beyond its own, above and below
// Rings, indexed row & (size - 1): each holds the rows live at once.
constexpr int kClassRing = 8;   // edge words and types: rows y-7 (output's top) .. y
constexpr int kReachRing = 4;   // reach masks: fill's row (interp - 2) .. interp
constexpr int kInterpRing = 8;  // interpolated colours and found flags: interp - 4 .. interp
constexpr int kFillRing = 4;    // filled colours: output - 1 .. output + 1
static_assert(kClassRing >= kOutputLag + 2 && kInterpRing >= kFillLag - kInterpLag + 3 &&
              kReachRing >= kFillLag - kInterpLag + 1 && kFillRing >= 3);

// One thread's rings (reused across its bands).
struct Rings {
  explicit Rings(int w)
      : edge(size_t(w) * kClassRing), types(size_t(w) * kClassRing), reach(size_t(w) * kReachRing),
        found(size_t(w) * kInterpRing), interp(size_t(w) * 3 * kInterpRing), filled(size_t(w) * 3 * kFillRing),
        scratch(size_t(w) + 4) {}
  std::vector<uint16_t> edge;
  std::vector<uint8_t> types;
  std::vector<uint32_t> reach;
  std::vector<uint8_t> found;
  std::vector<float> interp, filled;
  std::vector<uint8_t> scratch;
};

}  // namespace

Reconstruction reconstruct_oracle(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s) {
  check_sizes(epi, masks);
  const int w = epi.width, h = epi.height;
  Reconstruction r{RgbImage(w, h), std::vector<float>(size_t(w) * size_t(h)), {}};
  std::vector<uint8_t> types(size_t(w) * size_t(h));
  r.counts = classify_rows(epi, masks, 0, h, types.data());
  const EpiRows rows = whole_image_rows(epi, types.data());
  if (s.filter == Filter::epi)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) epi.cache[epi.index(x, y)] |= reach_full(epi, x, y);
  RgbImage interpolated(w, h), filled(w, h);
  std::vector<uint8_t> found(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      r.priority[epi.index(x, y)] = interpolate(rows, s, x, y, reach_mask(epi.cache[epi.index(x, y)]),
                                                interpolated.at(x, y), &found[epi.index(x, y)]);
  for (int y = 0; y < h; ++y) {
    const float* interp_rows[5];
    const uint8_t* found_rows[5];
    for (int k = 0; k < 5; ++k) {
      const int ry = y - 2 + k;
      interp_rows[k] = ry >= 0 && ry < h ? interpolated.at(0, ry) : nullptr;
      found_rows[k] = ry >= 0 && ry < h ? &found[epi.index(0, ry)] : nullptr;
    }
    for (int x = 0; x < w; ++x)
      fill(s, x, w, reach_mask(epi.cache[epi.index(x, y)]), interp_rows, found_rows, filled.at(x, y));
  }
  for (int y = 0; y < h; ++y) {
    const float* filled_rows[3] = {y > 0 ? filled.at(0, y - 1) : nullptr, filled.at(0, y),
                                   y + 1 < h ? filled.at(0, y + 1) : nullptr};
    for (int x = 0; x < w; ++x) output_pixel(rows, masks, s, x, y, filled_rows, r.image.at(x, y));
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
  // Bands run in rounds, band b in round b % rounds: bands of one round lie at least
  // kHalo rows apart, so none reads an edge word (its halo's input) that another writes back.
  const int rounds = 1 + (kHalo + band_rows - 1) / band_rows;
  std::vector<ClassCounts> band_counts(static_cast<size_t>(bands));
  tbb::task_arena arena(schedule.threads > 0 ? schedule.threads : tbb::task_arena::automatic);
  tbb::enumerable_thread_specific<Rings> thread_rings([w] { return Rings(w); });
  auto inside = [h](int y) { return y >= 0 && y < h; };

  // Band b: rows stream through classification -> reachability and interpolation -> fill ->
  // output, each stage lagging classification by its kLag; only owned rows [y0, y1) are
  // written back (EPI planes, priority, image), halo rows are recomputed.
  auto run_band = [&](int b, Rings& ring) {
    auto edge_row = [&](int y) { return &ring.edge[size_t(y & (kClassRing - 1)) * size_t(w)]; };
    auto type_row = [&](int y) { return &ring.types[size_t(y & (kClassRing - 1)) * size_t(w)]; };
    auto reach_row_ptr = [&](int y) { return &ring.reach[size_t(y & (kReachRing - 1)) * size_t(w)]; };
    auto interp_row = [&](int y) { return &ring.interp[size_t(y & (kInterpRing - 1)) * size_t(w) * 3]; };
    auto found_row = [&](int y) { return &ring.found[size_t(y & (kInterpRing - 1)) * size_t(w)]; };
    auto fill_row = [&](int y) { return &ring.filled[size_t(y & (kFillRing - 1)) * size_t(w) * 3]; };
    const EpiRows rows{ring.edge.data(), ring.types.data(), epi.color.data(), w, h, kClassRing - 1};
    const int y0 = b * band_rows, y1 = std::min(h, y0 + band_rows);
    auto owned = [&](int y) { return y >= y0 && y < y1; };
    const int class_last = std::min(h - 1, y1 - 1 + kHalo);
    const int interp_first = std::max(0, y0 - (kOutputLag - kInterpLag)), interp_last = std::min(h - 1, y1 - 1 + kOutputLag - kInterpLag);
    const int fill_first = std::max(0, y0 - (kOutputLag - kFillLag)), fill_last = std::min(h - 1, y1 - 1 + kOutputLag - kFillLag);
    ClassCounts halo_counts;
    for (int y = std::max(0, y0 - kHalo); y < y1 + kOutputLag; ++y) {
      if (y <= class_last) {  // classification of row y
        const size_t i0 = epi.index(0, y);
        uint16_t* edge = edge_row(y);
        uint8_t* types = type_row(y);
        classify_row(masks, y, &epi.edge[i0], edge, types, owned(y) ? band_counts[size_t(b)] : halo_counts);
        if (owned(y))
          for (int x = 0; x < w; ++x) epi.edge[i0 + size_t(x)] = edge[x], epi.cache[i0 + size_t(x)] = uint32_t(types[x]) << bits::kTypeShift;
      }
      const int iy = y - kInterpLag;  // reachability and interpolation of row iy
      if (iy >= interp_first && iy <= interp_last) {
        uint32_t* reach = reach_row_ptr(iy);
        if (s.filter == Filter::epi) {  // rows after the band's first two reuse the rows above
          const bool reuse = iy >= interp_first + 2;
          reach_row(rows.type_rows(), iy, reuse ? reach_row_ptr(iy - 1) : nullptr,
                    reuse ? reach_row_ptr(iy - 2) : nullptr, reach, ring.scratch.data());
          if (owned(iy))
            for (int x = 0; x < w; ++x) epi.cache[epi.index(x, iy)] |= reach[x];
        }
        float* colors = interp_row(iy);
        uint8_t* found = found_row(iy);
        for (int x = 0; x < w; ++x) {
          const float p = interpolate(rows, s, x, iy, reach[x], colors + 3 * x, found + x);
          if (owned(iy)) r.priority[epi.index(x, iy)] = p;
        }
      }
      const int fy = y - kFillLag;  // fill of row fy
      if (fy >= fill_first && fy <= fill_last) {
        const float* interp_rows[5];
        const uint8_t* found_rows[5];
        for (int k = 0; k < 5; ++k) {
          interp_rows[k] = inside(fy - 2 + k) ? interp_row(fy - 2 + k) : nullptr;
          found_rows[k] = inside(fy - 2 + k) ? found_row(fy - 2 + k) : nullptr;
        }
        const uint32_t* reach = reach_row_ptr(fy);
        float* out = fill_row(fy);
        for (int x = 0; x < w; ++x) fill(s, x, w, reach[x], interp_rows, found_rows, out + 3 * x);
      }
      const int oy = y - kOutputLag;  // output of row oy
      if (owned(oy)) {
        const float* filled_rows[3] = {inside(oy - 1) ? fill_row(oy - 1) : nullptr, fill_row(oy),
                                       inside(oy + 1) ? fill_row(oy + 1) : nullptr};
        for (int x = 0; x < w; ++x) output_pixel(rows, masks, s, x, oy, filled_rows, r.image.at(x, oy));
      }
    }
  };
  arena.execute([&] {
    for (int round = 0; round < rounds; ++round) {
      const int count = (bands - round + rounds - 1) / rounds;
      tbb::parallel_for(tbb::blocked_range<int>(0, count, 1), [&](const tbb::blocked_range<int>& range) {
        Rings& ring = thread_rings.local();
        for (int k = range.begin(); k != range.end(); ++k) run_band(round + k * rounds, ring);
      }, tbb::simple_partitioner());
    }
  });
  for (const ClassCounts& c : band_counts) {
    r.counts.empty += c.empty, r.counts.simple += c.simple, r.counts.complex += c.complex;
    r.counts.samples += c.samples, r.counts.ambiguous += c.ambiguous;
  }
}

}  // namespace epi

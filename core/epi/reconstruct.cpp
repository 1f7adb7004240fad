#include "epi/reconstruct.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
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
#include "epi/tables.h"
#include "simd/row_kernels.h"

namespace epi {

// The side codes and descriptor relation (simd::RelationTables) from the side descriptors.
const simd::RelationTables& relation_tables() {
  static const simd::RelationTables tables = [] {
    const SideDescriptors& d = side_descriptors();
    simd::RelationTables t{};
    for (int type = 0; type < 16; ++type)
      for (int side = 0; side < 4; ++side) {
        const bool blocked = d.word[type] & kSideBlocked;
        const uint8_t descriptor = uint8_t((d.word[type] >> (2 * side)) & 3);
        t.from[side][type] = blocked ? 0x80 : uint8_t(4 * descriptor);
        t.to[side][type] = blocked ? 0x80 : descriptor;
      }
    for (int i = 0; i < 16; ++i) t.relation[i] = uint8_t(((i < 8 ? d.relation_lo : d.relation_hi) >> (4 * (i & 7))) & 15);
    return t;
  }();
  return tables;
}

namespace {

void check_sizes(const EpiImage& epi, const BoundaryMasks& masks) {
  if (epi.width != masks.width || epi.height != masks.height)
    throw std::invalid_argument("EPI and boundary masks differ in size");
}

bool use_complex_filter(const ReconstructSettings& s, const BoundaryMasks& masks) {
  return output_filter(s, masks.centre_lines, kTypeComplex) == OutputFilter::complex_filter;
}

float interpolate(const EpiRows& epi, const ReconstructSettings& s, int x, int y, uint32_t reach, float rgb[3],
                  uint8_t* found) {
  bool f = true;
  const float p = s.filter == Filter::epi ? interpolate_pixel(epi, x, y, reach, rgb, &f, s.blend_unreached_near_edges)
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


// A plane's rows: row y at slot y & mask (kWholeImage: whole-image planes; 2^k - 1: a ring).
template <typename T>
struct RowPlane {
  T* data = nullptr;
  size_t stride = 0;  // elements per row
  int mask = kWholeImage;
  T* row(int y) const { return data + size_t(y & mask) * stride; }
};

// A decoded row (Plane::samples): five padded planes (simd::InterpolateRow) of green, blue,
// usable, sampled and red (last: its padding is -0, and the fill stage reads the start of the
// zero row as zero colours and found flags), each with kPad pixels on the left and a
// vector's worth on the right.
size_t samples_plane(int w) { return size_t(w) + 2 * simd::kPad + 64; }
size_t samples_stride(int w) { return 5 * samples_plane(w); }

// The tables the vector kernels gather from, widened and packed by edge code (simd/row_kernels.h).
struct WideTables {
  uint32_t area_and_secondary[1024];
  uint64_t classify[1024];
};
const WideTables& wide_tables() {
  static const WideTables tables = [] {
    const EpiTables& t = epi_tables();
    WideTables w{};
    for (int k = 0; k < 1024; ++k) {
      w.area_and_secondary[k] = t.area_a[k] | uint32_t(t.secondary_neighbour[k]) << 16;
      w.classify[k] = uint64_t(t.sidedness[k]) | uint64_t(t.centre_on_chord[k]) << 32 | uint64_t(t.area_a[k] < 32768) << 48;
    }
    return w;
  }();
  return tables;
}

// Storage for a set of planes: whole-image (rows = height) or rings (rows per plane from stages.h).
struct PlaneStore {
  std::vector<uint16_t> edge;
  std::vector<uint8_t> types, found;
  std::vector<uint32_t> reach;
  std::vector<float> interp, filled, samples, zero_samples;
  std::vector<uint8_t> padded_types, outside_types;
  int width = -1, rows_of_class = 0, rows_of_reach = 0, rows_of_interp = 0, rows_of_filled = 0;
  void resize(int w, int class_rows, int reach_rows, int interp_rows, int filled_rows) {
    if (w == width && class_rows == rows_of_class && reach_rows == rows_of_reach && interp_rows == rows_of_interp &&
        filled_rows == rows_of_filled)
      return;
    width = w, rows_of_class = class_rows, rows_of_reach = reach_rows, rows_of_interp = interp_rows, rows_of_filled = filled_rows;
    const size_t n = size_t(w);
    edge.assign(n * size_t(class_rows), 0), types.assign(n * size_t(class_rows), 0);
    reach.assign(samples_plane(w) * size_t(reach_rows), 0);  // padded: zeros outside the image
    // Padded like the decoded rows: zeros outside the image (the fill kernel reads the 5x5).
    found.assign(samples_plane(w) * size_t(interp_rows), 0), interp.assign(3 * samples_plane(w) * size_t(interp_rows), 0.0f);
    filled.assign(3 * n * size_t(filled_rows), 0.0f);
    samples.assign(samples_stride(w) * size_t(class_rows), 0.0f), zero_samples.assign(samples_stride(w), 0.0f);
    // The red plane (the last; simd::InterpolateRow) reads "no usable sample" as -0.
    for (std::vector<float>* v : {&samples, &zero_samples})
      for (size_t row = 0; row < v->size(); row += samples_stride(w))
        std::fill(v->begin() + ptrdiff_t(row + 4 * samples_plane(w)), v->begin() + ptrdiff_t(row + samples_stride(w)), -0.0f);
    // Pads and rows outside the image read as complex (blocked); decoding writes only the pixels.
    padded_types.assign(samples_plane(w) * size_t(class_rows), uint8_t(kTypeComplex));
    outside_types.assign(samples_plane(w), uint8_t(kTypeComplex));
  }
};

// Everything a row kernel reads and writes.
struct RowJob {
  const EpiImage& in;
  const BoundaryMasks& masks;
  const ReconstructSettings& settings;
  const simd::RowKernels* kernels;  // nullptr: the per-pixel oracle functions
  Reconstruction& out;
  int width, height;
  RowPlane<uint16_t> edge;
  RowPlane<uint8_t> types, found;
  RowPlane<uint32_t> reach;
  RowPlane<float> interp, filled, image, samples;
  RowPlane<uint8_t> padded_types;  // types with kPad pixels on the left (simd::RelationRow)
  // Rows written to `out` (edge words, cache words, priority; the image rows are the only ones
  // the output stages compute); other rows are halo, recomputed by the neighbouring band.
  int own_first, own_last;
  ClassCounts* counts;            // of owned rows
  float* priority_scratch;        // priority of halo rows (discarded), width floats
  const float* zero_samples;      // a decoded row of zeros (rows outside the image)
  const uint8_t* outside_types;   // a padded types row outside the image
  int stage_first = 0;            // first row of this stage in the current run (reach reuse)
  bool reuse_reach = false;       // reach may take the rows above by symmetry (not in the oracle)
  bool reuse_relations = true;    // relation rows kept from the rows before (update_relations)
  // The neighbour relations of the rows the reachability kernel reads (simd::RelationRow), a
  // ring of kRelationRows rows of four planes; rows below relations_next are computed (this run).
  uint8_t* relations = nullptr;
  int relations_next = -1;
  ComplexRowCache* complex_cache = nullptr;  // the complex filter's (with kernels), reset per job
  FallbackScratch* fallback = nullptr;       // fallback_row's (with kernels; null: per pixel)

  bool owned(int y) const { return y >= own_first && y <= own_last; }
  bool inside(int y) const { return y >= 0 && y < height; }
  EpiRows rows() const { return {edge.data, types.data, in.color.data(), width, height, edge.mask}; }
};

void classify_stage(RowJob& j, int y) {
  const size_t i0 = size_t(y) * size_t(j.width);
  uint16_t* edge = j.edge.row(y);
  uint8_t* types = j.types.row(y);
  ClassCounts halo;
  ClassCounts& counts = j.owned(y) ? *j.counts : halo;
  if (j.kernels) {
    const WideTables& t = wide_tables();
    const bool centre = j.masks.centre_lines;
    simd::ClassifyRow row{j.width, &j.masks.top[j.masks.index(0, y)], &j.masks.top[j.masks.index(0, y + 1)],
                          &j.masks.left[j.masks.index(0, y)], centre ? &j.masks.centre_h[j.masks.index(0, y)] : nullptr,
                          centre ? &j.masks.centre_v[j.masks.index(0, y)] : nullptr, &j.in.edge[i0],
                          t.classify, edge, types, {}};
    j.kernels->classify(row);
    counts.empty += row.counts[0], counts.simple += row.counts[1], counts.complex += row.counts[2];
    counts.samples += row.counts[3], counts.ambiguous += row.counts[4];
  } else {
    classify_row(j.masks, y, &j.in.edge[i0], edge, types, counts);
  }
  // The output's cache words are written by reachability (type and reach mask in one pass).
  if (j.owned(y) && edge != &j.out.edge[i0]) std::memcpy(&j.out.edge[i0], edge, size_t(j.width) * sizeof(uint16_t));
}

bool vector_kernels(const RowJob& j) { return j.kernels && j.settings.filter == Filter::epi; }

void decode_stage(RowJob& j, int y) {
  if (!j.kernels) return;  // both filters' vector kernels read the decoded rows
  const size_t plane = samples_plane(j.width);
  float* base = j.samples.row(y) + simd::kPad;  // planes green, blue, usable, sampled, red
  j.kernels->decode({j.width, j.edge.row(y), &j.in.color[size_t(y) * size_t(j.width)], epi_color8_to_linear().data(),
                     base + 4 * plane, base, base + plane, base + 2 * plane, base + 3 * plane});
  std::memcpy(j.padded_types.row(y) + simd::kPad, j.types.row(y), size_t(j.width));
}

// Relation rows (simd::RelationRow): four planes of samples_plane bytes, pixel 0 at kPad.
constexpr int kRelationRows = 8;
size_t relations_stride(int w) { return 4 * samples_plane(w); }
uint8_t* relation_row(const RowJob& j, int r) {
  return j.relations + size_t(r & (kRelationRows - 1)) * relations_stride(j.width) + simd::kPad;
}

// Computes the relation rows y - 2 .. y + 2 not yet computed in this run: one row per call
// while the rows run consecutively (each row's relations serve five rows of reachability).
void update_relations(RowJob& j, int y) {
  const bool consecutive = j.reuse_relations && j.relations_next == y + 2;
  for (int r = consecutive ? y + 2 : y - 2; r <= y + 2; ++r) {
    // Row y - 2's relations towards the row above are never read: computed as "outside".
    const bool above_read = r > y - 2 && j.inside(r - 1);
    j.kernels->relations({j.width, above_read ? j.padded_types.row(r - 1) : j.outside_types,
                          j.inside(r) ? j.padded_types.row(r) : j.outside_types, &relation_tables(),
                          relation_row(j, r), samples_plane(j.width)});
  }
  j.relations_next = y + 3;
}

void reachability_stage(RowJob& j, int y) {
  uint32_t* reach = j.reach.row(y);
  const TypeRows types{j.types.data, j.width, j.height, j.types.mask};
  if (j.settings.filter != Filter::epi) {
    std::memset(reach, 0, size_t(j.width) * sizeof(uint32_t));  // the render cache has no reachability
  } else if (j.kernels) {
    update_relations(j, y);
    uint32_t* cache = j.owned(y) ? &j.out.cache[size_t(y) * size_t(j.width)] : nullptr;
    simd::ReachRow row{j.width, {}, samples_plane(j.width), reach, cache, j.types.row(y), {}};
    for (int k = 0; k < 5; ++k) row.relations[k] = relation_row(j, y - 2 + k);
    if (j.reuse_reach && y - 2 >= j.stage_first) row.above[0] = j.reach.row(y - 1), row.above[1] = j.reach.row(y - 2);
    j.kernels->reachability(row);  // the cache words too
    return;
  } else {
    for (int x = 0; x < j.width; ++x) reach[x] = reach_full(types, x, y);
  }
  if (j.owned(y)) {
    uint32_t* cache = &j.out.cache[size_t(y) * size_t(j.width)];
    const uint8_t* type = j.types.row(y);
    for (int x = 0; x < j.width; ++x) cache[x] = uint32_t(type[x]) << bits::kTypeShift | reach[x];
  }
}

// The fallback's 7x7 reachability (simd::Reach7Row) of the pixels fallback_row marked in the
// fallback's scratch, into its reach7: the relation rows y - 3 .. y + 3 (simd::RelationRow) over
// the columns the marked pixels' windows cover (those of the 64-pixel chunks holding one, 3
// more on each side; the marked pixels may be few and far apart), in the scratch's planes
// (pixel 0 at kReach7Pad: the kernel reads whole vectors from 3 pixels before the first).
constexpr int kReach7Pad = 3;
void fallback_reach7(RowJob& j, int y) {
  FallbackScratch& f = *j.fallback;
  const size_t plane = size_t(j.width) + kReach7Pad + 69;  // Reach7Row reads to 66 past the row
  if (f.relations.size() != 28 * plane) f.relations.assign(28 * plane, 0);
  f.reach7.resize(size_t(j.width));
  const auto relation_row = [&](int k) { return f.relations.data() + 4 * size_t(k) * plane + kReach7Pad; };
  simd::Reach7Row row{{}, plane, f.reaching.data(), f.span_first, f.span_end, f.reach7.data()};
  for (int k = 0; k < 7; ++k) row.relations[k] = relation_row(k);
  const auto relations = [&](int x0, int x1) {
    for (int k = 0; k < 7; ++k) {
      const int r = y - 3 + k;
      // Row y - 3's relations towards the row above are not read: computed as outside.
      const uint8_t* above = k > 0 && j.inside(r - 1) ? j.padded_types.row(r - 1) : j.outside_types;
      const uint8_t* own = j.inside(r) ? j.padded_types.row(r) : j.outside_types;
      j.kernels->relations({x1 - x0, above + x0, own + x0, &relation_tables(), relation_row(k) + x0, plane});
    }
  };
  int x0 = 0, x1 = 0;  // the columns pending, merged while the chunks' ranges touch
  for (int c = f.span_first; c < f.span_end; c += 64) {
    const int count = std::min(64, f.span_end - c);
    if (!std::memchr(f.reaching.data() + c, 1, size_t(count))) continue;
    const int a = std::max(0, c - 3), b = std::min(j.width, c + count + 3);
    if (x1 > x0 && a <= x1) {
      x1 = b;
      continue;
    }
    if (x1 > x0) relations(x0, x1);
    x0 = a, x1 = b;
  }
  if (x1 > x0) relations(x0, x1);
  j.kernels->reach7(row);
}

void interpolate_stage(RowJob& j, int y) {
  const EpiRows rows = j.rows();
  const uint32_t* reach = j.reach.row(y);
  float* colors = j.interp.row(y);
  uint8_t* found = j.found.row(y);
  float* priority = j.owned(y) ? &j.out.priority[size_t(y) * size_t(j.width)] : j.priority_scratch;
  if (!j.kernels) {
    for (int x = 0; x < j.width; ++x) priority[x] = interpolate(rows, j.settings, x, y, reach[x], colors + 3 * x, found + x);
    return;
  }
  simd::InterpolateRow row{};
  const size_t plane = samples_plane(j.width);
  for (int k = 0; k < 5; ++k) {
    const float* base = j.inside(y - 2 + k) ? j.samples.row(y - 2 + k) : j.zero_samples;
    row.green[k] = base, row.blue[k] = base + plane, row.usable[k] = base + 2 * plane;
    row.sampled[k] = base + 3 * plane, row.red[k] = base + 4 * plane;
  }
  row.width = j.width, row.types = j.types.row(y), row.reach = reach;
  row.color = &j.in.color[size_t(y) * size_t(j.width)];
  row.rgb = colors, row.found = found, row.priority = priority;
  const bool rendercache = j.settings.filter == Filter::rendercache;
  if (rendercache) j.kernels->rendercache(row);
  else j.kernels->interpolate(row);
  // Pixels that reached nothing (found 0; runs of them after motion): the oracle's fallback, row
  // by row, or the render cache's 7x7 prefilter where its 3x3 holds no sample.
  // The edge-free 7x7 windows (most of those pixels) go to the vector kernel, the same bits.
  // The other pixels (windows with an edge, or at the image's sides) get their 7x7 reachability
  // (fallback_reach7) and their reachable mean from the vector kernels too, the last resort from
  // the scalar code.
  const bool by_rows = !rendercache && j.fallback;
  const bool blend = j.settings.blend_unreached_near_edges;
  const auto window_mean = [&](const uint8_t* take, const uint64_t* masks, uint8_t* mean_found) {
    simd::WindowMeanRow mean{};
    for (int k = 0; k < 7; ++k) {
      const float* base = j.inside(y - 3 + k) ? j.samples.row(y - 3 + k) : j.zero_samples;
      mean.green[k] = base, mean.blue[k] = base + plane, mean.red[k] = base + 4 * plane;
    }
    mean.width = j.width, mean.take = take, mean.rgb = colors, mean.masks = masks, mean.found = mean_found;
    mean.first = j.fallback->span_first, mean.end = j.fallback->span_end;
    j.kernels->window_mean(mean);
  };
  if (by_rows && fallback_row(rows, y, found, colors, blend, *j.fallback, true, true) > 0)
    window_mean(j.fallback->whole_window.data(), nullptr, nullptr);
  if (by_rows && j.fallback->reaching_count > 0) {
    FallbackScratch& f = *j.fallback;
    fallback_reach7(j, y);
    f.reach7_found.resize(size_t(j.width));
    window_mean(f.reaching.data(), f.reach7.data(), f.reach7_found.data());
    fallback_reaching_row(rows, y, colors, blend, f, f.reach7_found.data());
  }
  for (auto* p = static_cast<uint8_t*>(std::memchr(found, 0, size_t(j.width))); p;
       p = static_cast<uint8_t*>(std::memchr(p + 1, 0, size_t(found + j.width - p - 1)))) {
    const int x = int(p - found);
    if (rendercache) {
      window_average(rows, x, y, 3, colors + 3 * x);
      *p = 1;
    } else if (!by_rows) {
      fallback_color(rows, x, y, colors + 3 * x, j.settings.blend_unreached_near_edges);
    }
    priority[x] = kMaxPriority;
  }
}

// fill_in_place: in the tiled schedule with the vector kernels the filled rows are the
// interpolated rows (Plane::filled aliases Plane::interp): the fill step reads only pixels that
// found samples and writes only those that did not, so filling row y in place changes nothing
// the fill of rows y + 1 and y + 2 reads, and the pass-through pixels (nearly all) are never
// copied; anti-aliasing then writes the image row from the interpolated row. The interpolated
// ring holds the rows until the output stages have read them. Not in the staged schedule: its
// threads share whole-image planes, and a fill writing row y in place would race with the
// fills of rows y +- 1, y +- 2 on other threads loading those vectors.
static_assert(stage_lag(Stage::antialias) + 1 - stage_lag(Stage::interpolate) < ring_rows(Plane::interp) &&
                  stage_lag(Stage::complex) - stage_lag(Stage::interpolate) < ring_rows(Plane::interp),
              "the interpolated ring must hold the rows the output stages read as filled rows");
void fill_stage(RowJob& j, int y) {
  const float* interp_rows[5];
  const uint8_t* found_rows[5];
  for (int k = 0; k < 5; ++k) {
    interp_rows[k] = j.inside(y - 2 + k) ? j.interp.row(y - 2 + k) : nullptr;
    found_rows[k] = j.inside(y - 2 + k) ? j.found.row(y - 2 + k) : nullptr;
  }
  const uint32_t* reach = j.reach.row(y);
  float* out = j.filled.row(y);
  const bool in_place = j.filled.data == j.interp.data;  // fill_in_place
  if (vector_kernels(j) && j.settings.fill) {
    simd::FillRow row{j.width, {}, {}, reach, out};
    const float* zeros = j.zero_samples + 3 * simd::kPad;  // a zero row, padding included
    for (int k = 0; k < 5; ++k) {
      row.rows[k] = interp_rows[k] ? interp_rows[k] : zeros;
      row.found[k] = found_rows[k] ? found_rows[k] : reinterpret_cast<const uint8_t*>(zeros);
    }
    j.kernels->fill(row);
    return;
  }
  if (in_place) return;  // without the fill step the filled row is the interpolated row
  for (int x = 0; x < j.width; ++x) fill(j.settings, x, j.width, reach[x], interp_rows, found_rows, out + 3 * x);
}

void antialias_stage(RowJob& j, int y) {
  const float* rows[3] = {j.inside(y - 1) ? j.filled.row(y - 1) : nullptr, j.filled.row(y),
                          j.inside(y + 1) ? j.filled.row(y + 1) : nullptr};
  float* out = j.image.row(y);
  const EpiRows epi = j.rows();
  const uint8_t* types = j.types.row(y);
  const bool on = j.settings.filter == Filter::epi && j.settings.antialias;
  if (on && j.kernels) {
    const WideTables& t = wide_tables();
    j.kernels->antialias({j.width, {rows[0], rows[1], rows[2]}, types, j.edge.row(y), t.area_and_secondary, out});
    return;
  }
  for (int x = 0; x < j.width; ++x) {
    if (output_filter(j.settings, j.masks.centre_lines, types[x]) == OutputFilter::antialiased) {
      antialias_pixel(epi, x, y, rows, out + 3 * x);
    } else {
      const float* own = rows[1] + 3 * x;
      out[3 * x] = own[0], out[3 * x + 1] = own[1], out[3 * x + 2] = own[2];
    }
  }
}

void complex_stage(RowJob& j, int y) {
  if (!use_complex_filter(j.settings, j.masks)) return;
  const EpiRows epi = j.rows();
  const uint8_t* types = j.types.row(y);
  const float* filled = j.filled.row(y);
  float* out = j.image.row(y);
  static_assert(output_filter({}, true, kTypeComplex) == OutputFilter::complex_filter);
  if (j.kernels) return complex_row(epi, j.masks, y, types, filled, out, *j.complex_cache, j.kernels->target);
  // Complex pixels are few (0.3-3 %): found by memchr, not by a test per pixel.
  const size_t w = size_t(j.width);
  for (auto* p = static_cast<const uint8_t*>(std::memchr(types, kTypeComplex, w)); p;
       p = static_cast<const uint8_t*>(std::memchr(p + 1, kTypeComplex, w - size_t(p + 1 - types)))) {
    const int x = int(p - types);
    complex_pixel(epi, j.masks, x, y, filled + 3 * x, out + 3 * x);
  }
}

// The row kernel of each stage, in the order of kStages.
using StageRowFunction = void (*)(RowJob&, int);
constexpr std::array<StageRowFunction, kStageCount> kStageRows = {
    classify_stage, decode_stage, reachability_stage, interpolate_stage, fill_stage, antialias_stage, complex_stage};
void run_stage_row(Stage s, RowJob& j, int y) { kStageRows[size_t(s)](j, y); }

// Rings of one thread (reused across its bands and calls).
struct ThreadScratch {
  PlaneStore rings;
  std::vector<float> priority;
  std::vector<uint8_t> relations;
  ComplexRowCache complex_cache;
  FallbackScratch fallback;
  void resize(int w) {
    if (relations.size() != kRelationRows * relations_stride(w)) relations.assign(kRelationRows * relations_stride(w), 0);
    static_assert(ring_rows(Plane::samples) <= kClassRingRows, "decoded rows live in rings of the classified rows' size");
    rings.resize(w, kClassRingRows, ring_rows(Plane::reach), ring_rows(Plane::interp), ring_rows(Plane::filled));
    priority.resize(size_t(w));
  }
};

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }
double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

void prepare_output(const EpiImage& epi, const BoundaryMasks& masks, Reconstruction& r) {
  check_sizes(epi, masks);
  const int w = epi.width, h = epi.height;
  const size_t n = size_t(w) * size_t(h);
  if (r.image.width != w || r.image.height != h) r.image = RgbImage(w, h);
  r.priority.resize(n), r.edge.resize(n), r.cache.resize(n);
  r.counts = {};
}

void add_counts(ClassCounts& a, const ClassCounts& b) {
  a.empty += b.empty, a.simple += b.simple, a.complex += b.complex, a.samples += b.samples, a.ambiguous += b.ambiguous;
}

}  // namespace

struct Reconstructor::Scratch {
  PlaneStore whole;  // whole-image planes: oracle and staged (edge words go straight to the output)
  std::vector<float> priority;
  tbb::enumerable_thread_specific<ThreadScratch> threads;
  std::unique_ptr<tbb::task_arena> arena;
  int arena_threads = -1;
  tbb::task_arena& arena_for(int n) {
    if (!arena || arena_threads != n) {
      arena = std::make_unique<tbb::task_arena>(n > 0 ? n : int(+tbb::task_arena::automatic));
      arena_threads = n;
    }
    return *arena;
  }
};

Reconstructor::Reconstructor(KernelChoice choice)
    : kernels_(choice.oracle ? nullptr : &simd::row_kernels(choice.target)), scratch_(std::make_unique<Scratch>()) {}
Reconstructor::~Reconstructor() = default;

const char* Reconstructor::kernel_name() const { return kernels_ ? kernels_->target_name : "oracle"; }

namespace {

// A RowJob over whole-image planes (rows = height): the oracle's and the staged schedule's.
RowJob whole_image_job(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                       const simd::RowKernels* kernels, Reconstruction& r, PlaneStore& whole, ClassCounts* counts,
                       float* priority_scratch) {
  const int w = epi.width, h = epi.height;
  const size_t n = size_t(w);
  return RowJob{epi, masks, s, kernels, r, w, h,
                {r.edge.data(), n}, {whole.types.data(), n}, {whole.found.data() + simd::kPad, samples_plane(w)},
                {whole.reach.data() + simd::kPad, samples_plane(w)},
                {whole.interp.data() + 3 * simd::kPad, 3 * samples_plane(w)}, {whole.filled.data(), 3 * n},
                {r.image.pixels.data(), 3 * n},
                {whole.samples.data(), samples_stride(w)}, {whole.padded_types.data(), samples_plane(w)}, 0, h - 1, counts,
                priority_scratch, whole.zero_samples.data(), whole.outside_types.data()};
}

}  // namespace

void Reconstructor::oracle(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                           Reconstruction& r) {
  prepare_output(epi, masks, r);
  const int w = epi.width, h = epi.height;
  if (w == 0 || h == 0) return;  // nothing to compute (and no rows to point into)
  scratch_->whole.resize(w, h, h, h, h);
  RowJob job = whole_image_job(epi, masks, s, nullptr, r, scratch_->whole, &r.counts, nullptr);
  for (const StageInfo& stage : kStages)
    for (int y = 0; y < h; ++y) run_stage_row(stage.stage, job, y);
}

void Reconstructor::staged(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                           Reconstruction& r, ReconstructTimes& times, const Schedule& schedule) {
  prepare_output(epi, masks, r);
  times = {};
  const int w = epi.width, h = epi.height;
  if (w == 0 || h == 0) return;
  scratch_->whole.resize(w, h, h, h, h);
  tbb::combinable<ClassCounts> counts;
  scratch_->arena_for(schedule.threads).execute([&] {
    for (const StageInfo& stage : kStages) {
      const auto t = Clock::now();
      const double cpu = thread_cpu_ms();
      tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& range) {
        ThreadScratch& local = scratch_->threads.local();
        local.resize(w);
        RowJob job = whole_image_job(epi, masks, s, kernels_, r, scratch_->whole, &counts.local(), nullptr);
        job.stage_first = range.begin(), job.reuse_reach = schedule.reach_symmetry;
        job.reuse_relations = schedule.reuse_relations;
        job.relations = local.relations.data();
        job.complex_cache = &local.complex_cache, local.complex_cache.reset();
        job.fallback = schedule.row_fallback ? &local.fallback : nullptr;
        for (int y = range.begin(); y != range.end(); ++y) run_stage_row(stage.stage, job, y);
      });
      times[stage.stage] = ms_since(t);
      times.cpu_ms[size_t(stage.stage)] = thread_cpu_ms() - cpu;
    }
  });
  counts.combine_each([&](const ClassCounts& c) { add_counts(r.counts, c); });
}

void Reconstructor::tiled(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                          const Schedule& schedule, Reconstruction& r) {
  prepare_output(epi, masks, r);
  const int w = epi.width, h = epi.height;
  if (w == 0 || h == 0) return;
  const int band_rows = std::max(1, schedule.rows_per_band);
  const int bands = (h + band_rows - 1) / band_rows;
  std::vector<ClassCounts> band_counts(static_cast<size_t>(bands));

  // Band b: rows stream through the stages, each lagging classification by its lag; only owned
  // rows [y0, y1) are written to the output, halo rows are recomputed by each band that needs them.
  auto run_band = [&](int b, ThreadScratch& local) {
    const int y0 = b * band_rows, y1 = std::min(h, y0 + band_rows);
    // The rows each stage computes: the output stages the band's own; each stage those its
    // readers need (their rows widened by the footprint), within the image.
    std::array<int, kStageCount> first{}, last{};
    first.fill(h), last.fill(-1);
    for (int k = kStageCount - 1; k >= 0; --k) {
      const StageInfo& stage = kStages[size_t(k)];
      if (stage.output == Plane::image) first[size_t(k)] = y0, last[size_t(k)] = y1 - 1;
      if (first[size_t(k)] > last[size_t(k)]) continue;
      for (int i = 0; i < stage.input_count; ++i) {
        const StageInput& in = stage.inputs[size_t(i)];
        const size_t p = size_t(producer(in.plane));
        first[p] = std::min(first[p], std::max(0, first[size_t(k)] - in.radius));
        last[p] = std::max(last[p], std::min(h - 1, last[size_t(k)] + in.radius));
      }
    }
    PlaneStore& ring = local.rings;
    const size_t n = size_t(w);
    RowJob job{epi, masks, s, kernels_, r, w, h,
               {ring.edge.data(), n, kClassRingRows - 1}, {ring.types.data(), n, kClassRingRows - 1},
               {ring.found.data() + simd::kPad, samples_plane(w), ring_rows(Plane::interp) - 1},
               {ring.reach.data() + simd::kPad, samples_plane(w), ring_rows(Plane::reach) - 1},
               {ring.interp.data() + 3 * simd::kPad, 3 * samples_plane(w), ring_rows(Plane::interp) - 1}, {ring.filled.data(), 3 * n, ring_rows(Plane::filled) - 1},
               {r.image.pixels.data(), 3 * n}, {ring.samples.data(), samples_stride(w), kClassRingRows - 1},
               {ring.padded_types.data(), samples_plane(w), kClassRingRows - 1},
               y0, y1 - 1, &band_counts[size_t(b)], local.priority.data(),
               ring.zero_samples.data(), ring.outside_types.data()};
    if (kernels_) job.filled = job.interp;  // fill_in_place
    job.reuse_reach = schedule.reach_symmetry, job.reuse_relations = schedule.reuse_relations;
    job.relations = local.relations.data();
    job.complex_cache = &local.complex_cache, local.complex_cache.reset();
    job.fallback = schedule.row_fallback ? &local.fallback : nullptr;
    job.stage_first = first[size_t(Stage::reachability)];
    const int classified_first = first[size_t(Stage::classify)];
    for (int y = classified_first; y <= last[size_t(Stage::classify)] + kMaxLag; ++y)
      for (const StageInfo& stage : kStages) {
        const int row = y - stage_lag(stage.stage);
        if (row >= first[size_t(stage.stage)] && row <= last[size_t(stage.stage)]) run_stage_row(stage.stage, job, row);
      }
  };
  scratch_->arena_for(schedule.threads).execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const tbb::blocked_range<int>& range) {
      ThreadScratch& local = scratch_->threads.local();
      local.resize(w);
      for (int b = range.begin(); b != range.end(); ++b) run_band(b, local);
    }, tbb::simple_partitioner());
  });
  for (const ClassCounts& c : band_counts) add_counts(r.counts, c);
}

Reconstruction reconstruct_oracle(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s) {
  Reconstruction r;
  Reconstructor(KernelChoice{true, 0}).oracle(epi, masks, s, r);
  return r;
}

Reconstruction reconstruct_tiled(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                                 const Schedule& schedule) {
  Reconstruction r;
  reconstruct_tiled(epi, masks, s, schedule, r);
  return r;
}

void reconstruct_tiled(const EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& s,
                       const Schedule& schedule, Reconstruction& out) {
  Reconstructor().tiled(epi, masks, s, schedule, out);
}

}  // namespace epi

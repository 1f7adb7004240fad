// The Highway row kernels of the reconstruction filters, one table per compiled target
// (dynamic dispatch: the Reconstructor picks a table once, never per row). Each kernel
// computes one row of a stage exactly as the per-pixel oracle in core/epi does, bit for bit;
// tests/simd runs every compiled target against it. docs/epi.md, "SIMD kernels".
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>


namespace epi::simd {

// One row of interpolation (interpolate.h: the 5x5 kernel-weighted mean of the reachable
// usable samples; complex pixels: of every sample) over decoded, padded rows: row k of each
// array is image row y - 2 + k, pixel x of it at index x + kPad; the kPad pixels on the left,
// at least one vector's worth on the right and rows outside the image hold zeros (no sample).
constexpr int kPad = 2;
struct InterpolateRow {
  int width;
  // Linear colour, decoded once per row; red is negated where the pixel holds no usable
  // sample (-0 without a colour, padding and rows outside too): its sign is the usable flag.
  const float* red[5];
  const float* green[5];
  const float* blue[5];
  const float* usable[5];   // 1: the pixel holds a usable sample, else 0
  const float* sampled[5];  // 1: the pixel holds a sample, else 0
  // The row's own pixels (width each, no padding): types, 24-bit reach masks, sample words (age).
  const uint8_t* types;
  const uint32_t* reach;
  const uint32_t* color;
  // Outputs, width each: colours (3 floats per pixel), found (1: some sample reached, else 0:
  // the colour and priority are then the caller's, the oracle's fallback), priority.
  float* rgb;
  uint8_t* found;
  float* priority;
};

// The interpolation fallback's mean over a whole 7x7 (interpolate.cpp, fallback_row: a pixel
// that reached nothing in its 5x5, whose 7x7 lies inside the image, holds a sample and no edge):
// the weighted mean, w = 1 / (1 + dx^2 + dy^2)^2, of the window's usable samples, black where
// none is usable. Rows as InterpolateRow's, but seven: row k is image row y - 3 + k. The pixels
// x in [first, end) with take[x] = 1 (none closer than 3 to the image's sides, none with a
// usable sample in its 5x5: they reached nothing there) get their colour in rgb + 3 x; no other
// pixel of rgb is written. The kernel reads only the 7x7's outer ring.
//
// With `masks` (pixel x's at masks[x], reach_window7's bits), the fallback's reachable mean
// instead (interpolate.cpp, reachable_mean: a window with an edge, or at the image's sides):
// only the samples the mask reaches count (a taken pixel reached no usable one in its 5x5), and
// found[x] is 1 where one did, else 0 and the colour black (the caller's last resort then).
// Pixels closer than 3 to the left side are skipped (nothing written); those closer to the
// right side are taken. found's other entries in the vectors visited are unspecified.
struct WindowMeanRow {
  int width;
  const float* red[7];  // negated where not usable, as InterpolateRow's
  const float* green[7];
  const float* blue[7];
  const uint8_t* take;
  int first, end;
  float* rgb;
  const uint64_t* masks = nullptr;
  uint8_t* found = nullptr;
};

// What a pixel type shows on each side, for the neighbour relation of two adjacent pixels
// (epi/tables.h, SideDescriptors: its primary region along the whole side, its secondary, or
// both split at the crossing): by type, from[s] = 4 x the descriptor of side s (0 top, 1 right,
// 2 bottom, 3 left) and to[s] = the descriptor, both 0x80 for a blocked side (complex pixels;
// outside the image); relation[4a + b]: the relation of descriptors a and b facing each other
// (bit 2a' + b': region a' of the first pixel reaches region b' of the second; 0 primary, 1
// secondary). relation[from | to] is then the relation of two pixels, 0 if either is blocked.
struct RelationTables {
  alignas(16) uint8_t from[4][16];
  alignas(16) uint8_t to[4][16];
  alignas(16) uint8_t relation[16];
};

// The neighbour relations of one row r, computed once per row and read by the reachability of
// the five rows whose 5x5 window holds row r (docs/epi.md, "Reachability reused across rows"):
// 4 bits per pixel (RelationTables.relation), in four byte planes of `plane` bytes each,
// pixel x at out[x]: right (x -> x + 1), left (x -> x - 1), down ((x, r - 1) -> (x, r)), up
// ((x, r) -> (x, r - 1)). Types are padded rows (pixel x at x + kPad, kPad before and at least
// 64 after of kTypeComplex, which is blocked: rows outside the image are all of it), `above`
// row r - 1. The kernel writes whole vectors, into the planes' padding too: zeros there.
struct RelationRow {
  int width;
  const uint8_t* above;
  const uint8_t* types;
  const RelationTables* tables;
  uint8_t* out;  // the right plane; left, down, up follow at `plane` bytes each
  size_t plane;
};
// One row y of reachability (reachability.h: the 24-bit primary-to-primary masks of the 5x5)
// from the relation rows of rows y - 2 .. y + 2 (RelationRow; relations[k] the right plane of
// row y - 2 + k, at least kPad + 1 bytes of zeros before pixel 0 and 66 after the row).
struct ReachRow {
  int width;
  const uint8_t* relations[5];
  size_t plane;
  uint32_t* reach;  // out, width masks
  // nullptr, or out: the cache words of the row (epi_pixel.h: type << 24 | reach mask), from `types`.
  uint32_t* cache;
  const uint8_t* types;
  // The masks of rows y - 1 and y - 2 (pixel x at above[k][x], kPad zeros before, zeros after),
  // or nullptr: then all 24 offsets are computed, else the 14 forward ones and the other 10
  // from these rows by symmetry (docs/epi.md, "Reachability reused across rows").
  const uint32_t* above[2];
};
// One row y of classification (classify.h: classify_pixel for each pixel). Boundary mask rows
// (rasterize.h, width + 1 bytes each): `top` the tops of row y, `bottom` the tops of row y + 1,
// `left` the left sides of row y (pixel x's right side is left[x + 1]); `centre_h`, `centre_v`
// the centre lines of row y, nullptr when the masks have none.
struct ClassifyRow {
  int width;
  const uint8_t* top;
  const uint8_t* bottom;
  const uint8_t* left;
  const uint8_t* centre_h;
  const uint8_t* centre_v;
  const uint16_t* in;          // the input edge words (sample bits)
  // By edge code, 1024 entries: EpiTables::sidedness in bits 0-31, centre_on_chord in 32-47, and
  // in bit 48 whether area_a < 32768 (region B the larger): one gather for the three tables.
  const uint64_t* code_tables;
  uint16_t* edge;              // out: classified edge words
  uint8_t* types;              // out: pixel types
  int64_t counts[5];           // added to: empty, simple, complex, samples, ambiguous
};

// One row of anti-aliasing (antialias.h) over the filled primary colours (3 floats per pixel):
// rows[0..2] rows y - 1, y, y + 1 (nullptr outside the image).
struct AntialiasRow {
  int width;
  const float* rows[3];
  const uint8_t* types;
  const uint16_t* edge;            // classified edge words (codes)
  // By edge code, 1024 entries: EpiTables::area_a in bits 0-15, secondary_neighbour in 16-23.
  const uint32_t* area_and_secondary;
  float* out;                      // 3 floats per pixel
};

// One classified row decoded for the other kernels: colours to linear light through `lut`
// (the 256-entry sRGB table), usable and sampled flags as 1 or 0. Outputs
// start at pixel 0 of the padded planes (width entries written, padding untouched).
struct DecodeRow {
  int width;
  const uint16_t* edge;
  const uint32_t* color;
  const float* lut;
  float *red, *green, *blue, *usable, *sampled;  // red negated where not usable (InterpolateRow)
};

// One row of the fill step (fill.h) over padded rows of interpolated colours (3 floats per
// pixel) and found flags: row k = image row y - 2 + k, pixel x at rows[k] + 3x and found[k] + x,
// kPad pixels of zeros on the left and at least one vector's worth on the right; rows outside
// the image all zeros.
struct FillRow {
  int width;
  const float* rows[5];
  const uint8_t* found[5];
  const uint32_t* reach;  // the row's own masks
  // 3 floats per pixel; or rows[2] itself (in place: the kernel reads only found pixels and
  // writes only the others, so the rows after read the same colours; the tiled schedule).
  float* out;
};

// The fallback's 7x7 reachability (reachability.h: reach_window7, the same masks: bit
// (dy + 3) x 7 + dx + 3, the centre's bit 24 set) of the pixels x in [first, end) with take[x]
// = 1, from the relation rows (RelationRow's four planes, `plane` bytes apart) of rows y - 3 ..
// y + 3: relations[k] the right plane of row y - 3 + k, pixel x at [x]; row y - 3's down and up
// planes are not read. A taken pixel's mask depends only on the relations within 3 columns of
// its own that lie in the image (those into the outside are blocked, so what lies beyond is
// never reached); the kernel reads whole vectors, from 3 bytes before `first` to 66 after `end`.
// Only the taken pixels' masks[x] are written.
struct Reach7Row {
  const uint8_t* relations[7];
  size_t plane;
  const uint8_t* take;
  int first, end;
  uint64_t* masks;
};

struct RowKernels {
  const char* target_name;
  int64_t target;  // the HWY_* bit
  void (*interpolate)(const InterpolateRow& row);
  void (*reachability)(const ReachRow& row);
  void (*relations)(const RelationRow& row);
  void (*classify)(ClassifyRow& row);
  void (*antialias)(const AntialiasRow& row);
  void (*decode)(const DecodeRow& row);
  void (*fill)(const FillRow& row);
  // The render cache's filter (rendercache.h) over the same rows as interpolation: the 3x3 of
  // the sampled flags and colours (rows 1-3), the own sample words (age); `usable` and `reach`
  // are not read. Outputs as interpolation's (found 0: the caller's fallback).
  void (*rendercache)(const InterpolateRow& row);
  void (*window_mean)(const WindowMeanRow& row);
  void (*reach7)(const Reach7Row& row);
};

// The table of one target; 0: the best this CPU runs. Throws std::invalid_argument for a
// target that is not compiled or not supported here.
const RowKernels& row_kernels(int64_t target = 0);
// The targets compiled in and supported by this CPU, best first (e.g. AVX3, AVX2, SSE4, scalar).
std::vector<int64_t> compiled_targets();

}  // namespace epi::simd

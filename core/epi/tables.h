// The lookup tables of the EPI filters, generated from the cell geometry at start-up
// (never typed in). tests/epi/tables_test.cpp checks every entry against brute force.
#pragma once

#include <cstdint>

namespace epi {

// Reachability masks between pixels a and b, 4 bits: Pa-Pb, Pa-Sb, Sa-Pb, Sa-Sb.
constexpr uint8_t kReachPP = 1, kReachPS = 2, kReachSP = 4, kReachSS = 8;

// Directions from a pixel to its side neighbour.
enum Direction : int { kRight = 0, kDown = 1, kLeft = 2, kUp = 3 };
constexpr int kDirDx[4] = {1, 0, -1, 0};
constexpr int kDirDy[4] = {0, 1, 0, -1};

// Neighbours for the secondary colour: the four sides first, then the diagonals.
constexpr int kNeighbourDx[8] = {1, 0, -1, 0, 1, -1, -1, 1};
constexpr int kNeighbourDy[8] = {0, 1, 0, -1, 1, 1, -1, -1};

struct EpiTables {
  // Sample sidedness: per edge code, 2 bits per sample region (0 A, 1 B, 2 ambiguous).
  uint32_t sidedness[1024];
  // Area of region A, in units of 1/65535 of the pixel.
  uint16_t area_a[1024];
  // Secondary-colour neighbour (index into kNeighbourDx/Dy): low nibble when A is secondary,
  // high nibble when B is secondary.
  uint8_t secondary_neighbour[1024];
  // Neighbour reachability: [direction][(type_a << 4) | type_b] -> 4-bit mask a <-> b.
  uint8_t neighbour[4][256];
  // Chaining: [(a<->b) << 4 | (b<->d)] -> a<->d.
  uint8_t chain[256];
  // Centre-line crossings that agree with a simple code's chord (docs/epi.md, "Corners"):
  // bit m the 1/8 piece m of the line y = 1/2 (BoundaryMasks::centre_h), bit 8 + m of x = 1/2
  // (centre_v); set when the piece's centre lies within kChordTolerance of the chord's line.
  // 0xffff for codes that are not simple.
  uint16_t centre_on_chord[1024];

  int side(int code, int region) const { return int(sidedness[code] >> (2 * region)) & 3; }
  float area_of_a(int code) const { return float(area_a[code]) * (1.0f / 65535.0f); }
  int neighbour_for_secondary(int code, bool secondary_is_b) const {
    return secondary_is_b ? secondary_neighbour[code] >> 4 : secondary_neighbour[code] & 15;
  }
};
// How far (in pixels) a recorded centre-line crossing may lie from a simple pixel's chord and
// still belong to it: a straight edge's crossings lie within 1/16 of their pieces' centres, and
// the chord within 1/16 of the edge, so 1/8 bounds one straight edge; 1/64 more for rounding.
constexpr double kChordTolerance = 1.0 / 8.0 + 1.0 / 64.0;

static_assert(sizeof(EpiTables) <= 16 * 1024, "the tables must stay under 16 KB");

// Generated once, on first use (thread-safe).
const EpiTables& epi_tables();

// For the vector reachability kernel (simd/reachability-inl.h): what a pixel shows on each side,
// as 2-bit descriptors (0 the primary region along the whole side, 1 the secondary, 2 both
// split at the crossing with the primary first clockwise, 3 the secondary first) at bits
// 2 side, plus kSideBlocked (complex: reaches nothing) and kSideNonEmpty; and the neighbour
// relation of two descriptors facing each other, 4 bits at 4 (4 a + b), entries 0-7 in
// relation_lo and 8-15 in relation_hi. Built from regions_on_side with the overlap rule of the
// neighbour table, which it reproduces (tables_test.cpp).
constexpr uint32_t kSideBlocked = 1u << 8, kSideNonEmpty = 1u << 9;
struct SideDescriptors {
  uint32_t word[16];  // by pixel type
  uint32_t relation_lo = 0, relation_hi = 0;
};
const SideDescriptors& side_descriptors();

// Pieces of the generation, exposed for the tests.
EpiTables generate_tables();
// Which region of a pixel of this type touches its side `side`, and which part of it:
// returned as up to two (region, part) entries; part 0 whole side, 1 before the crossing
// (clockwise), 2 after it. region 0 = primary, 1 = secondary. Returns the count.
int regions_on_side(int type, int side, int regions[2], int parts[2]);

}  // namespace epi

#include "epi/reachability.h"

#include <array>
#include <cstddef>
#include <type_traits>

#include "epi/geometry.h"
#include "epi/tables.h"

namespace epi {

namespace {

struct Step {
  int index;     // offset (dx, dy) as (dy + R) * (2R + 1) + (dx + R)
  int dx, dy;
  int pred[2];   // predecessor offsets (index), -1 if none; the centre is R * (2R + 1) + R
  int dir[2];    // direction of the step from each predecessor
};

// The (2R+1)^2 - 1 offsets of the window in order of Manhattan distance, so predecessors come first.
template <int R>
std::array<Step, (2 * R + 1) * (2 * R + 1) - 1> make_steps() {
  constexpr int n_side = 2 * R + 1;
  std::array<Step, n_side * n_side - 1> steps{};
  int n = 0;
  for (int dist = 1; dist <= 2 * R; ++dist)
    for (int dy = -R; dy <= R; ++dy)
      for (int dx = -R; dx <= R; ++dx) {
        if ((dx < 0 ? -dx : dx) + (dy < 0 ? -dy : dy) != dist) continue;
        Step s{(dy + R) * n_side + (dx + R), dx, dy, {-1, -1}, {0, 0}};
        int k = 0;
        if (dx != 0) {
          const int sx = dx > 0 ? 1 : -1;
          s.pred[k] = (dy + R) * n_side + (dx - sx + R);
          s.dir[k++] = sx > 0 ? kRight : kLeft;
        }
        if (dy != 0) {
          const int sy = dy > 0 ? 1 : -1;
          s.pred[k] = (dy - sy + R) * n_side + (dx + R);
          s.dir[k++] = sy > 0 ? kDown : kUp;
        }
        steps[size_t(n++)] = s;
      }
  return steps;
}

const std::array<Step, 24>& steps() {
  static const std::array<Step, 24> s = make_steps<2>();
  return s;
}
const std::array<Step, 48>& steps7() {
  static const std::array<Step, 48> s = make_steps<3>();
  return s;
}

// type_at(px, py) is called for pixels inside the image only. `record`, when not nullptr, is
// called with every propagation step (the visualizer's trace; the fast path compiles without it).
template <typename TypeAt, typename Record = std::nullptr_t>
uint32_t reach(TypeAt type_at, int width, int height, int x, int y, Record record = nullptr) {
  const EpiTables& t = epi_tables();
  uint8_t types[25];
  int any = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int px = x + dx, py = y + dy;
      const bool inside = px >= 0 && py >= 0 && px < width && py < height;
      const int type = inside ? type_at(px, py) : kTypeComplex;
      types[(dy + 2) * 5 + dx + 2] = uint8_t(type);
      any |= type;
    }
  // Fast path: a 5x5 of empty pixels reaches everything.
  if (any == kTypeEmpty) return 0xffffffu;
  uint8_t masks[25] = {};
  uint32_t result = 0;
  for (const Step& s : steps()) {
    uint8_t m = 0;
    [[maybe_unused]] ReachStep traced{s.dx, s.dy, 0, {}, {}, {}, types[s.index], {}, {}, {}, 0};
    for (int k = 0; k < 2 && s.pred[k] >= 0; ++k) {
      const int p = s.pred[k];
      const uint8_t step = t.neighbour[s.dir[k]][(types[p] << 4) | types[s.index]];
      const uint8_t path = p == 12 ? step : t.chain[(masks[p] << 4) | step];
      m |= path;
      if constexpr (!std::is_same_v<Record, std::nullptr_t>) {
        traced.preds = k + 1, traced.pred_dx[k] = p % 5 - 2, traced.pred_dy[k] = p / 5 - 2;
        traced.dir[k] = s.dir[k], traced.pred_type[k] = types[p], traced.neighbour[k] = step, traced.path[k] = path;
      }
    }
    masks[s.index] = m;
    if constexpr (!std::is_same_v<Record, std::nullptr_t>) traced.mask = m, record(traced);
    if (m & kReachPP) result |= 1u << reach_bit(s.dx, s.dy);
  }
  return result;
}

}  // namespace

uint32_t reach_full(const EpiImage& epi, int x, int y) {
  return reach([&](int px, int py) { return pixel_type(epi.cache[epi.index(px, py)]); }, epi.width,
                      epi.height, x, y);
}
uint32_t reach_full(TypeRows p, int x, int y) {
  return reach([p](int px, int py) { return p.at(px, py); }, p.width, p.height, x, y);
}
uint32_t reach_full_traced(TypeRows p, int x, int y, std::vector<ReachStep>& steps) {
  steps.clear();
  return reach([p](int px, int py) { return p.at(px, py); }, p.width, p.height, x, y,
               [&steps](const ReachStep& s) { steps.push_back(s); });
}

uint64_t reach_window7(TypeRows p, int x, int y) {
  const EpiTables& t = epi_tables();
  uint8_t types[49];
  int any = 0;
  for (int dy = -3; dy <= 3; ++dy)
    for (int dx = -3; dx <= 3; ++dx) {
      const int px = x + dx, py = y + dy;
      const bool inside = px >= 0 && py >= 0 && px < p.width && py < p.height;
      const int type = inside ? p.at(px, py) : kTypeComplex;
      types[(dy + 3) * 7 + dx + 3] = uint8_t(type);
      any |= type;
    }
  if (any == kTypeEmpty) return kWindow7All;  // fast path: a 7x7 of empty pixels reaches everything
  uint8_t masks[49] = {};
  uint64_t result = uint64_t(1) << 24;  // the centre
  for (const Step& s : steps7()) {
    uint8_t m = 0;
    for (int k = 0; k < 2 && s.pred[k] >= 0; ++k) {
      const int q = s.pred[k];
      const uint8_t step = t.neighbour[s.dir[k]][(types[q] << 4) | types[s.index]];
      m |= q == 24 ? step : t.chain[(masks[q] << 4) | step];
    }
    masks[s.index] = m;
    if (m & kReachPP) result |= uint64_t(1) << s.index;
  }
  return result;
}

}  // namespace epi

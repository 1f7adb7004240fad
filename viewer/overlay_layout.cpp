#include "overlay_layout.h"

#include <algorithm>
#include <array>

namespace epi::viewer {

float overlap_area(const Rect& a, const Rect& b) {
  const float w = std::min(a.x + a.width, b.x + b.width) - std::max(a.x, b.x);
  const float h = std::min(a.y + a.height, b.y + b.height) - std::max(a.y, b.y);
  return w > 0 && h > 0 ? w * h : 0.0f;
}

bool overlaps(const Rect& a, const Rect& b) { return overlap_area(a, b) > 0; }

bool panel_starts_collapsed(const Rect& panel, float window_width, float window_height, float max_share) {
  const float window_area = window_width * window_height;
  return window_area > 0 && overlap_area(panel, Rect{0, 0, window_width, window_height}) > max_share * window_area;
}

OverlayPlacement place_overlay(const Rect& panel, float full_width, float full_height, float compact_width,
                               float compact_height, float window_width, float window_height, float margin,
                               float max_full_share) {
  // The four corners for an overlay of w x h, top right first (where it has always been).
  auto corners = [&](float w, float h) {
    const float left = margin, right = window_width - margin - w;
    const float top = margin, bottom = window_height - margin - h;
    return std::array<Rect, 4>{Rect{right, top, w, h}, Rect{right, bottom, w, h}, Rect{left, bottom, w, h},
                               Rect{left, top, w, h}};
  };
  const Rect panel_with_gap{panel.x - margin, panel.y - margin, panel.width + 2 * margin, panel.height + 2 * margin};
  const bool has_panel = panel.width > 0 && panel.height > 0;
  for (const bool compact : {false, true}) {
    const float w = compact ? compact_width : full_width, h = compact ? compact_height : full_height;
    if (w + 2 * margin > window_width || h + 2 * margin > window_height) continue;
    if (!compact && w * h > max_full_share * window_width * window_height) continue;
    for (const Rect& r : corners(w, h))
      if (!has_panel || !overlaps(r, panel_with_gap)) return {r.x, r.y, compact};
  }
  const auto c = corners(compact_width, compact_height);
  const Rect* best = &c[0];
  for (const Rect& r : c)
    if (overlap_area(r, panel) < overlap_area(*best, panel)) best = &r;
  return {best->x, best->y, true};
}

}  // namespace epi::viewer

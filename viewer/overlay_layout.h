// Where the stats overlay goes so that it never hides the panel: pure rectangle math, no window,
// so tests call it directly (tests/viewer/overlay_layout_test.cpp).
//
// The overlay tries the window's four corners, top right first, in its full form and then in its
// compact form (two lines, no graph); a small window gets the compact form only. A free
// rectangle of the overlay's size exists beside a rectangular panel only in a strip that spans the
// whole window (left, right, above or below the panel), and such a strip always holds one of the
// window's corners, so the corners are the only places worth trying. When neither form fits anywhere, the compact one goes to the corner that
// overlaps the panel least.
#pragma once

namespace epi::viewer {

struct Rect {
  float x = 0, y = 0, width = 0, height = 0;
};

bool overlaps(const Rect& a, const Rect& b);
float overlap_area(const Rect& a, const Rect& b);

struct OverlayPlacement {
  float x = 0, y = 0;    // the overlay's top-left corner, window coordinates
  bool compact = false;  // draw the two-line form
};

// `panel` has zero size when the panel is hidden. The sizes are the overlay's forms as last drawn.
// `margin` is kept from the window's border. The full form is used only where it covers at most
// `max_full_share` of the window (at 512x512 it would hide a third of the image).
OverlayPlacement place_overlay(const Rect& panel, float full_width, float full_height, float compact_width,
                               float compact_height, float window_width, float window_height, float margin = 10.0f,
                               float max_full_share = 0.25f);

// Whether the panel, `panel` as first drawn open, starts collapsed to its title bar: when it would
// cover more than `max_share` of the window (the default 512x512 window: about 58 %; 960x600:
// 26 %). A user opens it by its title bar; a large window shows it open.
bool panel_starts_collapsed(const Rect& panel, float window_width, float window_height, float max_share = 1.0f / 3.0f);

}  // namespace epi::viewer

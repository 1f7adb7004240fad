// The overlay's placement against a brute-force search: whenever the overlay (full, else compact)
// fits anywhere in the window clear of the panel, place_overlay finds such a place, inside the
// window; the full form wins whenever it fits; when nothing fits, the compact form still stays
// inside the window.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "overlay_layout.h"

namespace epi::viewer {
namespace {

constexpr float kMargin = 10.0f;

Rect with_gap(const Rect& panel) {
  return {panel.x - kMargin, panel.y - kMargin, panel.width + 2 * kMargin, panel.height + 2 * kMargin};
}

// Every placement of a w x h overlay inside the window's margins, on a 1-pixel grid plus the far
// ends, and the least overlap with the panel any of them has (0: it fits clear of the panel and its gap).
float least_overlap(const Rect& panel, float w, float h, float window_w, float window_h, bool with_the_gap) {
  const Rect obstacle = with_the_gap ? with_gap(panel) : panel;
  const float x_end = window_w - kMargin - w, y_end = window_h - kMargin - h;
  float least = INFINITY;
  for (float x = kMargin;; x = std::min(x + 1.0f, x_end)) {
    for (float y = kMargin;; y = std::min(y + 1.0f, y_end)) {
      least = std::min(least, overlap_area({x, y, w, h}, obstacle));
      if (least == 0 || y >= y_end) break;
    }
    if (least == 0 || x >= x_end) break;
  }
  return least;
}

bool fits_window(float w, float h, float window_w, float window_h) {
  return w + 2 * kMargin <= window_w && h + 2 * kMargin <= window_h;
}

TEST(OverlayLayout, MatchesABruteForceSearchOverRandomPanelsAndWindows) {
  std::mt19937 rng(7);
  auto uniform = [&](float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); };
  int full = 0, compact = 0, overlapping = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const float window_w = std::round(uniform(200, 1400)), window_h = std::round(uniform(150, 1000));
    // Panels as users leave them: at the default corner or dragged anywhere, partly off-screen too.
    const bool at_default = trial % 3 == 0;
    const Rect panel{at_default ? 10.0f : std::round(uniform(-100, window_w)), at_default ? 10.0f : std::round(uniform(-100, window_h)),
                     std::round(uniform(30, 450)), std::round(uniform(20, 600))};
    const float full_w = std::round(uniform(250, 420)), full_h = std::round(uniform(150, 260));
    const float compact_w = std::round(uniform(200, full_w)), compact_h = std::round(uniform(30, 60));
    const OverlayPlacement at = place_overlay(panel, full_w, full_h, compact_w, compact_h, window_w, window_h, kMargin);
    const float w = at.compact ? compact_w : full_w, h = at.compact ? compact_h : full_h;
    SCOPED_TRACE(::testing::Message() << "trial " << trial << ": window " << window_w << "x" << window_h << ", panel "
                                      << panel.x << "," << panel.y << " " << panel.width << "x" << panel.height);
    const bool full_fits = fits_window(full_w, full_h, window_w, window_h) &&
                           full_w * full_h <= 0.25f * window_w * window_h &&
                           least_overlap(panel, full_w, full_h, window_w, window_h, true) == 0;
    const bool compact_fits = fits_window(compact_w, compact_h, window_w, window_h) &&
                              least_overlap(panel, compact_w, compact_h, window_w, window_h, true) == 0;
    EXPECT_EQ(at.compact, !full_fits);
    if (full_fits || compact_fits) {
      EXPECT_EQ(overlap_area({at.x, at.y, w, h}, with_gap(panel)), 0.0f);
      EXPECT_GE(at.x, kMargin);
      EXPECT_GE(at.y, kMargin);
      EXPECT_LE(at.x + w, window_w - kMargin);
      EXPECT_LE(at.y + h, window_h - kMargin);
    } else if (fits_window(compact_w, compact_h, window_w, window_h)) {
      // Nowhere clear: the compact form, still inside the window.
      EXPECT_TRUE(at.compact);
      EXPECT_GE(at.x, kMargin);
      EXPECT_GE(at.y, kMargin);
      EXPECT_LE(at.x + w, window_w - kMargin);
      EXPECT_LE(at.y + h, window_h - kMargin);
      ++overlapping;
    }
    full += !at.compact, compact += at.compact;
  }
  // The random cases reach each outcome.
  EXPECT_GT(full, 50);
  EXPECT_GT(compact, 50);
  EXPECT_GT(overlapping, 5);
}

TEST(OverlayLayout, TheDefaultWindowKeepsThePanelReadable) {
  // epi-viewer's default: a 512x512 window, the panel at (10, 10) about 345x440, the overlay
  // about 400x230 full and 380x40 compact. The full form fits nowhere; the compact one below the panel.
  const Rect panel{10, 10, 345, 440};
  const OverlayPlacement at = place_overlay(panel, 400, 230, 380, 40, 512, 512);
  EXPECT_TRUE(at.compact);
  EXPECT_FALSE(overlaps({at.x, at.y, 380, 40}, panel));
  EXPECT_EQ(at.y, 512 - 10 - 40);
  // A wide window: the full form, top right, as before.
  const OverlayPlacement wide = place_overlay(panel, 400, 230, 380, 40, 960, 600);
  EXPECT_FALSE(wide.compact);
  EXPECT_EQ(wide.x, 960 - 10 - 400);
  EXPECT_EQ(wide.y, 10);
  // The panel hidden or folded to its title bar (348x20): top right, compact at 512x512, where the
  // full form would hide 35 % of the image; full from about 610x610.
  for (const Rect folded : {Rect{}, Rect{10, 10, 348, 20}}) {
    const OverlayPlacement small = place_overlay(folded, 400, 230, 380, 40, 512, 512);
    EXPECT_TRUE(small.compact);
    EXPECT_EQ(small.x, 512 - 10 - 380);
    EXPECT_EQ(small.y, folded.width > 0 ? 512 - 10 - 40 : 10);
    const OverlayPlacement large = place_overlay(folded, 400, 230, 380, 40, 620, 620);
    EXPECT_FALSE(large.compact);
  }
}

TEST(OverlayLayout, ThePanelStartsCollapsedOnlyWhereItWouldHideMuchOfTheImage) {
  const Rect panel{10, 10, 345, 440};  // as drawn open at the monitor scale 1
  EXPECT_TRUE(panel_starts_collapsed(panel, 512, 512));    // the default window: 58 % hidden
  EXPECT_TRUE(panel_starts_collapsed(panel, 96, 72));      // a tiny window: all of it
  EXPECT_FALSE(panel_starts_collapsed(panel, 1280, 720));  // 16 %
  EXPECT_FALSE(panel_starts_collapsed(panel, 960, 600));   // 26 %
  EXPECT_FALSE(panel_starts_collapsed(panel, 700, 700));   // 31 %
  EXPECT_TRUE(panel_starts_collapsed(panel, 640, 480));    // 49 %
  // Only the part inside the window counts; an empty window or panel never collapses it.
  EXPECT_FALSE(panel_starts_collapsed(Rect{900, 900, 345, 440}, 1000, 1000));
  EXPECT_FALSE(panel_starts_collapsed(Rect{}, 512, 512));
  EXPECT_FALSE(panel_starts_collapsed(panel, 0, 0));
}

TEST(OverlayLayout, ATallPanelSendsTheOverlayBelowOrBeside) {
  // The panel dragged to the top right: the overlay takes another corner in full.
  const Rect panel{600, 10, 350, 400};
  const OverlayPlacement at = place_overlay(panel, 400, 230, 380, 40, 960, 600);
  EXPECT_FALSE(at.compact);
  EXPECT_FALSE(overlaps({at.x, at.y, 400, 230}, panel));
}

}  // namespace
}  // namespace epi::viewer

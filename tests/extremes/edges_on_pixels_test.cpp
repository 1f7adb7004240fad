// Analytic scenes with a known image: an emissive half-plane, quadrant and triangle whose edges lie
// exactly on pixel borders, corners and diagonals through pixel corners, seen with a camera whose
// pixels are exactly one unit wide at the plane (eye at height 32, 90-degree field of view, 64x64).
// The camera steps by whole pixels, so the edges stay on pixel borders in every frame.
#include <algorithm>
#include <cmath>

#include "epi/reconstruct.h"
#include "extremes.h"

namespace epi::extremes {
namespace {

constexpr float kEmission = 0.5f;

// An emissive, unlit polygon (triangles fanned from the first vertex) on z = 0, facing +z.
Scene emissive_polygon(std::vector<glm::vec3> corners) {
  Scene scene;
  const uint32_t m = add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(kEmission));
  Mesh mesh;
  mesh.positions = corners;
  for (uint32_t k = 1; k + 1 < corners.size(); ++k) mesh.triangles.push_back({0, k, k + 1});
  finish_mesh(mesh, m);
  add_object(scene, mesh, "polygon");
  return scene;
}

// Eye above (x, y) at height 32 looking straight down, image y up = world y: pixel (i, j) of a
// 64x64 image covers world x in [x + i - 32, x + i - 31], y in [y + 31 - j, y + 32 - j].
Camera above(float x, float y, int w = 64, int h = 64, float yfov = 90.0f) {
  Camera c;
  c.eye = {x, y, 32.0f}, c.target = {x, y, 0.0f}, c.up = {0.0f, 1.0f, 0.0f}, c.yfov_degrees = yfov;
  (void)w, (void)h;
  return c;
}

// The camera steps one pixel (one unit) at a time from x = -3 to 0, then rests.
std::vector<Camera> stepping() {
  std::vector<Camera> cameras;
  for (int k = -3; k <= 0; ++k) cameras.push_back(above(float(k), 0.0f));
  for (int k = 0; k < 6; ++k) cameras.push_back(above(0.0f, 0.0f));
  return cameras;
}

// Compares every pixel with its expected coverage (0, 1, or a band for crossed pixels).
struct Expect {
  int wrong = 0;
  std::string first;
  void check(const RgbImage& image, int x, int y, float lo, float hi) {
    const float v = image.at(x, y)[0];
    if (v >= lo && v <= hi) return;
    if (wrong++ == 0) first = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is " + std::to_string(v) +
                              ", expected [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  }
};

constexpr float kTol = 0.02f;  // sRGB8 storage of 0.5 and exact area coverage
// The boundary masks record where an edge crosses a pixel side to 1/8 of a pixel, and the
// anti-aliasing takes the middle of that eighth: an edge exactly on a pixel border is drawn 1/16 of
// a pixel inside one of the two pixels beside it (measured: 1/16 of the colour step, into the pixel
// right of or below the border). This is the method's precision (the paper's 1/8-pixel masks), the
// bound docs/reliability.md ("Extremes") states: pixels beside the border may be off by 1/16.
constexpr float kBleed = kEmission / 16.0f + kTol;

TEST(EdgesOnPixelBorders, AVerticalEdgeOnAPixelBorderCoversWholeColumns) {
  // World x <= 0 is lit: image columns 0..31 full, 32..63 empty.
  const Scene scene = emissive_polygon({{-100, -100, 0}, {0, -100, 0}, {0, 100, 0}, {-100, 100, 0}});
  const Rendered run = render_frames(scene, stepping(), settings(64, 64, 0.3));
  EXPECT_EQ(run.insane, 0u);
  Expect e;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float full = x < 32 ? kEmission : 0.0f;
      const float off = x == 31 || x == 32 ? kBleed : kTol;  // beside the border
      e.check(run.image, x, y, full - off, full + off);
    }
  EXPECT_EQ(e.wrong, 0) << e.first;
  EXPECT_GT(run.stats.edges.border, 0);
}

TEST(EdgesOnPixelBorders, AQuadrantCornerOnAPixelCornerCoversWholePixels) {
  // World x <= 0, y <= 0 is lit: columns 0..31 of rows 32..63.
  const Scene scene = emissive_polygon({{-100, -100, 0}, {0, -100, 0}, {0, 0, 0}, {-100, 0, 0}});
  const Rendered run = render_frames(scene, stepping(), settings(64, 64, 0.3));
  EXPECT_EQ(run.insane, 0u);
  Expect e;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float full = x < 32 && y >= 32 ? kEmission : 0.0f;
      const bool beside_x = (x == 31 || x == 32) && y >= 31, beside_y = (y == 31 || y == 32) && x <= 32;
      const float off = beside_x && beside_y ? 2.0f * kBleed : beside_x || beside_y ? kBleed : kTol;
      e.check(run.image, x, y, full - off, full + off);
    }
  EXPECT_EQ(e.wrong, 0) << e.first;
}

TEST(EdgesOnPixelBorders, ADiagonalThroughPixelCornersHalfCoversThePixelsItCrosses) {
  // World y <= x is lit: pixel (i, j) spans i + j in [i + j, i + j + 2] of x_img + y_img; lit where
  // x_img + y_img > 64: full when i + j >= 64, empty when i + j <= 62, half when i + j == 63.
  const Scene scene = emissive_polygon({{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}});
  const Rendered run = render_frames(scene, stepping(), settings(64, 64, 0.3));
  EXPECT_EQ(run.insane, 0u);
  Expect e;
  int half = 0;
  for (int y = 1; y < 63; ++y)
    for (int x = 1; x < 63; ++x) {
      if (x + y >= 64) e.check(run.image, x, y, kEmission - kTol, kEmission + kTol);
      else if (x + y <= 62) e.check(run.image, x, y, 0.0f, kTol);
      else e.check(run.image, x, y, 0.5f * kEmission - 0.1f, 0.5f * kEmission + 0.1f), ++half;
    }
  EXPECT_EQ(e.wrong, 0) << e.first << " (" << half << " crossed pixels)";
}

// A one-row and a one-column image of the half-plane: the field of view chosen so that the row's
// 64 pixels are again one unit wide; the edge lies on the border between pixels 31 and 32.
TEST(EdgesOnPixelBorders, OneRowAndOneColumnImagesPutTheEdgeOnTheirMiddleBorder) {
  const float yfov = float(2.0 * std::atan(1.0 / 64.0) * 180.0 / M_PI);  // 64x1: half-width 1 at unit depth
  {
    const Scene scene = emissive_polygon({{-100, -100, 0}, {0, -100, 0}, {0, 100, 0}, {-100, 100, 0}});
    std::vector<Camera> cameras;
    for (int k = -3; k <= 0; ++k) cameras.push_back(above(float(k), 0.0f, 64, 1, yfov));
    for (int k = 0; k < 8; ++k) cameras.push_back(above(0.0f, 0.0f, 64, 1, yfov));
    const Rendered run = render_frames(scene, cameras, settings(64, 1, 0.3));
    EXPECT_EQ(run.insane, 0u);
    Expect e;
    for (int x = 0; x < 64; ++x) {
      const float full = x < 32 ? kEmission : 0.0f, off = x == 31 || x == 32 ? kBleed : kTol;
      e.check(run.image, x, 0, full - off, full + off);
    }
    EXPECT_EQ(e.wrong, 0) << "64x1: " << e.first;
  }
  {
    // World y <= 0 lit: rows 32..63 of a 1x64 column (90 degrees: rows one unit tall).
    const Scene scene = emissive_polygon({{-100, -100, 0}, {100, -100, 0}, {100, 0, 0}, {-100, 0, 0}});
    std::vector<Camera> cameras;
    for (int k = -3; k <= 0; ++k) cameras.push_back(above(0.0f, float(k)));
    for (int k = 0; k < 8; ++k) cameras.push_back(above(0.0f, 0.0f));
    const Rendered run = render_frames(scene, cameras, settings(1, 64, 0.3));
    EXPECT_EQ(run.insane, 0u);
    Expect e;
    for (int y = 0; y < 64; ++y) {
      const float full = y >= 32 ? kEmission : 0.0f, off = y == 31 || y == 32 ? kBleed : kTol;
      e.check(run.image, 0, y, full - off, full + off);
    }
    EXPECT_EQ(e.wrong, 0) << "1x64: " << e.first;
  }
}

TEST(EdgesOnPixelBorders, AOnePixelImageShowsWhatItsCentreSees) {
  const Scene scene = emissive_polygon({{-100, -100, 0}, {0, -100, 0}, {0, 100, 0}, {-100, 100, 0}});
  const float yfov = 1.0f;  // the pixel covers about 0.56 units at height 32
  std::vector<Camera> lit, dark;
  for (int k = 0; k < 6; ++k) lit.push_back(above(-5.0f + 0.5f * float(k), 0.0f, 1, 1, yfov));
  for (int k = 0; k < 6; ++k) dark.push_back(above(5.0f - 0.5f * float(k), 0.0f, 1, 1, yfov));
  const Rendered a = render_frames(scene, lit, settings(1, 1, 1.0));
  const Rendered b = render_frames(scene, dark, settings(1, 1, 1.0));
  EXPECT_EQ(a.insane + b.insane, 0u);
  EXPECT_NEAR(a.image.pixels[0], kEmission, kTol);
  EXPECT_NEAR(b.image.pixels[0], 0.0f, kTol);
  EXPECT_EQ(a.stats.samples, 1u);  // a budget of 100 % of one pixel
}

// The 2D pipeline alone: a vertical edge through the centres of column 32 that starts exactly on
// the image's top border (as pattern edges and clipped edges may). Red samples left of it, blue
// right: no pixel of row 0 mixes the two (before the fix in core/epi/rasterize.cpp the first row's
// pixels reached across: the crossing on the border line was not recorded).
TEST(EdgesOnPixelBorders, AnEdgeStartingOnTheImageBorderSeparatesTheFirstRow) {
  const float red[3] = {0.8f, 0.05f, 0.05f}, blue[3] = {0.05f, 0.1f, 0.8f};
  for (const bool transposed : {false, true}) {
    SCOPED_TRACE(transposed);
    EpiImage epi(64, 64);
    BoundaryMasks masks(64, 64, true);
    const Segment s = transposed ? Segment{0.0, 32.5, 64.0, 32.5} : Segment{32.5, 0.0, 32.5, 64.0};
    rasterize_edges(masks, std::span(&s, 1));
    for (int a = 1; a < 64; a += 2)
      for (int b = 1; b < 64; b += 2) {
        const int x = transposed ? b : a, y = transposed ? a : b;
        epi.set_sample(x, y, 0.5, 0.5, a < 32 ? red : blue);
      }
    const Reconstruction out = reconstruct_tiled(epi, masks, ReconstructSettings{});
    int wrong = 0;
    std::string first;
    for (int a = 0; a < 64; ++a)
      for (int b = 0; b < 64; ++b) {
        if (a == 32) continue;  // halved by the edge
        const int x = transposed ? b : a, y = transposed ? a : b;
        const float* want = a < 32 ? red : blue;
        const float* p = out.image.at(x, y);
        for (int c = 0; c < 3; ++c)
          if (std::abs(p[c] - want[c]) > 0.02f) {
            if (wrong++ == 0) first = "(" + std::to_string(x) + ", " + std::to_string(y) + "): " + std::to_string(p[0]);
            break;
          }
      }
    EXPECT_EQ(wrong, 0) << first;
  }
}

}  // namespace
}  // namespace epi::extremes

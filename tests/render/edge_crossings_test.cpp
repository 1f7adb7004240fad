// EdgeCrossings (the occlusion test's "is there an edge between these two points?") against a
// brute-force test of every piece, and the occlusion test at pixels an edge crosses.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/edge_crossings.h"
#include "render/point_cache.h"

namespace epi::render {
namespace {

using edges::EdgeKind;

// Brute force: parametric intersection of the two closed segments (no degenerate cases drawn);
// `u` is where along s.
bool crosses(glm::dvec2 a, glm::dvec2 b, const Segment& s, double& u) {
  const glm::dvec2 r = b - a, q{s.x1 - s.x0, s.y1 - s.y0}, d{s.x0 - a.x, s.y0 - a.y};
  const double den = r.x * q.y - r.y * q.x;
  if (den == 0.0) return false;
  const double t = (d.x * q.y - d.y * q.x) / den;
  u = (d.x * r.y - d.y * r.x) / den;
  return t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0;
}
bool crosses(glm::dvec2 a, glm::dvec2 b, const Segment& s) {
  double u;
  return crosses(a, b, s, u);
}

// The occlusion tests' view: looking down -z from z = 10 at planes z = const.
ViewFrame planes_view(int w, int h) {
  View view;
  view.camera.eye = {0, 0, 10}, view.camera.target = {0, 0, 0}, view.camera.up = {0, 1, 0};
  view.camera.yfov_degrees = 40.0f, view.width = w, view.height = h;
  return ViewFrame(view);
}

// A grey hit of the plane z = plane_z (normal +z) seen at pixel position (px, py).
ShadeResult plane_hit(const ViewFrame& frame, float px, float py, float plane_z, uint32_t object) {
  const Ray ray = frame.ray(px, py);
  ShadeResult r;
  r.x = px, r.y = py, r.hit = true, r.object = object;
  r.position = ray.origin + (plane_z - ray.origin.z) / ray.direction.z * ray.direction;
  r.normal = {0, 0, 1}, r.color = glm::vec3(0.5f);
  return r;
}

// any_piece_near: true for every rectangle a barrier piece passes through (points along each piece
// checked one by one), false for every rectangle no piece comes within a cell of; shadow pieces
// never count. Pieces and rectangles inside the image (the occlusion test's windows are cut to it).
TEST(EdgeCrossings, AnyPieceNearFindsEveryPieceInARectangle) {
  std::mt19937 rng(11);
  const int w = 83, h = 57;
  std::uniform_real_distribution<double> x(0.0, w), y(0.0, h);
  std::uniform_int_distribution<int> size(0, 12);
  for (int round = 0; round < 30; ++round) {
    std::vector<Segment> segments;
    std::vector<EdgeKind> kinds;
    for (int k = 0; k < 6; ++k) {
      segments.push_back({x(rng), y(rng), x(rng), y(rng)});
      kinds.push_back(k % 3 == 2 ? EdgeKind::shadow : EdgeKind::silhouette);
    }
    EdgeCrossings crossings;
    crossings.build(segments, kinds, w, h);
    for (int q = 0; q < 200; ++q) {
      const int x0 = std::uniform_int_distribution<int>(0, w - 1)(rng), y0 = std::uniform_int_distribution<int>(0, h - 1)(rng);
      const int x1 = std::min(w - 1, x0 + size(rng)), y1 = std::min(h - 1, y0 + size(rng));
      // The least distance (in x or y, pixels) from the rectangle to a barrier piece's points.
      double nearest = 1e9;
      for (size_t k = 0; k < segments.size(); ++k) {
        if (kinds[k] == EdgeKind::shadow) continue;
        const Segment& s = segments[k];
        for (int t = 0; t <= 2000; ++t) {
          const double px = s.x0 + (s.x1 - s.x0) * t / 2000.0, py = s.y0 + (s.y1 - s.y0) * t / 2000.0;
          const double dx = std::max({double(x0) - px, px - double(x1 + 1), 0.0});
          const double dy = std::max({double(y0) - py, py - double(y1 + 1), 0.0});
          nearest = std::min(nearest, std::max(dx, dy));
        }
      }
      const bool near = crossings.any_piece_near(x0, y0, x1, y1);
      if (nearest < 0.01) {
        EXPECT_TRUE(near) << x0 << "," << y0 << " " << x1 << "," << y1;
      }
      if (nearest > EdgeCrossings::kCell + 0.01) {
        EXPECT_FALSE(near) << x0 << "," << y0 << " " << x1 << "," << y1;
      }
    }
  }
  EdgeCrossings empty;
  empty.build({}, {}, w, h);
  EXPECT_FALSE(empty.any_piece_near(0, 0, w, h));
}

TEST(EdgeCrossings, AgreesWithTestingEveryBarrierPiece) {
  std::mt19937 rng(7);
  const int w = 97, h = 61;
  std::uniform_real_distribution<double> x(-20.0, w + 20.0), y(-20.0, h + 20.0), step(-2.5, 2.5), len(-30.0, 30.0);
  for (int round = 0; round < 20; ++round) {
    std::vector<Segment> segments;
    std::vector<EdgeKind> kinds;
    const EdgeKind all[] = {EdgeKind::silhouette, EdgeKind::border, EdgeKind::sharp, EdgeKind::shadow, EdgeKind::umbral};
    for (int k = 0; k < 60; ++k) {
      const double x0 = x(rng), y0 = y(rng);
      segments.push_back({x0, y0, x0 + len(rng), y0 + len(rng)});
      kinds.push_back(all[rng() % 5]);
    }
    EdgeCrossings crossings;
    crossings.build(segments, kinds, w, h);
    int separated = 0;
    for (int k = 0; k < 2000; ++k) {
      const glm::dvec2 a{std::uniform_real_distribution<double>(0.0, w)(rng), std::uniform_real_distribution<double>(0.0, h)(rng)};
      const glm::dvec2 b = a + glm::dvec2(step(rng), step(rng));
      bool expected = false;
      for (size_t s = 0; s < segments.size(); ++s)
        expected |= (kinds[s] == EdgeKind::silhouette || kinds[s] == EdgeKind::border || kinds[s] == EdgeKind::sharp) &&
                    crosses(a, b, segments[s]);
      ASSERT_EQ(crossings.separated(a, b), expected) << round << " " << k;
      separated += expected;
    }
    EXPECT_GT(separated, 20);  // the test sees both answers
  }
}

// With depths: a piece counts only where it is nearer than the limit at the crossing (1/depth
// interpolated along the piece), against every piece tested in turn, over random pieces (many
// reaching past the image, so clipped), depths and limits; the limit +inf counts every piece.
TEST(EdgeCrossings, OnlyPiecesNearerThanTheLimitWhereTheyCrossCount) {
  std::mt19937 rng(17);
  const int w = 97, h = 61;
  std::uniform_real_distribution<double> x(-20.0, w + 20.0), y(-20.0, h + 20.0), step(-4.0, 4.0), len(-30.0, 30.0);
  std::uniform_real_distribution<double> depth(1.0, 20.0);
  int counted = 0, behind = 0;
  for (int round = 0; round < 20; ++round) {
    std::vector<Segment> segments;
    std::vector<EdgeKind> kinds;
    std::vector<glm::dvec2> inv;
    for (int k = 0; k < 60; ++k) {
      const double x0 = x(rng), y0 = y(rng);
      segments.push_back({x0, y0, x0 + len(rng), y0 + len(rng)});
      kinds.push_back(k % 4 ? EdgeKind::silhouette : EdgeKind::shadow);
      inv.emplace_back(1.0 / depth(rng), 1.0 / depth(rng));
    }
    EdgeCrossings crossings;
    crossings.build(segments, kinds, w, h, inv);
    for (int k = 0; k < 2000; ++k) {
      const glm::dvec2 a{std::uniform_real_distribution<double>(0.0, w)(rng), std::uniform_real_distribution<double>(0.0, h)(rng)};
      const glm::dvec2 b = a + glm::dvec2(step(rng), step(rng));
      const double limit = depth(rng);
      bool expected = false, any = false;
      for (size_t s = 0; s < segments.size(); ++s) {
        double u;
        if (kinds[s] != EdgeKind::silhouette || !crosses(a, b, segments[s], u)) continue;
        any = true;
        expected |= 1.0 / (inv[s].x + u * (inv[s].y - inv[s].x)) < limit;
      }
      ASSERT_EQ(crossings.separated(a, b, limit), expected) << round << " " << k;
      ASSERT_EQ(crossings.separated(a, b), any) << round << " " << k;
      counted += expected, behind += any && !expected;
    }
  }
  EXPECT_GT(counted, 50);  // both answers, and pieces ignored for their depth
  EXPECT_GT(behind, 50);
  EdgeCrossings mismatched;
  EXPECT_THROW(mismatched.build(std::vector<Segment>(2), std::vector<EdgeKind>(2), 8, 8, std::vector<glm::dvec2>(1)),
               std::invalid_argument);
}

TEST(EdgeCrossings, ExtremesOnGridLinesEndpointsHugeAndEmpty) {
  EdgeCrossings none;
  none.build({}, {}, 8, 8);
  EXPECT_FALSE(none.separated({1, 1}, {6, 6}));
  const std::vector<Segment> segments = {{4.0, -1e9, 4.0, 1e9},               // a grid line, far past the image
                                         {0.0, 0.0, 0.0, 0.0},                // a point
                                         {NAN, 0.0, 1.0, 1.0}};               // not finite: ignored
  const std::vector<EdgeKind> kinds(3, EdgeKind::silhouette);
  EdgeCrossings crossings;
  crossings.build(segments, kinds, 8, 8);
  EXPECT_TRUE(crossings.separated({3.5, 2.0}, {4.5, 2.0}));
  EXPECT_TRUE(crossings.separated({3.0, 7.9}, {4.0, 7.9}));  // ends on the line: touching counts
  EXPECT_FALSE(crossings.separated({4.1, 0.1}, {7.9, 7.9}));
  EXPECT_TRUE(crossings.separated({0.0, 0.0}, {1.0, 1.0}));  // through the point piece
  EXPECT_FALSE(crossings.separated({1.0, 0.5}, {2.0, 0.5}));
}

// A cache given the far results, projected, then the near ones (objects 0 and 1, identity
// transforms), projected and put through the occlusion test with these edges.
PointCache near_over_far(const ViewFrame& frame, const ShadeBatch& far, const ShadeBatch& near,
                         const PointCacheSettings& settings, const EdgeCrossings& crossings) {
  const std::vector<glm::mat4> identity(2, glm::mat4(1.0f));
  PointCache cache(frame.view().width, frame.view().height, settings);
  cache.insert(frame, far, identity);
  cache.project(frame, identity, false);
  cache.insert(frame, near, identity);
  cache.project(frame, identity, false);
  cache.cull_behind_surfaces(frame, identity, crossings);
  return cache;
}

// A far plane (z = -5, object 0) sampled at every pixel's centre.
ShadeBatch far_plane(const ViewFrame& frame) {
  ShadeBatch far;
  for (int y = 0; y < frame.view().height; ++y)
    for (int x = 0; x < frame.view().width; ++x) far.results.push_back(plane_hit(frame, float(x) + 0.5f, float(y) + 0.5f, -5.0f, 0));
  return far;
}

// The same with no edge anywhere and the given sparse occlusion radius (the new-occluder rule
// off: the near results land in front of the far points, so it would act on them too).
PointCache near_over_far(const ViewFrame& frame, const ShadeBatch& far, const ShadeBatch& near, int sparse_radius) {
  PointCacheSettings settings;
  settings.sparse_occlusion_radius = sparse_radius;
  settings.new_occluder_radius = 0;
  EdgeCrossings none;
  none.build({}, {}, frame.view().width, frame.view().height);
  return near_over_far(frame, far, near, settings, none);
}

// A near plane over the left part of the image in front of a far plane, its silhouette at
// x = 7.6. Far points on the near plane's side of the silhouette are hidden, also inside the
// pixel the silhouette crosses; those beyond it are not, also inside that pixel.
TEST(PointCache, TheOcclusionTestActsInsidePixelsAnEdgeCrossesOnTheNearSideOnly) {
  const int w = 16, h = 8;
  const ViewFrame frame = planes_view(w, h);
  auto hit = [&](float px, float py, float plane_z, uint32_t object) { return plane_hit(frame, px, py, plane_z, object); };
  ShadeBatch far, near;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) far.results.push_back(hit(float(x) + (x == 7 && y % 2 ? 0.9f : 0.5f), float(y) + 0.5f, -5.0f, 0));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x <= 6; ++x) near.results.push_back(hit(float(x) + 0.5f, float(y) + 0.5f, 1.0f, 1));
  const std::vector<Segment> silhouette = {{7.6, -1.0, 7.6, h + 1.0}};
  const std::vector<EdgeKind> kinds = {EdgeKind::silhouette};
  for (const bool with_edge : {true, false}) {
    EdgeCrossings crossings;
    if (with_edge) crossings.build(silhouette, kinds, w, h);
    const PointCache cache = near_over_far(frame, far, near, PointCacheSettings{}, crossings);
    const PointImage& image = cache.image();
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x <= 6; ++x) ASSERT_GE(image.point[image.index(x, y)], 0);  // the near plane
      const bool far_point_left_of_edge = y % 2 == 0;
      EXPECT_EQ(image.point[image.index(7, y)] >= 0, with_edge && !far_point_left_of_edge) << y;
      EXPECT_EQ(image.point[image.index(8, y)] >= 0, with_edge) << y;  // 2 px from the near points
      for (int x = 9; x < w; ++x) EXPECT_GE(image.point[image.index(x, y)], 0);  // no near point within 2 px
    }
  }
}

// A near plane sampled only every 6 pixels (as a surface the camera approaches is, magnified
// between its samples) over a densely sampled far plane, no edge anywhere: every far point is
// hidden, also those 3 and 4 pixels from the nearest near point, which the 2-pixel test alone
// left drawn (the dark floor dots on rooms' table top along its path: docs/render.md, "Sparse
// near surfaces"). The dense near plane of the test above keeps the far points 3 or more pixels
// beyond its last column: a point with near neighbours is no lone sample of a sparse surface.
TEST(PointCache, FarPointsBetweenTheSamplesOfASparseNearSurfaceAreHidden) {
  const int w = 24, h = 14;
  const ViewFrame frame = planes_view(w, h);
  auto hit = [&](float px, float py, float plane_z, uint32_t object) { return plane_hit(frame, px, py, plane_z, object); };
  const ShadeBatch far = far_plane(frame);
  ShadeBatch near;
  for (int y = 1; y < h; y += 6)
    for (int x = 1; x < w; x += 6) near.results.push_back(hit(float(x) + 0.5f, float(y) + 0.5f, 1.0f, 1));
  // 15: the largest radius (a 31-pixel window row, one 32-bit mask, wider than the image).
  for (const int sparse_radius : {0, 4, 8, kMaxOcclusionRadius}) {
    const PointCache cache = near_over_far(frame, far, near, sparse_radius);
    const PointImage& image = cache.image();
    size_t near_drawn = 0, far_drawn = 0;
    for (size_t i = 0; i < image.point.size(); ++i)
      if (image.point[i] >= 0) (cache.points()[size_t(image.point[i])].object == 1 ? near_drawn : far_drawn) += 1;
    EXPECT_EQ(near_drawn, near.results.size()) << sparse_radius;
    if (sparse_radius == 0) {
      EXPECT_GT(far_drawn, 100u);  // 3 or 4 pixels from every near point
    } else {
      EXPECT_EQ(far_drawn, 0u) << sparse_radius;
    }
  }
  PointCacheSettings too_wide;
  too_wide.sparse_occlusion_radius = kMaxOcclusionRadius + 1;
  EXPECT_THROW(PointCache(w, h, too_wide), std::invalid_argument);
  too_wide = {};
  too_wide.occlusion_radius = kMaxOcclusionRadius + 1;
  EXPECT_THROW(PointCache(w, h, too_wide), std::invalid_argument);
}

// One lone near point over a dense far plane: the far points it hides are exactly those within
// sparse_occlusion_radius of it (Chebyshev distance; its tangent plane is parallel to the far
// plane), for every radius up to the largest, with the window whole or cut by the image's border.
TEST(PointCache, ALoneNearPointHidesTheFarPointsWithinTheSparseRadius) {
  const int w = 40, h = 34;
  const ViewFrame frame = planes_view(w, h);
  const ShadeBatch far = far_plane(frame);
  for (const auto& [nx, ny] : {std::pair{20, 17}, std::pair{1, 2}, std::pair{w - 1, h - 3}})
    for (const int radius : {3, 4, 8, 13, kMaxOcclusionRadius}) {
      ShadeBatch near;
      near.results.push_back(plane_hit(frame, float(nx) + 0.5f, float(ny) + 0.5f, 1.0f, 1));
      const PointCache cache = near_over_far(frame, far, near, radius);
      const PointImage& image = cache.image();
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          if (x == nx && y == ny) continue;  // the near point itself
          const bool within = std::max(std::abs(x - nx), std::abs(y - ny)) <= radius;
          ASSERT_EQ(image.point[image.index(x, y)] < 0, within) << "near point " << nx << "," << ny << ", radius "
                                                                << radius << ", far point " << x << "," << y;
        }
    }
}

// The background seen at every pixel's centre (results that hit nothing: background points).
ShadeBatch background(const ViewFrame& frame) {
  ShadeBatch sky;
  for (int y = 0; y < frame.view().height; ++y)
    for (int x = 0; x < frame.view().width; ++x) {
      ShadeResult r;
      r.x = float(x) + 0.5f, r.y = float(y) + 0.5f, r.hit = false;
      sky.results.push_back(r);
    }
  return sky;
}

// A surface the camera has just revealed where it used to see the background (chains' floor after
// a fast orbit: black dots) is sampled sparsely, in pairs of points, among the background points
// of every pixel. A pair is no lone sample, so the sparse rule leaves a far plane's points
// between the pairs drawn; background points there, with no barrier edge within 8 pixels, are all
// hidden (docs/render.md, "Stray background points"). With a silhouette down the image, the
// background points within 8 pixels of it are not stray: those 3 or more pixels from every pair
// stay, and every one beyond the silhouette, where no surface is, stays.
TEST(PointCache, StrayBackgroundPointsAmidASparseSurfaceAreHidden) {
  const int w = 40, h = 30;
  const ViewFrame frame = planes_view(w, h);
  ShadeBatch pairs;
  for (int y = 2; y < h; y += 6)
    for (int x = 2; x < 20; x += 6)
      for (int dx : {0, 1}) pairs.results.push_back(plane_hit(frame, float(x + dx) + 0.5f, float(y) + 0.5f, 1.0f, 1));
  auto drawn = [](const PointCache& cache, uint32_t object, int x_from, int x_to) {
    size_t n = 0;
    const PointImage& image = cache.image();
    for (int y = 0; y < image.height; ++y)
      for (int x = x_from; x < x_to; ++x) {
        const int32_t p = image.point[image.index(x, y)];
        n += p >= 0 && cache.points()[size_t(p)].object == object;
      }
    return n;
  };
  PointCacheSettings settings;  // the defaults: dense radius 2, sparse 4
  settings.new_occluder_radius = 0;
  EdgeCrossings none;
  none.build({}, {}, w, h);
  // The far plane between the pairs (columns 2-3, 8-9, 14-15; rows 2, 8, ..., 26): drawn 3 or
  // more pixels from every pair, in rows 5, 11, ..., 29 and columns 18 and 19.
  const size_t beyond_3_pixels = 5 * 20 + 25 * 2;
  const PointCache plane = near_over_far(frame, far_plane(frame), pairs, settings, none);
  EXPECT_EQ(drawn(plane, 0, 0, 20), beyond_3_pixels);
  // The background there: hidden wherever a pair lies within 8 pixels, so up to x = 23.
  const PointCache sky = near_over_far(frame, background(frame), pairs, settings, none);
  EXPECT_EQ(drawn(sky, kNone, 0, 24), 0u);
  EXPECT_EQ(drawn(sky, kNone, 24, w), size_t((w - 24) * h));
  EXPECT_EQ(drawn(sky, 1, 0, w), pairs.results.size());
  // A silhouette at x = 21.5 (the surface's outline): no stray background near it.
  EdgeCrossings outline;
  outline.build(std::vector<Segment>{{21.5, -1.0, 21.5, h + 1.0}}, std::vector<EdgeKind>{EdgeKind::silhouette}, w, h);
  const PointCache edged = near_over_far(frame, background(frame), pairs, settings, outline);
  EXPECT_EQ(drawn(edged, kNone, 22, w), size_t((w - 22) * h));
  EXPECT_GT(drawn(edged, kNone, 12, 22), 20u);  // near the outline (its 4-pixel cell within 8): the other rules only
  EXPECT_EQ(drawn(edged, kNone, 0, 12), 0u);    // farther from it: stray, hidden
  // Without the sparse rule there is no stray rule either.
  settings.sparse_occlusion_radius = 0;
  EXPECT_EQ(drawn(near_over_far(frame, background(frame), pairs, settings, none), kNone, 0, 20), beyond_3_pixels);
}

// Which far points (object 0) are drawn: one flag per pixel.
std::vector<bool> far_drawn(const PointCache& cache) {
  const PointImage& image = cache.image();
  std::vector<bool> drawn(image.point.size());
  for (size_t i = 0; i < drawn.size(); ++i) drawn[i] = image.point[i] >= 0 && cache.points()[size_t(image.point[i])].object == 0;
  return drawn;
}

// A lone near result that lands in front of the far point drawn at its pixel is a new occluder
// (an object that has just come in front, docs/render.md "New occluders"): for
// new_occluder_frames projections it hides the far points within new_occluder_radius (Chebyshev
// distance), then only those within sparse_occlusion_radius, for every radius up to the largest,
// with the window whole or cut by the image's border. A near point shaded before the far ones
// were drawn is no new occluder: the sparse radius only.
TEST(PointCache, ANewOccluderHidesTheFarPointsWithinItsRadiusForAFewFrames) {
  const int w = 40, h = 34;
  const ViewFrame frame = planes_view(w, h);
  const ShadeBatch far = far_plane(frame);
  const std::vector<glm::mat4> identity(2, glm::mat4(1.0f));
  EdgeCrossings none;
  none.build({}, {}, w, h);
  for (const auto& [nx, ny] : {std::pair{20, 17}, std::pair{1, 2}, std::pair{w - 1, h - 3}})
    for (const int radius : {5, 8, 13, kMaxOcclusionRadius}) {
      PointCacheSettings settings;
      settings.new_occluder_radius = radius, settings.new_occluder_frames = 3;
      ShadeBatch near;
      near.results.push_back(plane_hit(frame, float(nx) + 0.5f, float(ny) + 0.5f, 1.0f, 1));
      PointCache cache(w, h, settings);
      cache.insert(frame, far, identity);
      cache.project(frame, identity, false);
      cache.insert(frame, near, identity);
      for (int projection = 0; projection < 5; ++projection) {
        cache.project(frame, identity, false);
        cache.cull_behind_surfaces(frame, identity, none);
        const int reach = projection < settings.new_occluder_frames ? radius : settings.sparse_occlusion_radius;
        const std::vector<bool> drawn = far_drawn(cache);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            if (x == nx && y == ny) continue;  // the near point itself
            const bool within = std::max(std::abs(x - nx), std::abs(y - ny)) <= reach;
            ASSERT_EQ(drawn[size_t(y * w + x)], !within) << "near point " << nx << "," << ny << ", radius " << radius
                                                         << ", projection " << projection << ", far point " << x << "," << y;
          }
      }
    }
  // The near result first, the far plane after it (nothing was drawn where the near one landed),
  // then a result a little nearer at the near point's pixel (by less than kNewOccluderMargin: not
  // in front of it). Neither is a new occluder.
  PointCache cache(w, h, PointCacheSettings{});
  ShadeBatch near, nearer;
  near.results.push_back(plane_hit(frame, 20.5f, 17.5f, 1.0f, 1));
  nearer.results.push_back(plane_hit(frame, 20.5f, 17.5f, 1.5f, 1));  // depth 8.5 where 9 is drawn
  cache.insert(frame, near, identity);
  cache.project(frame, identity, false);
  cache.insert(frame, far, identity);
  cache.project(frame, identity, false);
  cache.insert(frame, nearer, identity);
  cache.project(frame, identity, false);
  cache.cull_behind_surfaces(frame, identity, none);
  const std::vector<bool> drawn = far_drawn(cache);
  size_t hidden = 0;
  for (size_t i = 0; i < drawn.size(); ++i) hidden += !drawn[i];
  EXPECT_EQ(hidden, size_t(9 * 9));  // the sparse radius' window (4), the near point's pixel included
  PointCacheSettings too_wide;
  too_wide.new_occluder_radius = kMaxOcclusionRadius + 1;
  EXPECT_THROW(PointCache(w, h, too_wide), std::invalid_argument);
}

// Asserts that exactly the far points within Chebyshev distance `reach` of the near point
// (nx, ny) and at x <= last_x are hidden (the near point's own pixel not checked).
void expect_hidden_within(const std::vector<bool>& drawn, int w, int h, int nx, int ny, int reach, int last_x,
                          const std::string& context) {
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (x == nx && y == ny) continue;
      const bool within = std::max(std::abs(x - nx), std::abs(y - ny)) <= reach && x <= last_x;
      ASSERT_EQ(drawn[size_t(y * w + x)], !within) << context << ", far point " << x << "," << y;
    }
}

// A new occluder does not hide across an edge: a silhouette 3.4 pixels to the right of the near
// point keeps every far point beyond it, at the new-occluder radius as at the smaller ones.
TEST(PointCache, ANewOccluderStopsAtAnEdge) {
  const int w = 40, h = 34, nx = 20, ny = 17;
  const ViewFrame frame = planes_view(w, h);
  ShadeBatch near;
  near.results.push_back(plane_hit(frame, float(nx) + 0.5f, float(ny) + 0.5f, 1.0f, 1));
  const std::vector<Segment> silhouette = {{nx + 3.9, -1.0, nx + 3.9, h + 1.0}};
  const std::vector<EdgeKind> kinds = {EdgeKind::silhouette};
  EdgeCrossings crossings;
  crossings.build(silhouette, kinds, w, h);
  const PointCache cache = near_over_far(frame, far_plane(frame), near, PointCacheSettings{}, crossings);
  expect_hidden_within(far_drawn(cache), w, h, nx, ny, PointCacheSettings{}.new_occluder_radius, nx + 3, "edge");
}

// An edge behind a new occluder does not stop it: the same silhouette as above at the far
// plane's depth (the far objects' own edges) lets it hide every far point within its radius,
// while at the near plane's depth it stops it as before. A lone point that is no new occluder
// keeps stopping at any edge (only new occluders look at the edges' depth).
TEST(PointCache, AnEdgeBehindANewOccluderDoesNotStopIt) {
  const int w = 40, h = 34, nx = 20, ny = 17;
  const ViewFrame frame = planes_view(w, h);
  ShadeBatch near;
  near.results.push_back(plane_hit(frame, float(nx) + 0.5f, float(ny) + 0.5f, 1.0f, 1));  // depth 9
  const std::vector<Segment> silhouette = {{nx + 3.9, -1.0, nx + 3.9, h + 1.0}};
  const std::vector<EdgeKind> kinds = {EdgeKind::silhouette};
  const int radius = PointCacheSettings{}.new_occluder_radius;
  for (const double edge_depth : {9.0, 11.9, 12.1, 15.0}) {  // the far plane at 15: halfway is 12
    EdgeCrossings crossings;
    crossings.build(silhouette, kinds, w, h, std::vector<glm::dvec2>{{1.0 / edge_depth, 1.0 / edge_depth}});
    const std::vector<bool> drawn = far_drawn(near_over_far(frame, far_plane(frame), near, PointCacheSettings{}, crossings));
    expect_hidden_within(drawn, w, h, nx, ny, radius, edge_depth > 12.0 ? w : nx + 3, "edge at depth " + std::to_string(edge_depth));
  }
  // No new occluder (the near result inserted first): the sparse radius, stopped by the far edge.
  EdgeCrossings crossings;
  crossings.build(silhouette, kinds, w, h, std::vector<glm::dvec2>{{1.0 / 15.0, 1.0 / 15.0}});
  const std::vector<glm::mat4> identity(2, glm::mat4(1.0f));
  PointCache cache(w, h, PointCacheSettings{});
  cache.insert(frame, near, identity);
  cache.project(frame, identity, false);
  cache.insert(frame, far_plane(frame), identity);
  cache.project(frame, identity, false);
  cache.cull_behind_surfaces(frame, identity, crossings);
  expect_hidden_within(far_drawn(cache), w, h, nx, ny, PointCacheSettings{}.sparse_occlusion_radius, nx + 3, "no new occluder");
}

}  // namespace
}  // namespace epi::render

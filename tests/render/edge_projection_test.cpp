// 3D edges into pixel segments: projection against ViewFrame::project, near-plane and frustum
// clipping (property test over random segments), and occlusion culling against filtered depth.
#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "render/edge_projection.h"

namespace epi::render {
namespace {

ViewFrame test_frame(int w = 64, int h = 48) {
  View v;
  v.camera.eye = {0.3f, -0.2f, 6.0f}, v.camera.target = {0, 0, 0}, v.camera.yfov_degrees = 50.0f, v.camera.znear = 0.1f;
  v.width = w, v.height = h;
  return ViewFrame(v);
}

double distance_to_segment(glm::dvec2 p, const Segment& s) {
  const glm::dvec2 a(s.x0, s.y0), b(s.x1, s.y1);
  const glm::dvec2 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

TEST(EdgeProjection, EndpointsInFrontProjectAsViewFrameSays) {
  const ViewFrame frame = test_frame();
  std::vector<Segment> out;
  const glm::dvec3 a(-0.5, 0.2, 0.0), b(0.4, -0.3, 1.0);
  ASSERT_EQ(project_edge(frame, a, b, {}, out), EdgeFate::visible);
  ASSERT_EQ(out.size(), 1u);
  const Projection pa = frame.project(glm::vec3(a)), pb = frame.project(glm::vec3(b));
  EXPECT_NEAR(out[0].x0, pa.pixel.x, 1e-4);
  EXPECT_NEAR(out[0].y0, pa.pixel.y, 1e-4);
  EXPECT_NEAR(out[0].x1, pb.pixel.x, 1e-4);
  EXPECT_NEAR(out[0].y1, pb.pixel.y, 1e-4);
}

TEST(EdgeProjection, BehindTheEyeOrOffScreenIsOutside) {
  const ViewFrame frame = test_frame();
  std::vector<Segment> out;
  EXPECT_EQ(project_edge(frame, {0, 0, 7}, {1, 1, 9}, {}, out), EdgeFate::outside);      // behind
  EXPECT_EQ(project_edge(frame, {40, 0, 0}, {40, 5, 0}, {}, out), EdgeFate::outside);    // far right
  EXPECT_EQ(project_edge(frame, {0.3, -0.2, 6.05}, {0.3, -0.2, 6.09}, {}, out), EdgeFate::outside);  // inside znear
  EXPECT_TRUE(out.empty());
}

// Random segments, many crossing the near plane or the image border: every in-front point of the
// 3D segment that projects inside the image lies on an output piece, and every output point lies
// inside the grown image and on the projection of the segment.
TEST(EdgeProjection, ClippingKeepsExactlyTheVisiblePartOfRandomSegments) {
  const ViewFrame frame = test_frame();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coord(-8.0, 8.0);
  int crossing_near = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const glm::dvec3 a(coord(rng), coord(rng), coord(rng)), b(coord(rng), coord(rng), coord(rng));
    std::vector<Segment> out;
    const EdgeFate fate = project_edge(frame, a, b, {}, out);
    const glm::dvec3 eye(frame.eye()), fwd(frame.forward());
    crossing_near += (glm::dot(a - eye, fwd) - 0.1) * (glm::dot(b - eye, fwd) - 0.1) < 0;
    for (int k = 0; k <= 200; ++k) {
      const glm::dvec3 p = glm::mix(a, b, k / 200.0);
      const Projection proj = frame.project(glm::vec3(p));
      if (!(proj.depth > 0.1 + 1e-6)) continue;
      if (proj.pixel.x < 0 || proj.pixel.y < 0 || proj.pixel.x > 64 || proj.pixel.y > 48) continue;
      ASSERT_EQ(fate, EdgeFate::visible) << trial;
      ASSERT_EQ(out.size(), 1u);
      EXPECT_LT(distance_to_segment(glm::dvec2(proj.pixel), out[0]), 2e-3 * (1.0 + 1.0 / proj.depth)) << trial;
    }
    for (const Segment& s : out)
      for (const glm::dvec2 p : {glm::dvec2(s.x0, s.y0), glm::dvec2(s.x1, s.y1)}) {
        EXPECT_GE(p.x, -1.0 - 1e-9);
        EXPECT_LE(p.x, 65.0 + 1e-9);
        EXPECT_GE(p.y, -1.0 - 1e-9);
        EXPECT_LE(p.y, 49.0 + 1e-9);
      }
  }
  EXPECT_GT(crossing_near, 50);
}

PointImage plane_points(int w, int h, float depth, int hole_x0 = -1, int hole_x1 = -1) {
  PointImage image;
  image.width = w, image.height = h;
  image.point.assign(size_t(w * h), 0);
  image.depth.assign(size_t(w * h), depth);
  image.region.assign(size_t(w * h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = std::max(0, hole_x0); x < hole_x1; ++x) {
      image.point[size_t(y * w + x)] = -1;
      image.depth[size_t(y * w + x)] = std::numeric_limits<float>::infinity();
    }
  return image;
}

TEST(EdgeProjection, FilteredDepthIsTheWindowMaximumPlusASparsenessOffset) {
  PointImage image = plane_points(16, 16, 4.0f);
  image.depth[image.index(5, 5)] = 6.0f;
  image.point[image.index(9, 9)] = -1;  // one empty pixel
  std::vector<float> filtered;
  const DepthFilterSettings s;
  filter_depth(image, s, filtered);
  EXPECT_FLOAT_EQ(filtered[image.index(4, 4)], 6.0f * (1.0f + s.base_offset));  // window x 3..6 holds (5,5)
  EXPECT_FLOAT_EQ(filtered[image.index(7, 3)], 4.0f * (1.0f + s.base_offset));  // window x 6..9, y 2..5: full, no (5,5)
  EXPECT_FLOAT_EQ(filtered[image.index(8, 8)], 4.0f * (1.0f + s.base_offset + s.sparse_offset / 16.0f));
  const PointImage empty = plane_points(8, 8, 1.0f, 0, 8);
  filter_depth(empty, s, filtered);
  for (float d : filtered) EXPECT_TRUE(std::isinf(d));
}

// A wall of points at depth 3 in front of the camera: an edge behind it is culled, an edge on it
// is kept, and an edge behind it where the wall has a hole keeps the piece seen through the hole.
TEST(EdgeProjection, OcclusionCullingAgainstThePointDepth) {
  View v;
  v.camera.eye = {0, 0, 10}, v.camera.target = {0, 0, 0}, v.camera.yfov_degrees = 40.0f;
  v.width = 64, v.height = 64;
  const ViewFrame frame(v);
  std::vector<float> filtered;
  filter_depth(plane_points(64, 64, 3.0f, 28, 36), DepthFilterSettings{}, filtered);
  std::vector<Segment> out;
  // Behind the wall (z = 0: depth 10), across the whole image: only the hole's piece survives.
  ASSERT_EQ(project_edge(frame, {-3, 0.1, 0}, {3, 0.1, 0}, filtered, out), EdgeFate::visible);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_GT(std::min(out[0].x0, out[0].x1), 25.0);
  EXPECT_LT(std::max(out[0].x0, out[0].x1), 39.0);
  out.clear();
  EXPECT_EQ(project_edge(frame, {-3, 0.1, 0}, {-1, 0.1, 0}, filtered, out), EdgeFate::culled);
  EXPECT_TRUE(out.empty());
  // On the wall (depth 3).
  EXPECT_EQ(project_edge(frame, {-0.8, 0.1, 7}, {-0.3, 0.1, 7}, filtered, out), EdgeFate::visible);
}

// The banded, vectorized filter against the definition, pixel by pixel, on random sparse point
// images whose sizes are not multiples of the band (16 rows) or of a vector, smaller than the
// window, with empty pixels of finite depth and drawn ones of NaN depth (counted, never the
// maximum, as std::max folded from -inf has it): bit for bit.
TEST(EdgeProjection, FilteredDepthEqualsTheWindowDefinitionOnRandomImages) {
  std::mt19937 rng(11);
  const DepthFilterSettings s;
  for (auto [w, h] : {std::pair{37, 53}, std::pair{64, 16}, std::pair{5, 3}, std::pair{130, 97}, std::pair{1, 1},
                      std::pair{1, 19}, std::pair{19, 1}, std::pair{2, 2}, std::pair{3, 33}}) {
    PointImage image = plane_points(w, h, 1.0f);
    std::uniform_real_distribution<float> depth(0.5f, 20.0f), u(0.0f, 1.0f);
    for (size_t i = 0; i < image.depth.size(); ++i) {
      image.depth[i] = depth(rng);
      if (u(rng) < 0.6f) image.point[i] = -1;
      else if (u(rng) < 0.05f) image.depth[i] = std::numeric_limits<float>::quiet_NaN();
    }
    std::vector<float> filtered;
    filter_depth(image, s, filtered);
    ASSERT_EQ(filtered.size(), size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float m = -std::numeric_limits<float>::infinity();
        int n = 0;
        for (int qy = std::max(0, y - 1); qy <= std::min(h - 1, y + 2); ++qy)
          for (int qx = std::max(0, x - 1); qx <= std::min(w - 1, x + 2); ++qx)
            if (image.point[image.index(qx, qy)] >= 0) m = std::max(m, image.depth[image.index(qx, qy)]), ++n;
        const float want = n == 0 ? std::numeric_limits<float>::infinity()
                                  : m * (1.0f + s.base_offset + s.sparse_offset * (float(16 - n) / 16.0f));
        const float got = filtered[image.index(x, y)];
        ASSERT_TRUE(got == want || (std::isnan(got) && std::isnan(want))) << x << "," << y << " of " << w << "x" << h;
      }
  }
}

// The filtered depth of a w x h point image with random depths in [2, max_depth] and 30 % of
// its pixels empty.
std::vector<float> random_filtered_depth(int w, int h, float max_depth, std::mt19937& rng) {
  PointImage image = plane_points(w, h, 1.0f);
  std::uniform_real_distribution<float> depth(2.0f, max_depth), u(0.0f, 1.0f);
  for (size_t i = 0; i < image.depth.size(); ++i) {
    image.depth[i] = depth(rng);
    if (u(rng) < 0.3f) image.point[i] = -1;
  }
  std::vector<float> filtered;
  filter_depth(image, DepthFilterSettings{}, filtered);
  return filtered;
}

// The pieces' 1/depth at their ends against the 3D segment itself: the point of a-b nearest the
// eye ray through each end (random segments, many crossing the near plane, the image border, and
// culled into several pieces by a random depth image).
TEST(EdgeProjection, PieceEndsCarryTheDepthOfTheEdgeThere) {
  const ViewFrame frame = test_frame(96, 80);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-6.0, 6.0);
  const std::vector<float> filtered = random_filtered_depth(96, 80, 9.0f, rng);
  const glm::dvec3 eye(frame.eye()), fwd(frame.forward());
  size_t ends = 0;
  for (const bool cull : {false, true})
    for (int trial = 0; trial < 300; ++trial) {
      const glm::dvec3 a(coord(rng), coord(rng), coord(rng)), b(coord(rng), coord(rng), coord(rng));
      std::vector<Segment> out;
      std::vector<glm::dvec2> inv;
      project_edge(frame, a, b, cull ? std::span<const float>(filtered) : std::span<const float>(), out, &inv);
      ASSERT_EQ(inv.size(), out.size());
      for (size_t k = 0; k < out.size(); ++k)
        for (const auto& [x, y, got] : {std::tuple{out[k].x0, out[k].y0, inv[k].x}, std::tuple{out[k].x1, out[k].y1, inv[k].y}}) {
          // The point of line a-b closest to the eye ray through (x, y).
          const Ray ray = frame.ray(float(x), float(y));
          const glm::dvec3 o(ray.origin), d(glm::normalize(glm::dvec3(ray.direction))), e = b - a;
          const glm::dvec3 w0 = a - o;
          const double ee = glm::dot(e, e), ed = glm::dot(e, d), ew = glm::dot(e, w0), dw = glm::dot(d, w0);
          const double den = ee - ed * ed;
          if (den < 1e-9 * ee) continue;  // the edge seen end-on
          const double lambda = (ed * dw - ew) / den;
          const double want = 1.0 / glm::dot(a + lambda * e - eye, fwd);
          ASSERT_NEAR(got, want, 2e-4 * want) << "trial " << trial << ", piece " << k;
          ++ends;
        }
    }
  EXPECT_GT(ends, 500u);
}

// project_edges (parallel chunks) against project_edge edge by edge: the same pieces in the same
// order, the same owners and fates, bit for bit, with culling on a random depth image, whatever
// the thread count (run under 1 and 4 threads).
TEST(EdgeProjection, ParallelProjectionEqualsTheSerialOneBitForBit) {
  const ViewFrame frame = test_frame(96, 80);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-5.0, 5.0);
  std::vector<edges::SceneEdge> edges(1000);
  for (edges::SceneEdge& e : edges) e.a = {coord(rng), coord(rng), coord(rng)}, e.b = {coord(rng), coord(rng), coord(rng)};
  const std::vector<float> filtered = random_filtered_depth(96, 80, 6.0f, rng);
  for (const bool cull : {false, true}) {
    const std::span<const float> depths = cull ? std::span<const float>(filtered) : std::span<const float>();
    std::vector<Segment> want;
    std::vector<uint32_t> want_owner;
    std::vector<glm::dvec2> want_inv;
    std::vector<EdgeFate> want_fate;
    for (size_t k = 0; k < edges.size(); ++k) {
      want_fate.push_back(project_edge(frame, edges[k].a, edges[k].b, depths, want, &want_inv));
      want_owner.resize(want.size(), uint32_t(k));
    }
    int culled = 0, split = 0;
    for (EdgeFate f : want_fate) culled += f == EdgeFate::culled;
    for (size_t k = 1; k < want_owner.size(); ++k) split += want_owner[k] == want_owner[k - 1];
    if (cull) {  // the depth image culls some edges and splits others: the test covers both
      EXPECT_GT(culled, 20);
      EXPECT_GT(split, 20);
    }
    for (const int threads : {1, 4}) {
      tbb::task_arena arena(threads);
      std::vector<Segment> got = {{1, 2, 3, 4}};  // appended to
      std::vector<uint32_t> owner = {7};
      std::vector<glm::dvec2> inv = {{0.5, 0.25}};
      std::vector<EdgeFate> fate;
      EdgeProjectionScratch scratch;
      arena.execute([&] { project_edges(frame, edges, depths, got, owner, inv, fate, scratch); });
      ASSERT_EQ(got.size(), want.size() + 1);
      ASSERT_EQ(owner.size(), want_owner.size() + 1);
      ASSERT_EQ(inv.size(), want_inv.size() + 1);
      ASSERT_EQ(want_inv.size(), want.size());
      for (size_t k = 0; k < want.size(); ++k) {
        const Segment& a = got[k + 1], &b = want[k];
        ASSERT_TRUE(a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1) << k;
        ASSERT_EQ(owner[k + 1], want_owner[k]);
        ASSERT_TRUE(inv[k + 1] == want_inv[k]) << k;
      }
      EXPECT_EQ(fate, want_fate);
    }
  }
}

// mark_edge_pixels (pieces in parallel, atomic OR) against the pieces marked one after another,
// with pieces of every kind crossing each other and the image border.
TEST(EdgeProjection, EdgePixelsEqualThePiecesMarkedInTurn) {
  const int w = 120, h = 90;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> coord(-10.0, 130.0);
  std::vector<Segment> segments(3000);
  std::vector<edges::EdgeKind> kinds(segments.size());
  const edges::EdgeKind all[] = {edges::EdgeKind::silhouette, edges::EdgeKind::sharp, edges::EdgeKind::border,
                                 edges::EdgeKind::shadow};
  for (size_t k = 0; k < segments.size(); ++k) {
    const double x = coord(rng), y = coord(rng);
    segments[k] = {x, y, x + (coord(rng) - 60.0) * 0.2, y + (coord(rng) - 60.0) * 0.2};
    kinds[k] = all[rng() % 4];
  }
  std::vector<uint8_t> want(size_t(w * h), 0);
  for (size_t k = 0; k < segments.size(); ++k) {
    const uint8_t bit = kinds[k] == edges::EdgeKind::silhouette || kinds[k] == edges::EdgeKind::border ? kDepthEdge
                        : kinds[k] == edges::EdgeKind::sharp                                           ? kSharpEdge
                                                                                                       : kShadowEdge;
    const Segment& s = segments[k];
    const int steps = 1 + int(8.0 * std::hypot(s.x1 - s.x0, s.y1 - s.y0));
    for (int j = 0; j <= steps; ++j) {
      const double t = double(j) / steps, x = s.x0 + t * (s.x1 - s.x0), y = s.y0 + t * (s.y1 - s.y0);
      if (x >= 0.0 && y >= 0.0 && x < w && y < h) want[size_t(y) * size_t(w) + size_t(x)] |= bit;
    }
  }
  std::vector<uint8_t> got(7, 0xff);  // resized and cleared
  mark_edge_pixels(segments, kinds, w, h, got);
  EXPECT_EQ(got, want);
  int mixed = 0;
  for (uint8_t m : want) mixed += m != 0 && (m & (m - 1)) != 0;
  EXPECT_GT(mixed, 50);  // pixels of two kinds: the OR is exercised
}

}  // namespace
}  // namespace epi::render

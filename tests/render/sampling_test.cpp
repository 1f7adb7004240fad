// Prioritized sampling: the dither's count, spread and proportionality; jittered requests;
// camera extrapolation; predictive occupancy against a moving camera over a sampled plane.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "render/sampling.h"
#include "render/sparse_blend.h"

namespace epi::render {
namespace {

TEST(Dither, ExactCountOfDistinctPixelsForManyBudgetsAndRandomImages) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int trial = 0; trial < 40; ++trial) {
    const int w = 1 + int(rng() % 70), h = 1 + int(rng() % 50);
    std::vector<float> priority(size_t(w * h));
    const int shape = trial % 4;  // random, sparse spikes, all zero, huge range
    for (float& p : priority) {
      const float u = unit(rng);
      p = shape == 0 ? u : shape == 1 ? (u < 0.05f ? 16.0f : 0.0f) : shape == 2 ? 0.0f : std::pow(10.0f, 6.0f * u - 3.0f);
    }
    for (size_t count : {size_t(0), size_t(1), size_t(w * h / 50), size_t(w * h / 3), size_t(w * h), size_t(w * h + 7)}) {
      const std::vector<uint32_t> picked = dither_pixels(priority, w, h, count);
      ASSERT_EQ(picked.size(), std::min(count, size_t(w * h)));
      EXPECT_TRUE(std::is_sorted(picked.begin(), picked.end()));
      EXPECT_EQ(std::set<uint32_t>(picked.begin(), picked.end()).size(), picked.size());
      for (uint32_t p : picked) EXPECT_LT(p, uint32_t(w * h));
      const size_t positive = size_t(std::count_if(priority.begin(), priority.end(), [](float p) { return p > 0.0f; }));
      if (shape != 2 && count <= positive) {  // zero priority only once every positive pixel is taken
        for (uint32_t p : picked) EXPECT_GT(priority[p], 0.0f);
      }
      EXPECT_EQ(picked, dither_pixels(priority, w, h, count));  // deterministic
    }
  }
}

TEST(Dither, UniformPriorityIsSpreadEvenly) {
  const int w = 128, h = 128;
  const std::vector<float> priority(size_t(w * h), 1.0f);
  const std::vector<uint32_t> picked = dither_pixels(priority, w, h, size_t(w * h / 16));
  std::vector<int> blocks(16 * 16, 0);  // 8x8 blocks: 4 picks each expected
  for (uint32_t p : picked) ++blocks[size_t((p / w / 8) * 16 + (p % w) / 8)];
  int near_four = 0;  // error diffusion starts up in the first rows, so allow a few outliers
  for (int b : blocks) {
    EXPECT_GE(b, 1);
    EXPECT_LE(b, 7);
    near_four += b >= 3 && b <= 5;
  }
  EXPECT_GE(near_four, 240);
}

// A smooth random priority image: a few random bumps over a floor, range ~0.2 to ~3.
std::vector<float> smooth_priority(int w, int h, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> p(size_t(w) * size_t(h), 0.2f);
  for (int k = 0; k < 6; ++k) {
    const float cx = unit(rng) * float(w), cy = unit(rng) * float(h), r = (0.1f + 0.3f * unit(rng)) * float(w), a = 0.5f + unit(rng);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float d2 = ((float(x) - cx) * (float(x) - cx) + (float(y) - cy) * (float(y) - cy)) / (r * r);
        p[size_t(y) * size_t(w) + size_t(x)] += a * std::exp(-d2);
      }
  }
  return p;
}

// Sparse to dense budgets, uniform and smooth priority, 512x512 (8 bands of 64 rows): the count is
// exact, every strip of 8 rows (the top of every band among them) gets at least half the picks
// its priority asks for, and the picks follow priority (pixels above the median priority get
// their share).
TEST(Dither, EveryStripOfRowsGetsItsShareAtEveryDensity) {
  const int w = 512, h = 512;
  for (int image = 0; image < 2; ++image) {
    const std::vector<float> priority = image == 0 ? std::vector<float>(size_t(w * h), 1.0f) : smooth_priority(w, h, 11);
    double total = 0.0;
    for (float p : priority) total += p;
    std::vector<float> sorted = priority;
    std::nth_element(sorted.begin(), sorted.begin() + ptrdiff_t(sorted.size() / 2), sorted.end());
    const float median = sorted[sorted.size() / 2];
    for (double density : {0.001, 0.003, 0.005, 0.01, 0.05, 0.5}) {
      const size_t count = size_t(std::round(density * w * h));
      const std::vector<uint32_t> picked = dither_pixels(priority, w, h, count);
      ASSERT_EQ(picked.size(), count);
      std::vector<double> got(h / 8, 0.0), want(h / 8, 0.0);
      for (uint32_t p : picked) got[p / w / 8] += 1.0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) want[size_t(y / 8)] += double(priority[size_t(y * w + x)]) * double(count) / total;
      for (int s = 0; s < h / 8; ++s)
        EXPECT_GE(got[size_t(s)], 0.5 * want[size_t(s)]) << "image " << image << " density " << density << " rows " << s * 8;
      if (image == 1) {
        double high_want = 0.0, high_got = 0.0;
        for (size_t i = 0; i < priority.size(); ++i)
          if (priority[i] > median) high_want += double(priority[i]) * double(count) / total;
        for (uint32_t p : picked) high_got += priority[p] > median;
        EXPECT_NEAR(high_got / high_want, 1.0, 0.05) << "density " << density;
      }
    }
  }
}

// The bands are dithered in parallel: the picks are the same under 1, 2, 3 and 8 threads (a
// band's picks depend on its rows and its share only), at sparse and dense budgets, and on
// priority images of many shapes (the largest remainders and the zero-priority rule included).
TEST(Dither, TheSamePicksWhateverTheThreadCount) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const auto& size : {std::pair{512, 512}, std::pair{333, 270}, std::pair{64, 700}}) {
    const int w = size.first, h = size.second;  // (clang 14 cannot capture structured bindings)
    std::vector<float> priority = smooth_priority(w, h, uint32_t(w));
    for (size_t i = 0; i < priority.size(); i += 1 + rng() % 5) priority[i] = unit(rng) < 0.5f ? 0.0f : 16.0f;
    for (double density : {0.002, 0.02, 0.3}) {
      const size_t count = size_t(std::round(density * w * h));
      std::vector<uint32_t> reference;
      for (const int threads : {1, 2, 3, 8}) {
        tbb::task_arena arena(threads);
        std::vector<uint32_t> picked;
        arena.execute([&] { picked = dither_pixels(priority, w, h, count); });
        if (threads == 1) reference = picked;
        else ASSERT_EQ(picked, reference) << w << "x" << h << " density " << density << " threads " << threads;
      }
      ASSERT_EQ(reference.size(), count);
    }
  }
}

// Error diffusion conserves the mass it is given: every 64x64 tile (at 2 % and 20 %, smooth
// priority) holds the picks its priority mass asks for. The path crosses a tile in 8 pieces (one
// per 8-row strip), each within one pick of its mass (the carried error stays in [-0.5, 0.5]),
// so at most 8 picks off, plus the settling of the band's count.
TEST(Dither, EveryTileGetsItsPriorityMass) {
  const int w = 640, h = 448, tile = 64;
  const std::vector<float> priority = smooth_priority(w, h, 23);
  double total = 0.0;
  for (float p : priority) total += p;
  for (double density : {0.02, 0.2}) {
    const size_t count = size_t(std::round(density * w * h));
    const std::vector<uint32_t> picked = dither_pixels(priority, w, h, count);
    const int tw = w / tile, th = h / tile;
    std::vector<double> got(size_t(tw * th), 0.0), want(size_t(tw * th), 0.0);
    for (uint32_t p : picked) got[size_t(int(p) / w / tile * tw + int(p) % w / tile)] += 1.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) want[size_t(y / tile * tw + x / tile)] += double(priority[size_t(y * w + x)]) * double(count) / total;
    for (size_t t = 0; t < got.size(); ++t)
      EXPECT_NEAR(got[t], want[t], 8.0 + 0.01 * want[t]) << "tile " << t << " density " << density;
  }
}

TEST(Dither, PicksInProportionToPriority) {
  const int w = 96, h = 64;
  std::vector<float> priority(size_t(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) priority[size_t(y * w + x)] = x < w / 2 ? 1.0f : 3.0f;
  const std::vector<uint32_t> picked = dither_pixels(priority, w, h, 1500);  // 1/4 density (sparser ones drift more at the edges)
  size_t left = 0, right = 0;
  for (uint32_t p : picked) (p % w < uint32_t(w / 2) ? left : right)++;
  EXPECT_NEAR(double(right) / double(left), 3.0, 0.25);
}

// Every prefix of the submission order holds each shot in proportion (to within a round), and
// the shuffle is a permutation that spreads the first requests over the whole image.
TEST(Submission, EveryPrefixHoldsEveryShotInProportionAndIsSpread) {
  for (const std::vector<size_t>& sizes : {std::vector<size_t>{5000, 1200}, {7, 3000}, {0, 10}, {1000}, {300, 0, 77}}) {
    const std::vector<SubmissionPart> parts = interleave_shots(sizes, 256);
    std::vector<size_t> next(sizes.size(), 0);
    size_t total = 0, done = 0;
    for (size_t n : sizes) total += n;
    for (const SubmissionPart& p : parts) {
      ASSERT_EQ(p.begin, next[p.shot]);  // each shot in order, no gap, no overlap
      ASSERT_GT(p.end, p.begin);
      next[p.shot] = p.end, done += p.end - p.begin;
      for (size_t s = 0; s < sizes.size(); ++s)  // in proportion, to within one round's share
        EXPECT_LE(std::abs(double(next[s]) - double(sizes[s]) * double(done) / double(total)), double(sizes[s]) * 256.0 / double(total) + 1.0);
    }
    for (size_t s = 0; s < sizes.size(); ++s) EXPECT_EQ(next[s], sizes[s]);
  }
  const int w = 200, h = 100;
  std::vector<uint32_t> all(size_t(w * h));
  std::iota(all.begin(), all.end(), 0u);
  std::vector<ShadeRequest> requests;
  make_requests(all, w, 5, 2, 0, requests);
  std::vector<ShadeRequest> shuffled = requests;
  shuffle_requests(shuffled, 5, 2);
  std::set<uint32_t> ids;
  for (const ShadeRequest& r : shuffled) ids.insert(r.id);
  EXPECT_EQ(ids.size(), requests.size());
  std::vector<size_t> quarters(4, 0);  // the first 2% of the order, by quarter of the rows
  for (size_t k = 0; k < requests.size() / 50; ++k) ++quarters[size_t(shuffled[k].y) / 25];
  for (size_t q : quarters) EXPECT_GE(q, requests.size() / 50 / 4 / 2);
  std::vector<ShadeRequest> again = requests;
  shuffle_requests(again, 5, 2);
  for (size_t k = 0; k < again.size(); ++k) EXPECT_EQ(again[k].id, shuffled[k].id);
}

TEST(Requests, JitteredInsideTheirPixelAndReproducible) {
  const std::vector<uint32_t> pixels = {0, 5, 17, 99};
  std::vector<ShadeRequest> a, b, c;
  make_requests(pixels, 10, 42, 3, 100, a);
  make_requests(pixels, 10, 42, 3, 100, b);
  make_requests(pixels, 10, 42, 4, 100, c);
  ASSERT_EQ(a.size(), 4u);
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].id, 100 + k);
    EXPECT_EQ(int(a[k].x), int(pixels[k] % 10));
    EXPECT_EQ(int(a[k].y), int(pixels[k] / 10));
    EXPECT_EQ(a[k].x, b[k].x);
    EXPECT_EQ(a[k].y, b[k].y);
    EXPECT_NE(a[k].x, c[k].x);  // another frame, another jitter
  }
}

// Effort where samples are sparse: each request's effort against a brute-force count of the samples
// in the blocks within one block of its own, on random images (sizes not multiples of the block, one
// row, one column, one pixel) with regions of different density, requests at the image's corners
// and edges, and the extremes: no sample anywhere (the most effort), every pixel a sample (1), a
// non-finite request (left at 1) and most <= 1 (all 1).
TEST(SparseEffort, EachRequestTakesTheSquareRootOfItsNeighbourhoodsSparseness) {
  std::mt19937 rng(11);
  const float rgb[3] = {0.5f, 0.5f, 0.5f};
  const int sizes[][2] = {{1, 1}, {1, 37}, {53, 1}, {64, 64}, {61, 45}, {200, 130}};
  for (const auto& [w, h] : sizes)
    for (int pattern = 0; pattern < 4; ++pattern) {
      EpiImage epi(w, h);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          // 0: empty; 1: full; 2, 3: a sparse left part and a dense right part, at random
          const double density = pattern == 0 ? 0.0 : pattern == 1 ? 1.0 : x < w / 2 ? 0.02 * pattern : 0.6;
          if (unit(rng) < density) epi.set_sample(x, y, 0.5, 0.5, rgb);
        }
      std::vector<ShadeRequest> requests;
      for (int k = 0; k < 300; ++k) requests.push_back({uint32_t(k), float(unit(rng) * w), float(unit(rng) * h)});
      requests.push_back({300, 0.0f, 0.0f});
      requests.push_back({301, std::nextafter(float(w), 0.0f), std::nextafter(float(h), 0.0f)});
      requests.push_back({302, std::numeric_limits<float>::quiet_NaN(), 1.0f});
      for (const int most : {1, 4, 9}) {
        std::vector<uint32_t> counts;
        set_sparse_effort(requests, epi, 0.3f, most, counts);
        for (const ShadeRequest& r : requests) {
          int expected = 1;
          if (most > 1 && std::isfinite(r.x)) {
            const int bx = int(r.x) / kSparseBlendBlock, by = int(r.y) / kSparseBlendBlock;
            int samples = 0, pixels = 0;
            for (int y = 0; y < h; ++y)
              for (int x = 0; x < w; ++x)
                if (std::abs(x / kSparseBlendBlock - bx) <= 1 && std::abs(y / kSparseBlendBlock - by) <= 1)
                  ++pixels, samples += has_sample(epi.edge[epi.index(x, y)]);
            expected = samples == 0 ? most
                                    : std::clamp(int(std::lround(std::sqrt(0.3 * pixels / samples))), 1, most);
          }
          ASSERT_EQ(int(r.effort), expected) << w << "x" << h << " pattern " << pattern << " most " << most << " at "
                                             << r.x << ", " << r.y;
        }
        if (pattern == 0 && most > 1) EXPECT_EQ(int(requests[0].effort), most);
        if (pattern == 1) EXPECT_EQ(int(requests[0].effort), 1);
      }
    }
}

TEST(Predict, CameraExtrapolatesLinearly) {
  Camera a, b;
  a.eye = {0, 0, 5}, a.target = {0, 0, 0};
  b.eye = {1, 0, 5}, b.target = {0.5f, 0, 0};
  const Camera c = extrapolate_camera(a, b, 4.0f);
  EXPECT_FLOAT_EQ(c.eye.x, 5.0f);
  EXPECT_FLOAT_EQ(c.target.x, 2.5f);
  const Camera still = extrapolate_camera(b, b, 4.0f);
  EXPECT_EQ(still.eye, b.eye);
  // An eye that would leave the ray tracer's range (or overflow) is not extrapolated: ViewFrame
  // would refuse it, and the frame loop extrapolates every moving frame.
  Camera far_a = a, far_b = b;
  far_a.eye = {6e17f, 0, 5}, far_b.eye = {8e17f, 0, 5};
  far_a.target = far_a.eye - glm::vec3(0, 0, 1), far_b.target = far_b.eye - glm::vec3(0, 0, 1);
  const Camera clamped = extrapolate_camera(far_a, far_b, 2.0f);
  EXPECT_EQ(clamped.eye, far_b.eye);
  EXPECT_EQ(clamped.target, far_b.target);
  EXPECT_NO_THROW(ViewFrame(View{clamped, 8, 8}));
}

// A plane sampled at every pixel from the current camera; the camera slides right. The predicted
// view's gaps are exactly the strip at its right edge that the current view never saw.
TEST(Predict, OccupancyFindsTheGapsAboutToOpen) {
  const int w = 64, h = 48;
  auto view_at = [&](float x) {
    View v;
    v.camera.eye = {x, 0, 10}, v.camera.target = {x, 0, 0}, v.camera.yfov_degrees = 40.0f;
    v.width = w, v.height = h;
    return v;
  };
  const ViewFrame now(view_at(0.0f));
  PointCache cache(w, h);
  ShadeBatch batch;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Ray ray = now.ray(x + 0.5f, y + 0.5f);
      ShadeResult r;
      r.x = x + 0.5f, r.y = y + 0.5f, r.hit = true, r.object = 0;
      r.position = ray.origin + (-ray.origin.z / ray.direction.z) * ray.direction;
      batch.results.push_back(r);
    }
  const std::vector<glm::mat4> transforms(1, glm::mat4(1.0f));
  cache.insert(now, batch, transforms);
  const Camera predicted = extrapolate_camera(view_at(-0.25f).camera, now.view().camera, 4.0f);  // 1 unit right
  View pv = now.view();
  pv.camera = predicted;
  const ViewFrame ahead(pv);
  // One world unit at depth 10 with a 40 degree fov over 48 rows: pixels per unit.
  const float pixels_per_unit = float(h) / (2.0f * 10.0f * std::tan(glm::radians(20.0f)));
  const int shift = int(std::round(pixels_per_unit));
  // Half the points as 3x3 splats: a pixel of the seen part is a false gap only when none of
  // the ~9 points around it is in the half (~0.2%).
  for (int phase = 0; phase < 2; ++phase) {
    const std::vector<uint8_t> occupied = predicted_occupancy(cache, ahead, transforms, 2, phase, 3);
    int seen = 0, false_gaps = 0;
    for (int y = 1; y < h - 1; ++y)
      for (int x = 0; x < w; ++x) {
        const bool gap = !occupied[size_t(y * w + x)];
        if (x < w - shift - 1) ++seen, false_gaps += gap;
        if (x > w - shift + 1) {
          EXPECT_TRUE(gap) << x << "," << y;
        }
      }
    EXPECT_LT(false_gaps, seen / 100) << "phase " << phase;
  }
}

// The batched projection (project_batch) against the straightforward splat of every point, for
// random clouds on moving objects and random cameras; the two halves of stride 2 make up stride 1,
// and so do the three thirds of stride 3.
TEST(Predict, OccupancyEqualsTheStraightforwardSplat) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{37, 23}, std::pair{64, 48}, std::pair{5, 300}}) {
    View view;
    view.camera.eye = {0, 0, 6}, view.camera.target = {0, 0, 0}, view.width = w, view.height = h;
    const ViewFrame shot(view);
    PointCache cache(w, h);
    ShadeBatch batch;
    for (int k = 0; k < 3 * w * h + 600; ++k) {  // more results than slots: evictions too
      ShadeResult r;
      r.x = (u(rng) * 0.5f + 0.5f) * float(w), r.y = (u(rng) * 0.5f + 0.5f) * float(h);
      r.hit = k % 7 != 0, r.object = uint32_t(k % 3);
      r.position = {4.0f * u(rng), 4.0f * u(rng), 8.0f * u(rng)};
      r.normal = glm::normalize(glm::vec3(u(rng), u(rng), 1.0f));
      batch.results.push_back(r);
    }
    std::vector<glm::mat4> transforms(3, glm::mat4(1.0f));
    cache.insert(shot, batch, transforms);
    transforms[1] = glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, -0.2f, 0.1f));
    transforms[2] = glm::rotate(glm::mat4(1.0f), 0.2f, glm::vec3(0, 1, 0));
    View moved = view;
    moved.camera.eye = {0.4f, 0.1f, 5.5f};
    const ViewFrame ahead(moved);
    for (const int splat : {1, 3}) {
      std::vector<uint8_t> expected(size_t(w) * size_t(h), 0);
      for (const CachePoint& p : cache.points()) {
        if (!p.valid) continue;
        const Projection proj = ahead.project(cache.world_position(p, ahead, transforms));
        if (!(proj.depth > moved.camera.znear)) continue;
        const float fx = std::floor(proj.pixel.x - 0.5f * float(splat) + 0.5f), fy = std::floor(proj.pixel.y - 0.5f * float(splat) + 0.5f);
        if (!(fx > -float(splat) && fy > -float(splat) && fx < float(w) && fy < float(h))) continue;
        for (int y = std::max(0, int(fy)); y < std::min(h, int(fy) + splat); ++y)
          for (int x = std::max(0, int(fx)); x < std::min(w, int(fx) + splat); ++x) expected[size_t(y) * size_t(w) + size_t(x)] = 1;
      }
      EXPECT_EQ(predicted_occupancy(cache, ahead, transforms, 1, 0, splat), expected) << w << "x" << h << " splat " << splat;
      std::vector<uint8_t> both = predicted_occupancy(cache, ahead, transforms, 2, 0, splat);
      const std::vector<uint8_t> odd = predicted_occupancy(cache, ahead, transforms, 2, 1, splat);
      for (size_t i = 0; i < both.size(); ++i) both[i] |= odd[i];
      EXPECT_EQ(both, expected) << w << "x" << h << " splat " << splat;
      // A stride that is not a power of two (the division, not the mask): three thirds.
      std::vector<uint8_t> thirds(expected.size(), 0);
      for (int phase = 0; phase < 3; ++phase) {
        const std::vector<uint8_t> third = predicted_occupancy(cache, ahead, transforms, 3, phase, splat);
        for (size_t i = 0; i < thirds.size(); ++i) thirds[i] |= third[i];
      }
      EXPECT_EQ(thirds, expected) << w << "x" << h << " splat " << splat;
      EXPECT_GT(std::count(expected.begin(), expected.end(), 1), 0);
    }
  }
}

}  // namespace
}  // namespace epi::render

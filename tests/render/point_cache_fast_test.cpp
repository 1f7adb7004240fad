// Speed work changes no pixel (issue 11): the point cache's fast path against its reference path
// (PointCacheSettings::reference_path, the straightforward implementation kept as the oracle).
// Bit-identical point images, clouds, EPIs and frames, for the bundled scenes along their camera
// paths with a moving object, odd and degenerate sizes, and one or two threads; and the same for a
// bare cache fed random results with random edge masks (docs/performance.md, "Point processing").
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "load_scene.h"
#include "render/camera_path.h"
#include "render/point_cache_detail.h"
#include "render/renderer.h"

namespace epi::render {
namespace {

// Index of the first element whose bytes differ, -1 when none (sizes must match).
template <class T>
long first_difference(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return 0;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(T)) != 0) return long(i);
  return -1;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }
bool same_bits(const glm::vec3& a, const glm::vec3& b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z); }

bool same_point(const CachePoint& a, const CachePoint& b) {
  return same_bits(a.local, b.local) && a.srgb == b.srgb && a.object == b.object && a.normal == b.normal &&
         a.view == b.view && same_bits(a.lobe_width, b.lobe_width) && same_bits(a.priority_factor, b.priority_factor) &&
         same_bits(a.view_share, b.view_share) && a.staleness == b.staleness && a.image_id == b.image_id &&
         a.age == b.age && a.valid == b.valid;
}

bool same_colour(const PointColour& a, const PointColour& b) {
  return same_bits(a.color, b.color) && same_bits(a.view_dependent, b.view_dependent) &&
         same_bits(a.luminance_m2, b.luminance_m2) && a.count == b.count && a.epoch == b.epoch && a.weight == b.weight;
}

void expect_same_cache(const PointCache& fast, const PointCache& reference, const std::string& where) {
  const PointImage& f = fast.image();
  const PointImage& r = reference.image();
  EXPECT_EQ(first_difference(f.point, r.point), -1) << where << ": point image";
  EXPECT_EQ(first_difference(f.depth, r.depth), -1) << where << ": depth image";
  EXPECT_EQ(first_difference(f.region, r.region), -1) << where << ": region image";
  ASSERT_EQ(fast.points().size(), reference.points().size());
  ASSERT_EQ(fast.colours().size(), reference.colours().size());
  // The kept count (valid_points, read by the viewer every frame) against a count of the slots.
  for (const PointCache* cache : {&fast, &reference})
    EXPECT_EQ(cache->valid_points(), size_t(std::count_if(cache->points().begin(), cache->points().end(),
                                                          [](const CachePoint& p) { return p.valid; })))
        << where << (cache == &fast ? ": fast" : ": reference") << " path's valid count";
  for (size_t i = 0; i < fast.points().size(); ++i)
    if (!same_point(fast.points()[i], reference.points()[i]) || !same_colour(fast.colours()[i], reference.colours()[i])) {
      ADD_FAILURE() << where << ": cloud slot " << i << " differs";
      break;
    }
  EXPECT_EQ(first_difference(fast.highlights(), reference.highlights()), -1) << where << ": punctual highlights";
}

void expect_same_epi(const EpiImage& fast, const EpiImage& reference, const std::string& where) {
  EXPECT_EQ(first_difference(fast.edge, reference.edge), -1) << where << ": EPI edge words";
  EXPECT_EQ(first_difference(fast.color, reference.color), -1) << where << ": EPI colour words";
}

struct PathCase {
  std::string scene;
  int width, height;
  RenderMode mode;
  int frames;
};

std::string describe(const PathCase& c, int threads) {
  return c.scene + " " + std::to_string(c.width) + "x" + std::to_string(c.height) +
         (c.mode == RenderMode::epi ? " epi" : " rendercache") + " threads " + std::to_string(threads);
}

// Sync frames along the scene's path, its last object sliding sideways: the fast and the reference
// renderer must agree after every frame.
void run_path(const PathCase& c, int threads) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  const Scene scene = load_scene(std::string(EPI_SOURCE_DIR) + "/scenes/" + c.scene + ".gltf", LoadOptions{1});
  RayScene fast_rays(scene), reference_rays(scene);
  const Shader fast_shader(fast_rays, ShaderSettings{}), reference_shader(reference_rays, ShaderSettings{});
  FrameSettings s;
  s.width = c.width, s.height = c.height, s.mode = c.mode, s.sync = true, s.sample_budget = 0.05;
  FrameRenderer fast(scene, fast_rays, fast_shader, s);
  s.cache.reference_path = true;
  FrameRenderer reference(scene, reference_rays, reference_shader, s);
  const CameraPath path = scene_camera_path(scene, c.frames);
  std::vector<glm::mat4> transforms;
  for (const Object& o : scene.objects) transforms.push_back(o.object_to_world);
  for (int k = 0; k < c.frames; ++k) {
    if (!transforms.empty())
      transforms.back() = glm::translate(scene.objects.back().object_to_world, glm::vec3(0.01f * float(k % 10), 0.0f, 0.0f));
    const Camera camera = path.camera_at(k);
    const RgbImage& a = fast.render(camera, transforms);
    const RgbImage& b = reference.render(camera, transforms);
    const std::string where = describe(c, threads) + " frame " + std::to_string(k);
    EXPECT_EQ(first_difference(a.pixels, b.pixels), -1) << where << ": frame pixels";
    expect_same_epi(fast.epi(), reference.epi(), where);
    expect_same_cache(fast.cache(), reference.cache(), where);
    EXPECT_EQ(fast.stats().points.drawn, reference.stats().points.drawn) << where;
    EXPECT_EQ(fast.stats().points.culled, reference.stats().points.culled) << where;
    EXPECT_EQ(fast.stats().points.occluded, reference.stats().points.occluded) << where;
    EXPECT_EQ(fast.stats().points.expired, reference.stats().points.expired) << where;
    EXPECT_EQ(fast.stats().points.back_facing, reference.stats().points.back_facing) << where;
    if (::testing::Test::HasFailure()) return;
  }
  // chains' metals under its point and spot lights keep their punctual highlights apart (epi mode).
  if (c.scene == "chains" && c.mode == RenderMode::epi)
    EXPECT_GT(std::count_if(fast.cache().highlights().begin(), fast.cache().highlights().end(),
                            [](const PunctualHighlight& h) { return h.lights != 0; }),
              10)
        << describe(c, threads);
}

TEST(PointCacheFastPath, FramesAlongTheCameraPathsMatchTheReferenceBitForBit) {
  const PathCase cases[] = {
      {"cornell_box", 64, 48, RenderMode::epi, 24},  {"cornell_box", 37, 23, RenderMode::rendercache, 24},
      {"chains", 41, 29, RenderMode::epi, 16},       {"torus_capsule", 1, 40, RenderMode::epi, 16},
      {"torus_capsule", 40, 1, RenderMode::epi, 16}, {"rooms", 33, 31, RenderMode::epi, 12},
  };
  for (const PathCase& c : cases)
    for (int threads : {1, 2}) {
      run_path(c, threads);
      if (HasFailure()) return;
    }
}

// A bare cache: random hits and misses on random objects, random cameras, objects and edge masks,
// every entry point (project with and without the cull, depth_cull with edges,
// cull_behind_surfaces, fill_epi), all ages up to expiry.
TEST(PointCacheFastPath, RandomCloudsMatchTheReferenceBitForBit) {
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{1, 17}, std::pair{23, 1}, std::pair{31, 19}, std::pair{64, 64}}) {
    for (int threads : {1, 2}) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
      PointCacheSettings settings;
      settings.max_age = 12;  // points expire within the run
      PointCache fast(w, h, settings);
      settings.reference_path = true;
      PointCache reference(w, h, settings);
      std::mt19937 rng(uint32_t(w * 1000 + h * 10 + threads));
      std::uniform_real_distribution<float> u(0.0f, 1.0f);
      std::vector<glm::mat4> objects(3, glm::mat4(1.0f));
      EpiImage fast_epi(w, h), reference_epi(w, h);
      for (int frame = 0; frame < 40; ++frame) {
        const std::string where = std::to_string(w) + "x" + std::to_string(h) + " threads " + std::to_string(threads) +
                                  " frame " + std::to_string(frame);
        Camera camera;
        camera.eye = glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, 4.0f + u(rng));
        camera.target = glm::vec3(0.2f * (u(rng) - 0.5f), 0.2f * (u(rng) - 0.5f), 0.0f);
        camera.up = glm::vec3(0, 1, 0), camera.yfov_degrees = 40.0f;
        View view;
        view.camera = camera, view.width = w, view.height = h;
        const ViewFrame shot(view);
        objects[1] = glm::translate(glm::mat4(1.0f), glm::vec3(0.05f * float(frame % 7), 0.0f, 0.0f));
        objects[2] = glm::rotate(glm::mat4(1.0f), 0.1f * float(frame), glm::vec3(0, 1, 0));
        ShadeBatch batch;
        const int results = std::max(1, int(0.3f * float(w * h)));
        for (int k = 0; k < results; ++k) {
          ShadeResult r;
          r.x = u(rng) * float(w), r.y = u(rng) * float(h);
          const Ray ray = shot.ray(r.x, r.y);
          r.hit = u(rng) < 0.85f;
          if (r.hit) {
            r.object = uint32_t(rng() % 3);
            r.position = ray.origin + ray.direction * (2.0f + 4.0f * u(rng));
            r.normal = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, 1.0f));
            r.lobe_width = u(rng) < 0.5f ? 0.1f * u(rng) : 0.0f;
            r.diffuse_transmission = u(rng) < 0.7f ? u(rng) : 0.0f;  // rescaled with the view, or not
          }
          r.color = glm::vec3(u(rng), u(rng), u(rng));
          r.view_dependent = r.color * u(rng);
          batch.results.push_back(r);
        }
        const uint16_t epoch = uint16_t(frame / 5);
        EXPECT_EQ(fast.insert(shot, batch, objects, epoch), reference.insert(shot, batch, objects, epoch)) << where;
        std::vector<uint8_t> edges(size_t(w) * size_t(h));
        for (uint8_t& e : edges) e = u(rng) < 0.1f ? uint8_t(rng() % 8) : 0;
        std::vector<Segment> segments;
        std::vector<edges::EdgeKind> kinds;
        for (int k = 0; k < 1 + (w + h) / 8; ++k) {
          segments.push_back({u(rng) * w, u(rng) * h, u(rng) * w, u(rng) * h});
          kinds.push_back(edges::EdgeKind(rng() % edges::kEdgeKindCount));
        }
        EdgeCrossings crossings;
        crossings.build(segments, kinds, w, h);
        const bool cull_now = frame % 3 == 0;
        const ProjectionCounts a = fast.project(shot, objects, cull_now), b = reference.project(shot, objects, cull_now);
        EXPECT_EQ(a.projected, b.projected) << where;
        EXPECT_EQ(a.drawn, b.drawn) << where;
        EXPECT_EQ(a.culled, b.culled) << where;
        EXPECT_EQ(a.expired, b.expired) << where;
        EXPECT_EQ(a.back_facing, b.back_facing) << where;
        if (!cull_now) {
          EXPECT_EQ(fast.depth_cull(edges), reference.depth_cull(edges)) << where;
          EXPECT_EQ(fast.cull_behind_surfaces(shot, objects, crossings), reference.cull_behind_surfaces(shot, objects, crossings)) << where;
        }
        if (frame % 4 == 1) {  // results arriving between projection and fill (points change)
          const ShadeBatch late{{batch.results.begin(), batch.results.begin() + (results + 1) / 2}, {}, 0};
          EXPECT_EQ(fast.insert(shot, late, objects, epoch), reference.insert(shot, late, objects, epoch)) << where;
        }
        fast.set_refine_mask(edges), reference.set_refine_mask(edges);
        fast.fill_epi(fast_epi), reference.fill_epi(reference_epi);
        expect_same_cache(fast, reference, where);
        expect_same_epi(fast_epi, reference_epi, where);
        EXPECT_EQ(fast.valid_points(), reference.valid_points()) << where;
        if (HasFailure()) return;
      }
    }
  }
}

}  // namespace
}  // namespace epi::render

namespace epi::render {
namespace {

// Checked for every float of [0, 1] once (docs/performance.md; the codes now reach kEpiColourMax); here: every float within 300 ulps
// of each step, a million random ones, and the ends.
TEST(PointCacheFastPath, EpiColourByStepsEncodesLikeEncodeEpiColour8) {
  auto check = [](float v) {
    if (encode_epi_color8_by_steps(v) != encode_epi_color8(v)) ADD_FAILURE() << "at " << v << " (bits " << std::bit_cast<uint32_t>(v) << ")";
  };
  for (float v : {-1.0f, -0.0f, 0.0f, 1e-30f, 0.0031308f, 0.5f, 1.0f, 1.5f, 17.0f, kEpiColourMax, 1e30f,
                  std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()})
    check(v);
  for (int k = 1; k < 256; ++k) {
    uint32_t below = 0, at = std::bit_cast<uint32_t>(kEpiColourMax);  // the step, found independently
    while (at - below > 1) {
      const uint32_t mid = below + (at - below) / 2;
      (encode_epi_color8(std::bit_cast<float>(mid)) >= k ? at : below) = mid;
    }
    for (uint32_t bits = at - 300; bits != at + 300; ++bits) check(std::bit_cast<float>(bits));
    if (HasFailure()) return;
  }
  std::mt19937 rng(7);
  std::uniform_int_distribution<uint32_t> any(0, std::bit_cast<uint32_t>(kEpiColourMax));
  for (int k = 0; k < 1000000 && !HasFailure(); ++k) check(std::bit_cast<float>(any(rng)));
}

// The staleness without acos where a polynomial settles it: equal to the direct formula at every
// rounding boundary (cosines within 64 ulps of cos((k + 1/2) width / 16) and of the cap), at the
// ends, and for a million random cosines and widths.
TEST(PointCacheFastPath, StalenessStepsEqualsTheDirectFormula) {
  auto direct = [](float cosine, float width) {
    return uint8_t(std::lround(std::min(16.0f * std::acos(cosine) / width, 255.0f)));
  };
  size_t checked = 0;
  auto check = [&](float cosine, float width) {
    cosine = std::clamp(cosine, -1.0f, 1.0f);
    ++checked;
    if (detail::staleness_steps(cosine, width) != direct(cosine, width))
      ADD_FAILURE() << "cosine " << cosine << " (bits " << std::bit_cast<uint32_t>(cosine) << ") width " << width << ": "
                    << int(detail::staleness_steps(cosine, width)) << " != " << int(direct(cosine, width));
  };
  for (float width : {0.02f, 0.0217f, 0.05f, 0.1f, 0.3f, 0.77f, 1.0f, 3.0f, 10.0f}) {
    for (float c : {-1.0f, -0.99999994f, -0.5f, 0.0f, 0.5f, 0.99999994f, 1.0f}) check(c, width);
    for (int k = 0; k <= 256 && !HasFailure(); ++k) {
      const double angle = (k + 0.5) * double(width) / 16.0;
      if (angle > 3.14159265) break;
      const uint32_t bits = std::bit_cast<uint32_t>(float(std::cos(angle)));
      for (int d = -64; d <= 64; ++d) check(std::bit_cast<float>(uint32_t(int64_t(bits) + d)), width);
      check(-std::bit_cast<float>(bits), width);
    }
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> cosine(-1.0f, 1.0f), log_width(std::log(0.02f), std::log(4.0f));
  std::uniform_int_distribution<uint32_t> near_one(std::bit_cast<uint32_t>(0.99f), std::bit_cast<uint32_t>(1.0f));
  for (int k = 0; k < 500000 && !HasFailure(); ++k) {
    const float width = std::exp(log_width(rng));
    check(cosine(rng), width);
    check(std::bit_cast<float>(near_one(rng)), width);
  }
  EXPECT_GT(checked, size_t(1000000));
}

// The inline rounding of the EPI word's priority age equals std::lround: at every half-integer
// and its float neighbours up to 2^24 (where floats stop having halves), at the priority's cap,
// both signs, and for random floats over the whole range a priority can take.
TEST(PointCacheFastPath, RoundHalfAwayEqualsLround) {
  size_t checked = 0;
  auto check = [&](float x) {
    ++checked;
    if (round_half_away(x) != double(std::lround(x)))
      ADD_FAILURE() << x << " (bits " << std::bit_cast<uint32_t>(x) << "): " << round_half_away(x) << " != " << std::lround(x);
  };
  for (double half = 0.5; half < double(1 << 24) && !HasFailure(); half = half < 4096.0 ? half + 1.0 : half * 1.37 + 0.5) {
    const uint32_t bits = std::bit_cast<uint32_t>(float(half));
    for (int d = -3; d <= 3; ++d) {
      const float x = std::bit_cast<float>(uint32_t(int64_t(bits) + d));
      check(x), check(-x);
    }
  }
  for (float x : {0.0f, -0.0f, 0.49999997f, 0.5f, 1e4f, 9999.5f, 1e-30f, 3e9f, 16777215.0f, 16777216.0f}) check(x), check(-x);
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> value(0.0f, 1e4f);
  for (int k = 0; k < 1000000 && !HasFailure(); ++k) check(value(rng));
  EXPECT_GT(checked, size_t(1000000));
}

}  // namespace
}  // namespace epi::render

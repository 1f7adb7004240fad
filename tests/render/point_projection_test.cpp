// The point cache's projection kernels (core/render/point_projection.h) on every Highway target
// compiled and supported here, against the scalar code they replace: ViewFrame::project's depth
// and pixel bit for bit, the staleness, where the kernel settles it, equal to the scalar formula
// (detail::staleness_steps of the cosine PointCache::view_staleness computes), the back-face
// test equal to detail::faces_away, the diffuse transmission to brdf.h's of detail::facing_cosine
// bit for bit, the placement in the image's tiles equal to place()'s;
// the gathered inputs equal to gather_input's; the
// z-buffer's unpacking equal to unpack_winner's; and the faded colours equal to faded_colour_word's.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "render/point_cache_detail.h"
#include "render/point_projection.h"
#include "epi/epi_pixel.h"
#include "shade/brdf.h"

namespace epi::render {
namespace {

bool same_bits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b) || (std::isnan(a) && std::isnan(b)); }

TEST(PointProjection, EveryTargetGivesTheScalarBits) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> coordinate(-20.0f, 20.0f), log_width(std::log(0.02f), std::log(3.0f));
    size_t settled = 0, viewed = 0, facing[2] = {0, 0}, placed = 0, on_quarter = 0, past_one = 0;
    for (int round = 0; round < 40 && !HasFailure(); ++round) {
      View view;
      view.camera.eye = {coordinate(rng), coordinate(rng), coordinate(rng)};
      view.camera.target = view.camera.eye + glm::vec3(coordinate(rng), coordinate(rng), coordinate(rng) + 0.5f);
      view.camera.yfov_degrees = 20.0f + float(round);
      view.width = 37 + round * 13, view.height = 23 + round * 7;
      const ViewFrame frame(view);
      ProjectionBatch batch;
      const size_t n = ProjectionBatch::kSize - size_t(round % 7);  // a partial batch too
      for (size_t k = 0; k < ProjectionBatch::kSize; ++k) {
        glm::vec3 world{coordinate(rng), coordinate(rng), coordinate(rng)};
        if (k % 17 == 0) world = view.camera.eye;                               // zero distance to the eye
        if (k % 29 == 0) world = view.camera.eye + 1e-3f * (world - view.camera.eye);  // close to it
        if (k % 31 == 0) world *= 1e25f;                                         // overflow: inf, NaN
        batch.x[k] = world.x, batch.y[k] = world.y, batch.z[k] = world.z;
        batch.view[k] = uint32_t(rng());
        if (k % 5 == 0) batch.view[k] = 0x7fff7fffu + uint32_t(k % 3);  // near the octahedron's centre
        batch.lobe_width[k] = std::exp(log_width(rng));
        // The back-face test: random normals (0: none) and eyes, a fifth of them close to the
        // tangent plane (the sign of a small dot product), some not finite.
        batch.normal[k] = k % 11 == 0 ? 0u : uint32_t(rng());
        glm::vec3 eye{coordinate(rng), coordinate(rng), coordinate(rng)};
        if (k % 5 == 1) {
          const glm::vec3 n = detail::unpack_unit(batch.normal[k]);
          eye = eye - glm::dot(eye, n) * n + float(int(k % 3) - 1) * 1e-6f * n;
        }
        if (k % 7 == 2 && batch.normal[k] != 0) eye = detail::unpack_unit(batch.normal[k]) * std::abs(coordinate(rng));  // head-on: cosines past 1
        if (k % 37 == 0) eye *= 1e38f;
        batch.eye_x[k] = eye.x, batch.eye_y[k] = eye.y, batch.eye_z[k] = eye.z;
      }
      // place(): a third of the points in the view, some on pixel borders, quarter-pixel lines,
      // the image's last column and row and its borders just outside, some at the near plane.
      for (size_t k = 1; k < ProjectionBatch::kSize; k += 3) {
        std::uniform_real_distribution<float> along(0.0f, 1.0f);
        float x = along(rng) * float(view.width), y = along(rng) * float(view.height);
        if (k % 4 == 0) x = std::floor(x) + 0.25f * float(k % 5), y = std::floor(y);
        if (k % 13 == 0) x = std::nextafter(float(view.width), 0.0f);
        if (k % 19 == 0) y = float(view.height) * (k % 2 ? 1.0f : 0.0f);
        const Ray ray = frame.ray(x, y);
        const float t = k % 23 == 0 ? ray.tnear : ray.tnear + along(rng) * 30.0f;
        const glm::vec3 world = ray.origin + t * ray.direction;
        batch.x[k] = world.x, batch.y[k] = world.y, batch.z[k] = world.z;
      }
      // Half the points seen from where they were shaded, give or take a little.
      for (size_t k = 0; k < ProjectionBatch::kSize; k += 2) {
        const glm::vec3 to_eye = view.camera.eye - glm::vec3(batch.x[k], batch.y[k], batch.z[k]);
        const float l1 = std::abs(to_eye.x) + std::abs(to_eye.y) + std::abs(to_eye.z);
        if (!(l1 > 0.0f) || !std::isfinite(l1) || to_eye.z < 0.0f) continue;
        const auto q = [](float v) { return uint32_t(std::lround((std::clamp(v, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f)); };
        batch.view[k] = (q(to_eye.x / l1) + uint32_t(rng() % 9)) % 65536 | (q(to_eye.y / l1) + uint32_t(rng() % 9)) % 65536 << 16;
      }
      project_batch(frame, batch, n);
      for (size_t k = 0; k < n; ++k) {
        const glm::vec3 world(batch.x[k], batch.y[k], batch.z[k]);
        const Projection p = frame.project(world);
        if (!same_bits(p.depth, batch.depth[k]) || !same_bits(p.pixel.x, batch.pixel_x[k]) || !same_bits(p.pixel.y, batch.pixel_y[k]))
          ADD_FAILURE() << hwy::TargetName(target) << ": projection of entry " << k << " differs: " << p.depth << " "
                        << batch.depth[k] << ", " << p.pixel.x << " " << batch.pixel_x[k] << ", " << p.pixel.y << " " << batch.pixel_y[k];
        const bool away = detail::faces_away(batch.normal[k], glm::vec3(batch.eye_x[k], batch.eye_y[k], batch.eye_z[k]));
        if (batch.back_facing[k] != int(away)) ADD_FAILURE() << hwy::TargetName(target) << ": back-face test of entry " << k << " differs";
        const float facing_cos = detail::facing_cosine(batch.normal[k], glm::vec3(batch.eye_x[k], batch.eye_y[k], batch.eye_z[k]));
        facing[away] += 1;
        if (batch.normal[k] != 0 && !same_bits(diffuse_transmission(facing_cos), batch.transmission[k]))
          ADD_FAILURE() << hwy::TargetName(target) << ": transmission of entry " << k << " differs";
        const Placement at = place(p.depth, p.pixel.x, p.pixel.y, view.width, view.height, std::max(view.camera.znear, 0.0f));
        if (batch.pixel[k] != at.pixel || batch.tile[k] != at.tile || batch.spot[k] != at.spot)
          ADD_FAILURE() << hwy::TargetName(target) << ": placement of entry " << k << " differs: pixel " << at.pixel << " "
                        << batch.pixel[k] << ", tile " << at.tile << " " << batch.tile[k] << ", spot " << at.spot << " " << batch.spot[k];
        past_one += batch.normal[k] != 0 && facing_cos > 1.0f;
        placed += at.pixel >= 0;
        on_quarter += at.pixel >= 0 && (at.spot >> 16) % 4 != 0 && p.pixel.x == std::floor(p.pixel.x * 4.0f) / 4.0f;
        const glm::vec3 to_eye = frame.eye() - world;
        const float length = glm::length(to_eye);
        if (batch.staleness[k] < 0) continue;
        ++settled;
        ASSERT_TRUE(length > 0.0f) << hwy::TargetName(target) << " settled a point at the eye";
        const float cosine = std::clamp(glm::dot(to_eye / length, detail::unpack_unit(batch.view[k])), -1.0f, 1.0f);
        ASSERT_FALSE(std::isnan(cosine)) << hwy::TargetName(target) << " settled a NaN cosine";
        if (k % 2 == 0 && cosine > 0.99f) ++viewed;
        ASSERT_EQ(batch.staleness[k], int(detail::staleness_steps(cosine, batch.lobe_width[k])))
            << hwy::TargetName(target) << ", entry " << k << ": cosine " << cosine << ", width " << batch.lobe_width[k];
      }
    }
    EXPECT_GT(settled, size_t(8000)) << hwy::TargetName(target);  // of 40 x ~250: most are settled
    EXPECT_GT(viewed, size_t(500)) << hwy::TargetName(target);
    EXPECT_GT(std::min(facing[0], facing[1]), size_t(3000)) << hwy::TargetName(target);  // both verdicts
    EXPECT_GT(placed, size_t(2500)) << hwy::TargetName(target);  // of 40 x ~85 put in the view
    EXPECT_GT(on_quarter, size_t(50)) << hwy::TargetName(target);
    EXPECT_GT(past_one, size_t(20)) << hwy::TargetName(target);  // the transmission's clamp
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Random clouds and placements: batches whose points all have one object (the kernel's broadcast
// transform), mixed objects, the background (kNone, and objects past the last transform), no
// transforms at all, partial batches, first slots other than 0; gather_batch's inputs equal
// gather_input's bit for bit.
TEST(PointProjection, EveryTargetGathersTheInputsAsTheScalarCode) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coordinate(-50.0f, 50.0f), unit(0.0f, 1.0f);
    size_t uniform_batches = 0, background = 0, placed = 0;
    for (int round = 0; round < 60 && !HasFailure(); ++round) {
      const uint32_t objects = uint32_t(round % 5);  // 0: the background only
      std::vector<float> transforms(16 * objects), eyes(3 * objects);
      for (float& v : transforms) v = coordinate(rng) * (round % 7 == 3 ? 1e30f : 1.0f);
      for (float& v : eyes) v = coordinate(rng);
      const uint32_t first = round % 3 == 0 ? 0u : uint32_t(rng() % 4096);
      constexpr size_t kPoints = 600;
      std::vector<uint32_t> cloud((size_t(first) + kPoints) * CloudLayout::kWords);
      for (size_t slot = first; slot < first + kPoints; ++slot) {
        uint32_t* w = cloud.data() + slot * CloudLayout::kWords;
        for (size_t k = 0; k < 3; ++k) w[CloudLayout::kLocal + k] = std::bit_cast<uint32_t>(coordinate(rng));
        // One object per batch in odd rounds; else any object, the background (kNone) or one
        // past the transforms.
        const uint32_t pick = round % 2 == 1 ? uint32_t(round / 2) : uint32_t(rng());
        w[CloudLayout::kObject] = pick % 4 == 3 ? 0xffffffffu : objects > 0 && pick % 5 != 4 ? pick % objects : objects + pick % 3;
        w[CloudLayout::kNormal] = uint32_t(rng()), w[CloudLayout::kView] = uint32_t(rng());
        w[CloudLayout::kLobeWidth] = std::bit_cast<uint32_t>(unit(rng) * (rng() % 4 == 0 ? 0.01f : 2.0f));
      }
      const BatchPlacement at{transforms.empty() ? nullptr : transforms.data(), eyes.empty() ? nullptr : eyes.data(), objects,
                              glm::vec3(coordinate(rng), coordinate(rng), coordinate(rng)), 1e6f, 0.02f};
      std::vector<uint32_t> slots(ProjectionBatch::kSize);
      for (uint32_t& slot : slots) slot = first + uint32_t(rng() % kPoints);
      const size_t n = ProjectionBatch::kSize - size_t(rng() % 40);
      ProjectionBatch got, want;
      gather_batch(cloud.data(), first, slots.data(), n, at, got);
      for (size_t k = 0; k < n; ++k) gather_input(cloud.data(), slots[k], at, want, k);
      bool one_object = true;
      for (size_t k = 0; k < n; ++k) {
        const uint32_t object = cloud[size_t(slots[k]) * CloudLayout::kWords + CloudLayout::kObject];
        one_object &= object == cloud[size_t(slots[0]) * CloudLayout::kWords + CloudLayout::kObject];
        (object < objects ? placed : background) += 1;
        const float got_floats[] = {got.x[k], got.y[k], got.z[k], got.eye_x[k], got.eye_y[k], got.eye_z[k], got.lobe_width[k]};
        const float want_floats[] = {want.x[k], want.y[k], want.z[k], want.eye_x[k], want.eye_y[k], want.eye_z[k], want.lobe_width[k]};
        for (size_t c = 0; c < 7; ++c)
          if (!same_bits(got_floats[c], want_floats[c]))
            ADD_FAILURE() << hwy::TargetName(target) << ", round " << round << ", entry " << k << ", value " << c << ": "
                          << got_floats[c] << " instead of " << want_floats[c];
        if (got.normal[k] != want.normal[k] || got.view[k] != want.view[k])
          ADD_FAILURE() << hwy::TargetName(target) << ", round " << round << ", entry " << k << ": packed normal or view differs";
      }
      uniform_batches += one_object;
    }
    EXPECT_GE(uniform_batches, size_t(20)) << hwy::TargetName(target);
    EXPECT_GT(std::min(placed, background), size_t(3000)) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Random tiles (keys empty or not, any depth bits, region and index; winners anywhere in the
// records; the image's old regions random) of every width from 0 to 64 and odd row counts,
// written into a wider image: unpack_winners' planes equal unpack_winner's, pixel for pixel, and
// nothing outside the block is touched.
TEST(PointProjection, EveryTargetUnpacksTheWinnersAsTheScalarCode) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  constexpr size_t kPitch = 64, kImageWidth = 80, kRows = 7;
  struct Image {
    std::vector<int32_t> point, winners;
    std::vector<float> depth;
    std::vector<uint8_t> region;
    std::vector<uint32_t> word;
    std::vector<uint16_t> age_bin;
    explicit Image(std::mt19937& rng) {
      const size_t n = kImageWidth * (kRows + 2);
      for (size_t i = 0; i < n; ++i) {
        point.push_back(int32_t(rng())), winners.push_back(int32_t(rng())), depth.push_back(float(rng() % 1000));
        region.push_back(uint8_t(rng())), word.push_back(uint32_t(rng())), age_bin.push_back(uint16_t(rng()));
      }
    }
    WinnerPlanes planes(size_t at) {
      return {point.data() + at, winners.data() + at, depth.data() + at, region.data() + at, word.data() + at, age_bin.data() + at};
    }
    bool operator==(const Image& o) const {
      return point == o.point && winners == o.winners && region == o.region && word == o.word && age_bin == o.age_bin &&
             std::equal(depth.begin(), depth.end(), o.depth.begin(), [](float a, float b) { return same_bits(a, b); });
    }
  };
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937 rng(9);
    std::vector<ProjectedPoint> records(97);
    for (ProjectedPoint& r : records) r = {uint64_t(rng()) << 32 | rng(), uint32_t(rng()), uint16_t(rng()), uint16_t(rng())};
    size_t empty = 0, drawn = 0;
    for (size_t columns = 0; columns <= kPitch && !HasFailure(); ++columns) {
      std::vector<uint64_t> keys(kPitch * kRows);
      std::vector<uint32_t> winner(kPitch * kRows);
      for (size_t k = 0; k < keys.size(); ++k) {
        const bool none = rng() % 3 == 0;
        keys[k] = none ? detail::kEmptyKey : uint64_t(rng()) << 32 | rng();
        if (k % 13 == 0) keys[k] = uint64_t(0x7f800000u) << 32 | 0xffffffffu;  // low word all ones, not empty
        winner[k] = uint32_t(rng() % records.size());
        if (k % kPitch < columns) (none ? empty : drawn) += 1;
      }
      Image image(rng);
      Image expected = image;
      const size_t at = kImageWidth + 3;  // row 1, column 3
      for (size_t r = 0; r < kRows; ++r)
        for (size_t k = 0; k < columns; ++k)
          unpack_winner(keys[r * kPitch + k], records[winner[r * kPitch + k]], expected.planes(at + r * kImageWidth), k);
      unpack_winners(keys.data(), winner.data(), kPitch, records.data(), columns, kRows, image.planes(at), kImageWidth);
      EXPECT_TRUE(image == expected) << hwy::TargetName(target) << ", " << columns << " columns";
    }
    EXPECT_GT(std::min(empty, drawn), size_t(1000)) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Random colours and view-dependent parts (up to past kEpiColourMax, view-dependent parts larger
// than the colour, zeros, a few not finite), every staleness, both kinds of point, transmissions
// in [0, 1.2], colours on the encoding's steps and one float either side, fade windows including
// the smallest span, partial batches: fade_batch equals faded_colour_word bit for bit.
TEST(PointProjection, EveryTargetFadesColoursAsTheScalarCode) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  const ColourStepTables& steps = colour_step_tables();
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), log_colour(std::log(1e-4f), std::log(200.0f));
    size_t on_steps = 0, scaled = 0, codes[3] = {0, 0, 0};  // codes: 0, 1-254, 255
    for (int round = 0; round < 60 && !HasFailure(); ++round) {
      const float fade_start = round % 3 == 0 ? 2.0f : 4.0f * unit(rng), fade_span = round % 5 == 0 ? 1e-3f : 6.0f * unit(rng) + 1e-3f;
      FadeBatch batch;
      const size_t n = FadeBatch::kSize - size_t(round % 9) * 7;  // partial batches too
      for (size_t k = 0; k < FadeBatch::kSize; ++k) {
        float* colour[3] = {batch.r, batch.g, batch.b};
        float* view[3] = {batch.vr, batch.vg, batch.vb};
        for (int c = 0; c < 3; ++c) {
          colour[c][k] = k % 13 == 0 ? 0.0f : std::exp(log_colour(rng));
          view[c][k] = k % 3 == 0 ? 0.0f : colour[c][k] * 1.3f * unit(rng);  // some above the colour
          if (k % 7 == 0) {  // on a step of the encoding or a float either side, shown as it is
            const float step = steps.steps[1 + rng() % 255];
            colour[c][k] = (c == 0 ? step : c == 1 ? std::nextafter(step, 0.0f) : std::nextafter(step, 1e9f));
            view[c][k] = 0.0f;
          }
        }
        if (k % 61 == 0) batch.g[k] = std::numeric_limits<float>::quiet_NaN();
        if (k % 67 == 0) batch.b[k] = std::numeric_limits<float>::infinity();
        batch.staleness[k] = int32_t(k % 7 == 0 ? 0 : rng() % 256);
        batch.rescaled[k] = int32_t(k % 7 != 0 && rng() % 2);
        batch.transmission[k] = 1.2f * unit(rng);
      }
      fade_batch(fade_start, fade_span, batch, n);
      for (size_t k = 0; k < n; ++k) {
        const glm::vec3 colour(batch.r[k], batch.g[k], batch.b[k]), view(batch.vr[k], batch.vg[k], batch.vb[k]);
        const uint32_t expected = faded_colour_word(colour, view, batch.staleness[k], batch.rescaled[k] != 0,
                                                    batch.transmission[k], fade_start, fade_span);
        ASSERT_EQ(batch.word[k], expected) << hwy::TargetName(target) << ", round " << round << ", entry " << k;
        on_steps += k % 7 == 0;
        scaled += std::max({colour.r, colour.g, colour.b}) > kEpiColourMax;
        for (int c = 0; c < 3; ++c) {
          const uint32_t code = (expected >> (8 * c)) & 255;
          ++codes[code == 0 ? 0 : code == 255 ? 2 : 1];
        }
      }
    }
    EXPECT_GT(on_steps, size_t(1000)) << hwy::TargetName(target);
    EXPECT_GT(scaled, size_t(100)) << hwy::TargetName(target);  // the scale to kEpiColourMax
    EXPECT_GT(std::min({codes[0], codes[1], codes[2]}), size_t(100)) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace
}  // namespace epi::render

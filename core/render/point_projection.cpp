// project_batch, gather_batch, unpack_winners and fade_batch for every Highway target
// (foreach_target.h compiles this file once per target).
#include "render/point_projection.h"

#include <algorithm>
#include <cstddef>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/point_projection.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "epi/epi_pixel.h"

HWY_BEFORE_NAMESPACE();
namespace epi::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

struct Constants {
  float eye[3], forward[3], right[3], up[3], half_width, half_height, width, height, znear;
  int32_t image_width, image_height, tile_columns;
};

// a.x * b.x + a.y * b.y + a.z * b.z, added left to right (glm::dot).
template <class V>
HWY_INLINE V Dot(V ax, V ay, V az, V bx, V by, V bz) {
  return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
}

// detail::unpack_unit: an octahedral 16:16 unit vector, normalized.
template <class D, class VU>
HWY_INLINE void UnpackUnit(D d, VU packed, hn::Vec<D>& nx, hn::Vec<D>& ny, hn::Vec<D>& nz) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0f), minus_one = hn::Set(d, -1.0f);
  const auto steps_65535 = hn::Set(d, 65535.0f), two = hn::Set(d, 2.0f);
  const auto ex = hn::Sub(hn::Mul(hn::Div(hn::ConvertTo(d, hn::BitCast(di, hn::And(packed, hn::Set(du, 0xffffu)))), steps_65535), two), one);
  const auto ey = hn::Sub(hn::Mul(hn::Div(hn::ConvertTo(d, hn::BitCast(di, hn::ShiftRight<16>(packed))), steps_65535), two), one);
  const auto z = hn::Sub(hn::Sub(one, hn::Abs(ex)), hn::Abs(ey));
  const auto folded = hn::Lt(z, zero);
  const auto fx = hn::Mul(hn::Sub(one, hn::Abs(ey)), hn::IfThenElse(hn::Ge(ex, zero), one, minus_one));
  const auto fy = hn::Mul(hn::Sub(one, hn::Abs(ex)), hn::IfThenElse(hn::Ge(ey, zero), one, minus_one));
  const auto x = hn::IfThenElse(folded, fx, ex), y = hn::IfThenElse(folded, fy, ey);
  const auto inverse = hn::Div(one, hn::Sqrt(Dot(x, y, z, x, y, z)));
  nx = hn::Mul(x, inverse), ny = hn::Mul(y, inverse), nz = hn::Mul(z, inverse);
}

// place(), a vector of entries at a time from entry i.
template <class V>
HWY_INLINE void Place(const Constants& c, V depth, V pixel_x, V pixel_y, ProjectionBatch& b, size_t i) {
  const hn::DFromV<V> d;
  const hn::RebindToSigned<decltype(d)> di;
  const auto zero = hn::Zero(d);
  const auto inside = hn::And(hn::And(hn::Gt(depth, hn::Set(d, c.znear)), hn::And(hn::Ge(pixel_x, zero), hn::Ge(pixel_y, zero))),
                              hn::And(hn::Lt(pixel_x, hn::Set(d, c.width)), hn::Lt(pixel_y, hn::Set(d, c.height))));
  const auto in = hn::RebindMask(di, inside);
  // Lanes outside the view convert 0 instead of what they hold (NaN or out of int's range: a
  // conversion with undefined behaviour on the emulated target); their results are masked below.
  const auto x = hn::IfThenElseZero(inside, pixel_x), y = hn::IfThenElseZero(inside, pixel_y);
  const auto px = hn::Min(hn::ConvertTo(di, x), hn::Set(di, c.image_width - 1));
  const auto py = hn::Min(hn::ConvertTo(di, y), hn::Set(di, c.image_height - 1));
  const auto three = hn::Set(di, 3);
  const auto four = hn::Set(d, 4.0f);
  const auto rx = hn::Min(three, hn::ConvertTo(di, hn::Mul(hn::Sub(x, hn::ConvertTo(d, px)), four)));
  const auto ry = hn::Min(three, hn::ConvertTo(di, hn::Mul(hn::Sub(y, hn::ConvertTo(d, py)), four)));
  const auto pixel = hn::Add(hn::Mul(py, hn::Set(di, c.image_width)), px);
  const auto tile = hn::Add(hn::Mul(hn::ShiftRight<TileLayout::kHeightShift>(py), hn::Set(di, c.tile_columns)),
                            hn::ShiftRight<TileLayout::kWidthShift>(px));
  const auto within = hn::Add(hn::ShiftLeft<TileLayout::kWidthShift>(hn::And(py, hn::Set(di, TileLayout::kHeight - 1))),
                              hn::And(px, hn::Set(di, TileLayout::kWidth - 1)));
  const auto spot = hn::Or(within, hn::ShiftLeft<16>(hn::Add(rx, hn::ShiftLeft<2>(ry))));
  const hn::RebindToUnsigned<decltype(d)> du;
  hn::Store(hn::IfThenElse(in, pixel, hn::Set(di, -1)), di, b.pixel + i);
  hn::Store(hn::BitCast(du, hn::IfThenElseZero(in, tile)), du, b.tile + i);
  hn::Store(hn::BitCast(du, hn::IfThenElseZero(in, spot)), du, b.spot + i);
}

void ProjectBatch(const Constants& c, ProjectionBatch& b, size_t n) {
  const hn::ScalableTag<float> d;
  const hn::RebindToSigned<decltype(d)> di;
  const hn::RebindToUnsigned<decltype(d)> du;
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0f), minus_one = hn::Set(d, -1.0f), half = hn::Set(d, 0.5f);
  for (size_t i = 0; i < n; i += hn::Lanes(d)) {
    const auto wx = hn::Load(d, b.x + i), wy = hn::Load(d, b.y + i), wz = hn::Load(d, b.z + i);
    // ViewFrame::project.
    const auto rx = hn::Sub(wx, hn::Set(d, c.eye[0])), ry = hn::Sub(wy, hn::Set(d, c.eye[1])), rz = hn::Sub(wz, hn::Set(d, c.eye[2]));
    const auto depth = Dot(rx, ry, rz, hn::Set(d, c.forward[0]), hn::Set(d, c.forward[1]), hn::Set(d, c.forward[2]));
    const auto sx = hn::Div(Dot(rx, ry, rz, hn::Set(d, c.right[0]), hn::Set(d, c.right[1]), hn::Set(d, c.right[2])),
                            hn::Mul(depth, hn::Set(d, c.half_width)));
    const auto sy = hn::Div(Dot(rx, ry, rz, hn::Set(d, c.up[0]), hn::Set(d, c.up[1]), hn::Set(d, c.up[2])),
                            hn::Mul(depth, hn::Set(d, c.half_height)));
    const auto pixel_x = hn::Mul(hn::Mul(hn::Add(sx, one), half), hn::Set(d, c.width));
    const auto pixel_y = hn::Mul(hn::Mul(hn::Sub(one, sy), half), hn::Set(d, c.height));
    hn::Store(depth, d, b.depth + i);
    hn::Store(pixel_x, d, b.pixel_x + i);
    hn::Store(pixel_y, d, b.pixel_y + i);
    Place(c, depth, pixel_x, pixel_y, b, i);
    // PointCache::view_staleness: the cosine of the turn, as it computes it.
    const auto tx = hn::Sub(hn::Set(d, c.eye[0]), wx), ty = hn::Sub(hn::Set(d, c.eye[1]), wy), tz = hn::Sub(hn::Set(d, c.eye[2]), wz);
    const auto length = hn::Sqrt(Dot(tx, ty, tz, tx, ty, tz));
    hn::Vec<decltype(d)> vx, vy, vz;
    UnpackUnit(d, hn::Load(du, b.view + i), vx, vy, vz);
    const auto cosine_raw = Dot(hn::Div(tx, length), hn::Div(ty, length), hn::Div(tz, length), vx, vy, vz);
    const auto cosine = hn::Min(hn::Max(cosine_raw, minus_one), one);
    // detail::staleness_steps' estimate and its error bound.
    const auto width = hn::Load(d, b.lobe_width + i);
    const auto x = hn::Abs(cosine);
    auto poly = hn::Add(hn::Set(d, 0.0742610f), hn::Mul(x, hn::Set(d, -0.0187293f)));
    poly = hn::Add(hn::Set(d, -0.2121144f), hn::Mul(x, poly));
    poly = hn::Add(hn::Set(d, 1.5707288f), hn::Mul(x, poly));
    auto turned = hn::Mul(hn::Sqrt(hn::Sub(one, x)), poly);
    turned = hn::IfThenElse(hn::Lt(cosine, zero), hn::Sub(hn::Set(d, 3.14159265f), turned), turned);
    const auto steps = hn::Div(hn::Mul(hn::Set(d, 16.0f), turned), width);
    const auto error = hn::Add(hn::Add(hn::Div(hn::Set(d, 16.0f * 1e-4f), width), hn::Mul(hn::Set(d, 1e-5f), steps)), hn::Set(d, 1e-5f));
    const auto cap = hn::Set(d, 255.0f);
    const auto capped = hn::Ge(hn::Sub(steps, error), cap);
    const auto low = hn::Floor(hn::Add(hn::Sub(steps, error), half)), high = hn::Floor(hn::Add(hn::Add(steps, error), half));
    const auto decided = hn::And(hn::Eq(low, high), hn::Le(high, cap));
    // Settled only for a positive distance and a cosine that is a number (NaN fails both tests).
    const auto sound = hn::And(hn::Gt(length, zero), hn::Eq(cosine_raw, cosine_raw));
    auto result = hn::IfThenElse(hn::RebindMask(di, decided), hn::ConvertTo(di, hn::IfThenElse(decided, high, zero)), hn::Set(di, -1));
    result = hn::IfThenElse(hn::RebindMask(di, capped), hn::Set(di, 255), result);
    result = hn::IfThenElse(hn::RebindMask(di, sound), result, hn::Set(di, -1));
    hn::Store(result, di, b.staleness + i);
    // detail::faces_away.
    const auto normal = hn::Load(du, b.normal + i);
    hn::Vec<decltype(d)> nx, ny, nz;
    UnpackUnit(d, normal, nx, ny, nz);
    const auto ex = hn::Load(d, b.eye_x + i), ey = hn::Load(d, b.eye_y + i), ez = hn::Load(d, b.eye_z + i);
    const auto facing = Dot(nx, ny, nz, ex, ey, ez);
    const auto away = hn::AndNot(hn::RebindMask(d, hn::Eq(normal, hn::Zero(du))), hn::Lt(facing, zero));
    hn::Store(hn::IfThenElseZero(hn::RebindMask(di, away), hn::Set(di, 1)), di, b.back_facing + i);
    // detail::facing_cosine, then diffuse_transmission (brdf.h): 1 - schlick(0.04, cosine).x,
    // with std::clamp's choices.
    const auto cosine_facing = hn::Div(facing, hn::Sqrt(Dot(ex, ey, ez, ex, ey, ez)));
    const auto m_raw = hn::Sub(one, cosine_facing);
    const auto m = hn::IfThenElse(hn::Lt(m_raw, zero), zero, hn::IfThenElse(hn::Lt(one, m_raw), one, m_raw));
    const auto m5 = hn::Mul(hn::Mul(hn::Mul(m, m), hn::Mul(m, m)), m);
    const auto f0 = hn::Set(d, 0.04f);
    hn::Store(hn::Sub(one, hn::Add(f0, hn::Mul(hn::Sub(one, f0), m5))), d, b.transmission + i);
  }
}

// HWY_EXPORT needs a plain function pointer per target.
void ProjectBatchFrame(const ViewFrame& frame, ProjectionBatch& batch, size_t n) {
  Constants c;
  for (int k = 0; k < 3; ++k)
    c.eye[k] = frame.eye()[k], c.forward[k] = frame.forward()[k], c.right[k] = frame.right()[k], c.up[k] = frame.up()[k];
  c.half_width = frame.half_width(), c.half_height = frame.half_height();
  c.width = float(frame.view().width), c.height = float(frame.view().height);
  c.znear = std::max(frame.view().camera.znear, 0.0f);
  c.image_width = frame.view().width, c.image_height = frame.view().height;
  c.tile_columns = TileLayout::columns(frame.view().width);
  ProjectBatch(c, batch, n);
}

// gather_input, a vector of points at a time: the points' words gathered; the transform
// broadcast when every lane's point has the same object (most batches), else gathered per lane.
void GatherBatch(const uint32_t* cloud, uint32_t first, const uint32_t* slots, size_t n, const BatchPlacement& at,
                 ProjectionBatch& b) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  const hn::RebindToSigned<decltype(d)> di;
  cloud += size_t(first) * CloudLayout::kWords;  // the indices below: from the first slot (32 bits)
  const float* cloud_floats = reinterpret_cast<const float*>(cloud);
  const auto objects = hn::Set(du, at.objects);
  const auto depth = hn::Set(d, at.background_depth), min_width = hn::Set(d, at.min_lobe_width);
  const auto one = hn::Set(d, 1.0f);
  for (size_t i = 0; i < n; i += hn::Lanes(d)) {
    const auto base = hn::Mul(hn::Sub(hn::LoadU(du, slots + i), hn::Set(du, first)), hn::Set(du, uint32_t(CloudLayout::kWords)));
    const auto word = [&](size_t offset) { return hn::BitCast(di, hn::Add(base, hn::Set(du, uint32_t(offset)))); };
    const auto lx = hn::GatherIndex(d, cloud_floats, word(CloudLayout::kLocal));
    const auto ly = hn::GatherIndex(d, cloud_floats, word(CloudLayout::kLocal + 1));
    const auto lz = hn::GatherIndex(d, cloud_floats, word(CloudLayout::kLocal + 2));
    const auto object = hn::GatherIndex(du, cloud, word(CloudLayout::kObject));
    const auto placed = hn::Lt(object, objects);  // else the background
    const auto placed_f = hn::RebindMask(d, placed);
    // glm's mat4 x vec4, w = 1: (m0 x + m1 y) + (m2 z + m3 1), per row.
    hn::Vec<decltype(d)> world[3], eye[3];
    const uint32_t lane0_object = hn::GetLane(object);
    if (hn::AllTrue(du, hn::Eq(object, hn::Set(du, lane0_object))) && lane0_object < at.objects) {
      const float* m = at.object_to_world + 16 * size_t(lane0_object);
      const float* e = at.eye_local + 3 * size_t(lane0_object);
      for (int r = 0; r < 3; ++r) {
        world[r] = hn::Add(hn::Add(hn::Mul(hn::Set(d, m[r]), lx), hn::Mul(hn::Set(d, m[4 + r]), ly)),
                           hn::Add(hn::Mul(hn::Set(d, m[8 + r]), lz), hn::Mul(hn::Set(d, m[12 + r]), one)));
        eye[r] = hn::Set(d, e[r]);
      }
    } else {
      const auto safe = hn::IfThenElseZero(placed, object);  // the background's lanes read object 0's (unused)
      const auto matrix = hn::BitCast(di, hn::Mul(safe, hn::Set(du, 16u)));
      const auto eye_at = hn::BitCast(di, hn::Mul(safe, hn::Set(du, 3u)));
      const float* m = at.objects > 0 ? at.object_to_world : nullptr;
      for (int r = 0; r < 3; ++r) {
        if (!m) {
          world[r] = eye[r] = hn::Zero(d);
          continue;
        }
        const auto column = [&](int c) { return hn::GatherIndex(d, m, hn::Add(matrix, hn::Set(di, 4 * c + r))); };
        world[r] = hn::Add(hn::Add(hn::Mul(column(0), lx), hn::Mul(column(1), ly)),
                           hn::Add(hn::Mul(column(2), lz), hn::Mul(column(3), one)));
        eye[r] = hn::GatherIndex(d, at.eye_local, hn::Add(eye_at, hn::Set(di, r)));
      }
    }
    const hn::Vec<decltype(d)> local[3] = {lx, ly, lz};
    float* const out_world[3] = {b.x + i, b.y + i, b.z + i};
    float* const out_eye[3] = {b.eye_x + i, b.eye_y + i, b.eye_z + i};
    for (int r = 0; r < 3; ++r) {
      const auto background = hn::Add(hn::Set(d, at.eye[r]), hn::Mul(local[r], depth));
      hn::Store(hn::IfThenElse(placed_f, world[r], background), d, out_world[r]);
      hn::Store(hn::IfThenElseZero(placed_f, hn::Sub(eye[r], local[r])), d, out_eye[r]);
    }
    hn::Store(hn::IfThenElseZero(placed, hn::GatherIndex(du, cloud, word(CloudLayout::kNormal))), du, b.normal + i);
    hn::Store(hn::GatherIndex(du, cloud, word(CloudLayout::kView)), du, b.view + i);
    const auto width = hn::GatherIndex(d, cloud_floats, word(CloudLayout::kLobeWidth));
    hn::Store(hn::IfThenElse(hn::Lt(width, min_width), min_width, width), d, b.lobe_width + i);  // std::max's choice
  }
}

// unpack_winner, a vector of pixels at a time: the keys' low and high words apart (a key is
// two 32-bit words, low first), the winners' words and age bins gathered from their records.
HWY_INLINE void UnpackWinnersRow(const uint64_t* keys, const uint32_t* winner, const ProjectedPoint* records, size_t n,
                                 const WinnerPlanes& out) {
  const hn::ScalableTag<uint32_t> d;
  const hn::RebindToSigned<decltype(d)> di;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  const hn::Rebind<uint16_t, decltype(di)> d16;
  const size_t lanes = hn::Lanes(d);
  const auto all_ones = hn::Set(d, ~uint32_t(0)), index_mask = hn::Set(d, detail::kIndexMask);
  const auto infinity = hn::Set(d, 0x7f800000u), region_mask = hn::Set(d, 15u), low16 = hn::Set(d, 0xffffu);
  const uint32_t* words = reinterpret_cast<const uint32_t*>(records);  // 4 per record: key low, key high, word, age bin | tile pixel
  static_assert(offsetof(ProjectedPoint, word) == 8 && offsetof(ProjectedPoint, age_bin) == 12);
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    hn::Vec<decltype(d)> low, high;
    hn::LoadInterleaved2(d, reinterpret_cast<const uint32_t*>(keys + i), low, high);
    const auto empty = hn::And(hn::Eq(low, all_ones), hn::Eq(high, all_ones));
    const auto point = hn::IfThenElse(empty, all_ones, hn::And(low, index_mask));
    hn::StoreU(hn::BitCast(di, point), di, out.point + i);
    hn::StoreU(hn::BitCast(di, point), di, out.winners + i);
    hn::StoreU(hn::BitCast(hn::RebindToFloat<decltype(d)>(), hn::IfThenElse(empty, infinity, high)),
               hn::RebindToFloat<decltype(d)>(), out.depth + i);
    const auto region = hn::IfThenElse(empty, hn::PromoteTo(d, hn::LoadU(d8, out.region + i)),
                                       hn::And(hn::ShiftRight<28>(low), region_mask));
    hn::StoreU(hn::DemoteTo(d8, hn::BitCast(di, region)), d8, out.region + i);
    const auto at = hn::BitCast(di, hn::ShiftLeft<2>(hn::LoadU(d, winner + i)));
    hn::StoreU(hn::GatherIndex(d, words + 2, at), d, out.word + i);
    const auto age_bin = hn::And(hn::GatherIndex(d, words + 3, at), low16);
    hn::StoreU(hn::DemoteTo(d16, hn::BitCast(di, age_bin)), d16, out.age_bin + i);
  }
  for (; i < n; ++i) unpack_winner(keys[i], records[winner[i]], out, i);
}

// encode_by_steps (point_cache.cpp) in lanes: 0 below the first step (and NaN), else the bucket's
// start code plus the steps passed in `scans` scans.
template <class D>
HWY_INLINE hn::Vec<hn::RebindToSigned<D>> EncodeBySteps(D d, const ColourStepTables& t, hn::Vec<D> linear) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const auto shown = hn::RebindMask(di, hn::Ge(linear, hn::Set(d, t.steps[1])));
  const auto bucket = hn::Min(hn::Sub(hn::ShiftRight<16>(hn::BitCast(du, linear)), hn::Set(du, t.first)), hn::Set(du, t.buckets - 1));
  auto k = hn::GatherIndex(di, t.start, hn::BitCast(di, bucket));
  const auto one = hn::Set(di, 1);
  for (int s = 0; s < t.scans; ++s) {
    const auto next = hn::GatherIndex(d, t.steps, hn::Add(k, one));
    k = hn::Add(k, hn::IfThenElseZero(hn::RebindMask(di, hn::Le(next, linear)), one));
  }
  return hn::IfThenElseZero(shown, k);
}

// std::max(a, b) and std::min(a, b) (glm's too), ties and NaNs included: (a < b) ? b : a and (b < a) ? b : a.
template <class V>
HWY_INLINE V StdMax(V a, V b) { return hn::IfThenElse(hn::Lt(a, b), b, a); }
template <class V>
HWY_INLINE V StdMin(V a, V b) { return hn::IfThenElse(hn::Lt(b, a), b, a); }

// faded_colour_word, a vector of points at a time: faded_colours, epi_colour and the encoding,
// the same operations in the same order.
void FadeBatchKernel(float fade_start, float fade_span, FadeBatch& b, size_t n) {
  const hn::ScalableTag<float> d;
  const hn::RebindToSigned<decltype(d)> di;
  const ColourStepTables& t = colour_step_tables();
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0f), sixteen = hn::Set(d, 16.0f);
  const auto start = hn::Set(d, fade_start), span = hn::Set(d, fade_span), colour_max = hn::Set(d, kEpiColourMax);
  for (size_t i = 0; i < n; i += hn::Lanes(d)) {
    auto fade = hn::Div(hn::Sub(hn::Div(hn::ConvertTo(d, hn::Load(di, b.staleness + i)), sixteen), start), span);
    fade = hn::IfThenElse(hn::Lt(fade, zero), zero, hn::IfThenElse(hn::Lt(one, fade), one, fade));  // std::clamp
    const auto kept = hn::Sub(one, fade);
    const auto rescaled = hn::RebindMask(d, hn::Ne(hn::Load(di, b.rescaled + i), hn::Zero(di)));
    const auto transmission = hn::Load(d, b.transmission + i);
    hn::Vec<decltype(d)> base[3], view[3];
    const float* colour[3] = {b.r + i, b.g + i, b.b + i};
    const float* view_dependent[3] = {b.vr + i, b.vg + i, b.vb + i};
    for (int c = 0; c < 3; ++c) {
      const auto vd = hn::Load(d, view_dependent[c]), col = hn::Load(d, colour[c]);
      view[c] = hn::Mul(vd, kept);
      const auto shown = hn::IfThenElse(rescaled, hn::Add(hn::Mul(hn::Sub(col, vd), transmission), view[c]), hn::Sub(col, hn::Mul(vd, fade)));
      base[c] = StdMax(hn::Sub(shown, view[c]), zero);  // epi_colour from here
    }
    const auto largest = StdMax(base[0], StdMax(base[1], base[2]));
    const auto scale = hn::IfThenElse(hn::Gt(largest, colour_max), hn::Div(colour_max, largest), one);
    hn::Vec<decltype(di)> word = hn::Zero(di);
    for (int c = 0; c < 3; ++c) {
      const auto scaled = hn::Mul(base[c], scale);
      const auto linear = StdMin(hn::Add(scaled, view[c]), StdMax(scaled, one));
      word = hn::Or(word, hn::ShiftLeftSame(EncodeBySteps(d, t, linear), 8 * c));
    }
    hn::Store(hn::BitCast(hn::RebindToUnsigned<decltype(d)>(), word), hn::RebindToUnsigned<decltype(d)>(), b.word + i);
  }
}

void UnpackWinners(const uint64_t* keys, const uint32_t* winner, size_t pitch, const ProjectedPoint* records,
                   size_t columns, size_t rows, const WinnerPlanes& out, size_t out_pitch) {
  for (size_t r = 0; r < rows; ++r) {
    const size_t o = r * out_pitch;
    UnpackWinnersRow(keys + r * pitch, winner + r * pitch, records, columns,
                     {out.point + o, out.winners + o, out.depth + o, out.region + o, out.word + o, out.age_bin + o});
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace epi::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace epi::render {

HWY_EXPORT(ProjectBatchFrame);
HWY_EXPORT(UnpackWinners);
HWY_EXPORT(GatherBatch);
HWY_EXPORT(FadeBatchKernel);

void fade_batch(float fade_start, float fade_span, FadeBatch& batch, size_t n) {
  HWY_DYNAMIC_DISPATCH(FadeBatchKernel)(fade_start, fade_span, batch, n);
}

void project_batch(const ViewFrame& frame, ProjectionBatch& batch, size_t n) {
  HWY_DYNAMIC_DISPATCH(ProjectBatchFrame)(frame, batch, n);
}

void gather_batch(const uint32_t* cloud, uint32_t first, const uint32_t* slots, size_t n, const BatchPlacement& at,
                  ProjectionBatch& batch) {
  HWY_DYNAMIC_DISPATCH(GatherBatch)(cloud, first, slots, n, at, batch);
}

void unpack_winners(const uint64_t* keys, const uint32_t* winner, size_t pitch, const ProjectedPoint* records,
                    size_t columns, size_t rows, const WinnerPlanes& out, size_t out_pitch) {
  HWY_DYNAMIC_DISPATCH(UnpackWinners)(keys, winner, pitch, records, columns, rows, out, out_pitch);
}

}  // namespace epi::render
#endif  // HWY_ONCE

#include "epi/trace.h"

#include <algorithm>
#include <stdexcept>

#include "epi/antialias.h"
#include "epi/fill.h"
#include "epi/geometry.h"
#include "epi/interpolate.h"
#include "epi/rendercache.h"
#include "epi/tables.h"

namespace epi {

namespace {

constexpr int kInterpRadius = 3;  // fill of the 3x3 reads the interpolated 5x5 around each: 7x7

Rgb to_rgb(const float c[3]) { return {c[0], c[1], c[2]}; }

}  // namespace

Tracer::Tracer(EpiImage epi, BoundaryMasks masks, const ReconstructSettings& settings)
    : epi_(std::move(epi)), masks_(std::move(masks)), settings_(settings),
      types_(size_t(epi_.width) * size_t(epi_.height)) {
  if (settings_.filter != Filter::epi) throw std::invalid_argument("the trace follows the EPI filters");
  if (epi_.width != masks_.width || epi_.height != masks_.height)
    throw std::invalid_argument("EPI and boundary masks differ in size");
  classify_rows(epi_, masks_, 0, epi_.height, types_.data());
  for (int y = 0; y < epi_.height; ++y)
    for (int x = 0; x < epi_.width; ++x) epi_.cache[epi_.index(x, y)] |= reach_full(epi_, x, y);
}

PixelTrace Tracer::trace(int x, int y) const {
  if (!epi_.inside(x, y)) throw std::out_of_range("pixel outside the image");
  const EpiTables& t = epi_tables();
  const EpiRows r = rows();
  const int w = epi_.width, h = epi_.height;
  PixelTrace p;
  p.x = x, p.y = y;

  // Classification.
  masks_.pixel_sides(x, y, p.sides);
  const uint16_t e = epi_.edge[epi_.index(x, y)];
  const PixelClass c = classify_pixel(masks_, x, y, e);
  p.kind = c.kind;
  p.type = c.type;
  p.code = edge_code(c.edge);
  p.has_sample = has_sample(c.edge);
  p.usable = usable_sample(c.edge);
  p.sample_region = sample_region(c.edge);
  if (c.kind == CellKind::simple) {
    p.p_low = code_low(p.code), p.p_high = code_high(p.code);
    p.area_a = t.area_of_a(p.code);
    p.primary_is_b = (p.type - 2) & 1;
    if (p.has_sample) p.sample_side = t.side(p.code, p.sample_region);
  }

  // Reachability.
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int k = (dy + 2) * 5 + dx + 2;
      p.inside[k] = epi_.inside(x + dx, y + dy);
      p.types[k] = uint8_t(p.inside[k] ? type_at(x + dx, y + dy) : kTypeComplex);
    }
  p.reach = reach_full_traced(r.type_rows(), x, y, p.reach_steps);
  p.reach_fast_path = p.reach_steps.empty();

  // Interpolation of the 7x7 around the pixel (its fill and its neighbours' fill read it).
  constexpr int kSide = 2 * kInterpRadius + 1;
  std::vector<float> interp(size_t(kSide) * size_t(w) * 3);
  std::vector<uint8_t> found(size_t(kSide) * size_t(w));
  auto interp_row = [&](int py) { return &interp[size_t(py - y + kInterpRadius) * size_t(w) * 3]; };
  auto found_row = [&](int py) { return &found[size_t(py - y + kInterpRadius) * size_t(w)]; };
  for (int py = std::max(0, y - kInterpRadius); py <= std::min(h - 1, y + kInterpRadius); ++py)
    for (int px = std::max(0, x - kInterpRadius); px <= std::min(w - 1, x + kInterpRadius); ++px) {
      bool f = false;
      const float priority = interpolate_pixel(r, px, py, reach_mask(epi_.cache[epi_.index(px, py)]),
                                               interp_row(py) + 3 * px, &f, settings_.blend_unreached_near_edges);
      found_row(py)[px] = f;
      if (px == x && py == y) p.priority = priority, p.found = f;
    }
  p.interpolated = to_rgb(interp_row(y) + 3 * x);
  p.age = sample_age(epi_.color[epi_.index(x, y)]);
  p.complex_estimate = c.kind == CellKind::complex;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      if (!epi_.inside(x + dx, y + dy)) continue;
      const uint16_t ne = r.edge_at(x + dx, y + dy);
      const bool reachable = (dx == 0 && dy == 0) || ((p.reach >> reach_bit(dx, dy)) & 1);
      const bool counts = p.complex_estimate ? has_sample(ne) : reachable && usable_sample(ne);
      if (!counts) continue;
      float rgb[3];
      decode_color(r.color_at(x + dx, y + dy), rgb);
      p.contributions.push_back({dx, dy, kInterpolationWeights[(dy + 2) * 5 + dx + 2], to_rgb(rgb)});
      p.total_weight += p.contributions.back().weight;
    }
  p.fallback = !p.found;
  if (p.fallback) {
    p.reach7 = reach_window7(r.type_rows(), x, y);
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        if (!epi_.inside(x + dx, y + dy) || !((p.reach7 >> window7_bit(dx, dy)) & 1) ||
            !usable_sample(r.edge_at(x + dx, y + dy)))
          continue;
        const float d = float(1 + dx * dx + dy * dy);
        float rgb[3];
        decode_color(r.color_at(x + dx, y + dy), rgb);
        p.fallback_contributions.push_back({dx, dy, 1.0f / (d * d), to_rgb(rgb)});
      }
  }

  // Fill of the 3x3 (the output's footprint), as reconstruct_oracle's fill step.
  std::vector<float> filled(size_t(3) * size_t(w) * 3);
  auto filled_row = [&](int py) { return &filled[size_t(py - y + 1) * size_t(w) * 3]; };
  for (int py = std::max(0, y - 1); py <= std::min(h - 1, y + 1); ++py) {
    const float* interp_rows[5];
    const uint8_t* found_rows[5];
    for (int k = 0; k < 5; ++k) {
      const int ry = py - 2 + k;
      interp_rows[k] = ry >= 0 && ry < h ? interp_row(ry) : nullptr;
      found_rows[k] = ry >= 0 && ry < h ? found_row(ry) : nullptr;
    }
    for (int px = std::max(0, x - 1); px <= std::min(w - 1, x + 1); ++px) {
      float* out = filled_row(py) + 3 * px;
      if (settings_.fill) {
        fill_pixel(px, w, reach_mask(epi_.cache[epi_.index(px, py)]), interp_rows, found_rows, out);
      } else {
        std::copy(interp_rows[2] + 3 * px, interp_rows[2] + 3 * px + 3, out);
      }
    }
  }
  p.filled = to_rgb(filled_row(y) + 3 * x);
  p.fill_ran = settings_.fill && !p.found;
  if (p.fill_ran)
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        if ((dx == 0 && dy == 0) || !epi_.inside(x + dx, y + dy) || !((p.reach >> reach_bit(dx, dy)) & 1) ||
            !found_row(y + dy)[x + dx])
          continue;
        p.fill_contributions.push_back(
            {dx, dy, kInterpolationWeights[(dy + 2) * 5 + dx + 2], to_rgb(interp_row(y + dy) + 3 * (x + dx))});
      }

  // Output, by the schedules' own choice (reconstruct.h, output_filter).
  const float* filled_rows[3] = {y > 0 ? filled_row(y - 1) : nullptr, filled_row(y),
                                 y + 1 < h ? filled_row(y + 1) : nullptr};
  float out[3] = {p.filled[0], p.filled[1], p.filled[2]};
  const OutputFilter output = output_filter(settings_, masks_.centre_lines, p.type);
  if (output == OutputFilter::complex_filter) {
    p.output = PixelTrace::Output::complex_filter;
    p.estimate = p.filled;
    complex_pixel_traced(r, masks_, x, y, filled_row(y) + 3 * x, out, p.complex);
  } else if (output == OutputFilter::antialiased) {
    p.output = PixelTrace::Output::antialiased;
    const int k = t.neighbour_for_secondary(p.code, !p.primary_is_b);
    const int nx = x + kNeighbourDx[k], ny = y + kNeighbourDy[k];
    p.primary_area = p.primary_is_b ? 1.0f - p.area_a : p.area_a;
    if (epi_.inside(nx, ny)) p.secondary_neighbour = k, p.secondary = to_rgb(filled_row(ny) + 3 * nx);
    antialias_pixel(r, x, y, filled_rows, out);
  }
  p.result = to_rgb(out);

  float rc[3];
  rendercache_pixel(r, x, y, rc);
  p.rendercache = to_rgb(rc);
  return p;
}

}  // namespace epi

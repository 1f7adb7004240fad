// Prioritized sampling (docs/render.md, "Sampling"): the priority image (interpolation weight and
// point age, from core/epi) turned into shading requests by error-diffusion dithering, a fixed
// budget per frame, and predictive sampling: the camera extrapolated a few frames ahead and a
// cheap projection of the cloud finding the gaps about to open.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "epi/epi_pixel.h"
#include "render/point_cache.h"
#include "shade/shader.h"
#include "shade/view.h"

namespace epi::render {

// Exactly min(count, width * height) distinct pixel indices, spread in proportion to priority
// by error diffusion along a space-filling path (docs/render.md, "Sampling"), in bands of rows
// dithered in parallel. Pixels of zero priority are taken only when every positive one is; zero
// priority everywhere counts as uniform. Deterministic, the same for any thread count.
std::vector<uint32_t> dither_pixels(std::span<const float> priority, int width, int height, size_t count);

// An error diffusion's picks (`chosen`, with each pixel's value at its decision) settled to
// exactly `count` pixels: a surplus drops the picks nearest the threshold, a shortfall adds the
// unpicked pixels nearest it, positive priority (null `priority`: uniform) before zero, ties by
// index. Sorted pixel indices.
std::vector<uint32_t> settle_picks(const float* priority, std::span<const uint8_t> chosen, std::span<const float> decision,
                                   size_t count);

// The parallel frame of dither_pixels: `count` is shared among bands of 64 rows by their priority
// sums (largest remainders; positive pixels first), and each band is dithered on its own by
// band_dither(priority of the band or null when uniform, uniform, width, rows, band count, band
// index, the band's priority sum: its max(0, p) added in pixel order in double), which returns
// band-relative pixel indices. The benchmark runs its baseline through it.
using BandDither = std::function<std::vector<uint32_t>(const float*, bool, int, int, size_t, uint64_t, double)>;
std::vector<uint32_t> dither_in_bands(std::span<const float> priority, int width, int height, size_t count,
                                      const BandDither& band_dither);

// One request per pixel, jittered uniformly inside it by a hash of (seed, frame, pixel); ids
// count up from first_id.
void make_requests(std::span<const uint32_t> pixels, int width, uint64_t seed, uint64_t frame, uint32_t first_id,
                   std::vector<ShadeRequest>& out);

// Effort where samples are sparse (docs/render.md, "Effort where samples are sparse"): a result
// is shown over about 1 / share pixels, share being the local fraction of the EPI's pixels that
// hold a sample, so its noise weighs in proportion to that footprint; the samples that minimize
// the summed error go in proportion to its square root (Neyman's allocation). Each request's
// effort becomes round(sqrt(dense / share)), clamped to [1, most], share counted over the
// kSparseBlendBlock-square blocks (sparse_blend.h) within one block of the request's (`counts`:
// the blocks' sample counts, the caller's storage). most <= 1: every effort 1.
void set_sparse_effort(std::span<ShadeRequest> requests, const EpiImage& epi, float dense, int most,
                       std::vector<uint32_t>& counts);

// The order in which a frame's requests go to the asynchronous shader, which may shade only a
// prefix before the next frame cancels the rest: each shot's requests are shuffled by a hash of
// (seed, frame) (Fisher-Yates), and the shots are cut into rounds of about round_size requests,
// each round holding every shot's next slice in proportion to its size. So every prefix is spread
// over the image and over the predicted gaps.
void shuffle_requests(std::vector<ShadeRequest>& requests, uint64_t seed, uint64_t frame);
struct SubmissionPart {
  size_t shot = 0, begin = 0, end = 0;  // requests [begin, end) of shot
};
std::vector<SubmissionPart> interleave_shots(std::span<const size_t> shot_sizes, size_t round_size);

// The camera `ahead` frames later if it keeps moving as from `previous` to `current` (eye and
// target extrapolated linearly, up and field of view kept); `current` where that camera would be
// degenerate or beyond the ray tracer's range (kMaxRayCoordinate).
Camera extrapolate_camera(const Camera& previous, const Camera& current, float ahead);

// Predictive occupancy: a pseudo-random 1/stride of the valid points (subset `phase`, chosen by a
// hash of the slot, so structure in the cloud's order does not show) projected into `frame` as
// splat x splat squares; one byte per pixel, 1 where occupied. The gaps are the zeros.
std::vector<uint8_t> predicted_occupancy(const PointCache& cache, const ViewFrame& frame,
                                         std::span<const glm::mat4> object_to_world, int stride, int phase, int splat);
// The same into `occupied` (resized, its storage kept: the renderer's, per frame).
void predicted_occupancy(const PointCache& cache, const ViewFrame& frame, std::span<const glm::mat4> object_to_world,
                         int stride, int phase, int splat, std::vector<uint8_t>& occupied);

}  // namespace epi::render

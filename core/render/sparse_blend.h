// Sparse regions become smooth, not a mosaic (docs/render.md, "Sparse regions"). Where a moving
// camera has spread the cached points apart (a surface it approaches), a pixel reaches at most
// one sample in its 5x5 and the EPI shows each noisy result as a patch. There the image is blended
// towards a normalized convolution of the EPI's samples (Knutsson and Westin 1993) with an
// edge-stopping recursive filter (the domain transform's recursive filter, Gastal and Oliveira
// 2011, whose distance is infinite across a pixel an edge crosses), by the local share of pixels
// holding a sample: untouched where samples are dense, replaced where they are sparse.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "epi/epi_pixel.h"
#include "image/image.h"

namespace epi::render {

struct SparseBlendSettings {
  float sigma = 2.0f;    // the filter's scale in pixels (its kernel's standard deviation)
  int iterations = 1;    // horizontal + vertical pass pairs (the domain transform's N; 2 measured the
                         // same along the paths at twice the cost)
  float dense = 0.3f;    // local share of pixels holding a sample at and above which the EPI stays
  float sparse = 0.05f;  // ... at and below which the smooth interpolation replaces it (linear between)
};

// Per pixel, filtered: linear r, g, b and weight of the samples, and the mass of pixels that are
// no barrier (the kernel's part inside the image and the pixel's edge-bounded region).
inline constexpr int kSparseBlendChannels = 5;

struct SparseBlendScratch {
  std::vector<float> sums;  // the filtered planes
};

// The normalized-convolution sums (the scalar definition, the oracle of sparse_blend's kernels), as kSparseBlendChannels planes of width x height floats (plane
// c of pixel i at sums[c * width * height + i]; a keep mask follows them): r, g, b and a weight of
// 1 where the EPI holds a sample and no barrier, and 1 for every pixel that is no barrier,
// filtered `iterations` times by rows then columns, each line with the kernel a^|d| (a from the
// iteration's scale) restarted at each barrier pixel, which keeps zeros.
void filter_samples(const EpiImage& epi, std::span<const uint8_t> barrier, const SparseBlendSettings& settings,
                    std::vector<float>& sums);

// Whether some kSparseBlendBlock-square block of the EPI (cut by the image's border) has fewer
// samples than `dense` times its pixels: sparse_blend does nothing in frames where none has.
inline constexpr int kSparseBlendBlock = 8;
bool any_sparse_block(const EpiImage& epi, float dense);
// The samples in each kSparseBlendBlock-square block of block row `by` (cut by the image's
// border), into row[0 .. blocks across); any_sparse_block's count, shared with set_sparse_effort.
void count_block_samples(const EpiImage& epi, int by, uint32_t* row);

// In frames with a sparse block (any_sparse_block), blends `image` (the reconstruction of `epi`)
// towards rgb / weight by t = clamp((dense - weight / mass) / (dense - sparse), 0, 1)
// (weight / mass: the local share of pixels holding a sample), except at barrier pixels (non-zero:
// an edge crosses them) and where no sample is reached. Returns the number of pixels changed.
// The filter runs as Highway kernels (sparse_blend_kernels.h): rows eight at a time in vector
// lanes, columns in strips of 32, the blend in the columns' last sweep.
size_t sparse_blend(RgbImage& image, const EpiImage& epi, std::span<const uint8_t> barrier,
                    const SparseBlendSettings& settings, SparseBlendScratch& scratch);

// sparse_blend over filter_samples and a plain per-pixel loop: its oracle, the same bits.
size_t sparse_blend_reference(RgbImage& image, const EpiImage& epi, std::span<const uint8_t> barrier,
                              const SparseBlendSettings& settings, std::vector<float>& sums);

}  // namespace epi::render

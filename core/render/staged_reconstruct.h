// The EPI reconstruction run one stage after the other over the whole image, each stage in
// parallel over rows, so that each stage can be timed (the paper's table 2). The output equals
// reconstruct_oracle (core/epi) bit for bit; core/epi's fused, tiled reconstructor is faster.
#pragma once

#include <vector>

#include "epi/reconstruct.h"

namespace epi::render {

struct ReconstructTimes {
  double classify = 0, reachability = 0, interpolate = 0, antialias = 0, complex = 0;  // ms (interpolate includes the fill step)
};

class StagedReconstructor {
 public:
  // Classifies `epi` in place (as the oracle does) and writes image, priority and counts into out.
  void run(EpiImage& epi, const BoundaryMasks& masks, const ReconstructSettings& settings, Reconstruction& out,
           ReconstructTimes& times);

 private:
  std::vector<uint32_t> reach_;
  std::vector<uint8_t> found_, types_;
  RgbImage interpolated_, filled_;
};

}  // namespace epi::render

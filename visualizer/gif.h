// Animated GIF (giflib) from RGB frames: one global palette of the 255 most frequent colours
// (5 bits per channel), each pixel mapped to its nearest palette colour, no dithering; the
// drawings are flat colours and anti-aliased lines, which this keeps sharp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace epi::vis {

// frames: RGB8, width x height each; delay in 1/100 s; loops forever. Throws std::runtime_error.
void write_gif(const std::string& file, const std::vector<std::vector<uint8_t>>& frames, int width, int height,
               int delay_centiseconds);

}  // namespace epi::vis

// The teaching patterns that ship with the visualizer, in the format of `epi reconstruct`
// (epi/pattern.h). Each isolates one case the EPI must handle (docs/visualizer.md, "Presets").
#pragma once

#include <string>
#include <vector>

#include "epi/pattern.h"

namespace epi::vis {

struct Preset {
  std::string name;
  std::string description;  // one sentence: what it shows
  int pixel_x, pixel_y;     // a pixel worth following
  Pattern pattern;
};

const std::vector<Preset>& presets();
// nullptr when there is no preset of that name.
const Preset* find_preset(const std::string& name);

}  // namespace epi::vis

// What the visualizer shows: a source (a preset, a PATTERN.json or an EPI snapshot), its EPI,
// the reconstructions beside it, and the trace of one pixel (core/epi/trace.h).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "epi/pattern.h"
#include "epi/reconstruct.h"
#include "epi/trace.h"
#include "image/image.h"

namespace epi::vis {

// what(): one line naming the file (or preset) and the problem.
struct SourceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Source {
  std::string name;                // preset name or file path
  std::optional<Pattern> pattern;  // pattern sources: the polygons (exact coverage is known)
  double density = 0.25;           // pattern sources
  uint64_t seed = 1;
  EpiImage epi;                    // samples (unclassified)
  BoundaryMasks masks;
  std::vector<Segment> segments;
  ReconstructSettings settings;
};

// A preset name, a PATTERN.json or an EPI snapshot (io/snapshot). Density and seed apply to
// patterns. Throws SourceError.
Source load_source(const std::string& name_or_file, double density, uint64_t seed);
// A pattern sampled with the density and seed.
Source pattern_source(const Pattern& pattern, const std::string& name, double density, uint64_t seed);

class Model {
 public:
  explicit Model(Source source);
  const Source& source() const { return source_; }
  int width() const { return source_.epi.width; }
  int height() const { return source_.epi.height; }
  const Tracer& tracer() const { return *tracer_; }
  const Reconstruction& epi_result() const { return epi_result_; }   // reconstruct_oracle, EPI filters
  const Reconstruction& rendercache_result() const { return rc_result_; }
  const RgbImage* exact() const { return source_.pattern ? &exact_ : nullptr; }  // pattern sources
  int type_at(int x, int y) const { return tracer_->type_at(x, y); }

 private:
  Source source_;
  std::unique_ptr<Tracer> tracer_;
  Reconstruction epi_result_, rc_result_;
  RgbImage exact_;
};

}  // namespace epi::vis

#include "model.h"

#include <fstream>

#include "presets.h"
#include "snapshot.h"

namespace epi::vis {

Source pattern_source(const Pattern& pattern, const std::string& name, double density, uint64_t seed) {
  if (!(density >= 0.0 && density <= 1.0)) throw SourceError("density " + std::to_string(density) + " is not in [0, 1]");
  Source s;
  s.name = name;
  s.pattern = pattern;
  s.density = density;
  s.seed = seed;
  s.epi = EpiImage(pattern.width, pattern.height);
  s.masks = BoundaryMasks(pattern.width, pattern.height, true);
  s.segments = pattern_edges(pattern);
  rasterize_edges(s.masks, s.segments);
  sample_pattern(pattern, density, seed, s.epi);
  return s;
}

Source load_source(const std::string& name_or_file, double density, uint64_t seed) {
  if (const Preset* p = find_preset(name_or_file)) return pattern_source(p->pattern, p->name, density, seed);
  if (!std::ifstream(name_or_file))
    throw SourceError(name_or_file + ": no such file, and not a preset (" + [] {
      std::string names;
      for (const Preset& p : presets()) names += (names.empty() ? "" : ", ") + p.name;
      return names;
    }() + ")");
  try {
    if (is_snapshot_file(name_or_file)) {
      Snapshot snap = load_snapshot(name_or_file);
      Source s;
      s.name = name_or_file;
      s.epi = std::move(snap.epi);
      s.masks = std::move(snap.masks);
      s.segments = std::move(snap.segments);
      s.settings = snap.settings;
      return s;
    }
    return pattern_source(load_pattern(name_or_file), name_or_file, density, seed);
  } catch (const SnapshotError& e) {
    throw SourceError(e.what());
  } catch (const PatternError& e) {
    throw SourceError(e.what());
  }
}

Model::Model(Source source) : source_(std::move(source)) {
  tracer_ = std::make_unique<Tracer>(source_.epi, source_.masks, source_.settings);
  EpiImage epi = source_.epi;
  epi_result_ = reconstruct_oracle(epi, source_.masks, source_.settings);
  ReconstructSettings rc = source_.settings;
  rc.filter = Filter::rendercache;
  epi = source_.epi;
  rc_result_ = reconstruct_oracle(epi, source_.masks, rc);
  if (source_.pattern) exact_ = exact_image(*source_.pattern);
}

}  // namespace epi::vis

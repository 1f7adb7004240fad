// `epi compare IMAGE REFERENCE`: how far an image is from a reference (io/image/image_compare.h).
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "commands.h"
#include "output.h"

namespace epi::cli {

int run_compare(const CompareOptions& options) {
  if (!options.json.empty()) {
    check_output_file(options.json);
    for (const std::string& input : {options.image, options.reference})
      if (std::filesystem::weakly_canonical(options.json) == std::filesystem::weakly_canonical(input))
        throw std::runtime_error(options.json + ": --json names an input image");
  }
  const ReferenceImage image = read_reference(options.image);
  const ReferenceImage reference = read_reference(options.reference, image.image.width, image.image.height);
  const ImageDifference d =
      compare_images(image.image, image.encoding, reference.image, reference.encoding, options.exposure);
  std::printf("%s against %s: %dx%d\n  %s\n", options.image.c_str(), options.reference.c_str(), d.width, d.height,
              difference_line(d).c_str());
  if (!options.json.empty()) {
    nlohmann::json json = difference_json(d);
    json["image"] = options.image;
    json["reference"] = options.reference;
    json["exposure"] = options.exposure;
    StagedOutputs outputs;
    outputs.add_json(options.json, json);
    outputs.commit();
  }
  return 0;
}

}  // namespace epi::cli

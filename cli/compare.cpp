// `epi compare IMAGE REFERENCE`: how far an image is from a reference (io/image/image_compare.h).
#include <cstdio>
#include <stdexcept>

#include "commands.h"
#include "output.h"

namespace epi::cli {

int run_compare(const CompareOptions& options) {
  if (!options.json.empty()) check_output_file(options.json);
  if (!options.diff.empty()) check_output_image(options.diff);
  check_distinct_outputs({options.json, options.diff});
  for (const std::string& input : {options.image, options.reference}) check_not_input({options.json, options.diff}, input);
  const ReferenceImage image = read_reference(options.image);
  const ReferenceImage reference = read_reference(options.reference, image.image.width, image.image.height);
  const ImageDifference d =
      compare_images(image.image, image.encoding, reference.image, reference.encoding, options.exposure);
  std::printf("%s against %s: %dx%d\n  %s\n", options.image.c_str(), options.reference.c_str(), d.width, d.height,
              difference_line(d).c_str());
  StagedOutputs outputs;
  if (!options.json.empty()) {
    nlohmann::json json = difference_json(d);
    json["image"] = options.image;
    json["reference"] = options.reference;
    json["exposure"] = options.exposure;
    outputs.add_json(options.json, json);
  }
  if (!options.diff.empty())
    outputs.add_image(options.diff, difference_image(image.image, image.encoding, reference.image, reference.encoding,
                                                     options.exposure, options.diff_scale));
  outputs.commit();
  return 0;
}

}  // namespace epi::cli

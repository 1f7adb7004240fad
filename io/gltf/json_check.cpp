#include "json_check.h"

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace epi::gltf {

namespace {

using nlohmann::json;

enum class Type { index, number, string, boolean, object, object_array, number_array, index_array, string_array };

struct Schema;

struct Property {
  const char* name;
  Type type;
  const Schema* schema = nullptr;  // for object and object_array
  size_t length = 0;               // for number_array: exact length, 0 = any
};

// An object's known properties; `other_values` types every other key (maps such as attributes).
struct Schema {
  std::vector<Property> properties;
  std::optional<Type> other_values = std::nullopt;
};

// Bottom-up, so that every nested schema exists before it is referenced.
const Schema kIndexMap{{}, Type::index};
const Schema kTextureInfo{
    {{"index", Type::index}, {"texCoord", Type::index}, {"scale", Type::number}, {"strength", Type::number}}};
const Schema kPbr{{{"baseColorFactor", Type::number_array, nullptr, 4},
                   {"baseColorTexture", Type::object, &kTextureInfo},
                   {"metallicFactor", Type::number},
                   {"roughnessFactor", Type::number},
                   {"metallicRoughnessTexture", Type::object, &kTextureInfo}}};
const Schema kMaterial{{{"pbrMetallicRoughness", Type::object, &kPbr},
                        {"normalTexture", Type::object, &kTextureInfo},
                        {"occlusionTexture", Type::object, &kTextureInfo},
                        {"emissiveTexture", Type::object, &kTextureInfo},
                        {"emissiveFactor", Type::number_array, nullptr, 3},
                        {"alphaMode", Type::string},
                        {"alphaCutoff", Type::number},
                        {"doubleSided", Type::boolean}}};
const Schema kPrimitive{{{"attributes", Type::object, &kIndexMap},
                         {"indices", Type::index},
                         {"material", Type::index},
                         {"mode", Type::index},
                         {"targets", Type::object_array, &kIndexMap}}};
const Schema kMesh{{{"primitives", Type::object_array, &kPrimitive}, {"weights", Type::number_array}}};
const Schema kNode{{{"camera", Type::index},
                    {"children", Type::index_array},
                    {"skin", Type::index},
                    {"matrix", Type::number_array, nullptr, 16},
                    {"mesh", Type::index},
                    {"rotation", Type::number_array, nullptr, 4},
                    {"scale", Type::number_array, nullptr, 3},
                    {"translation", Type::number_array, nullptr, 3},
                    {"weights", Type::number_array}}};
const Schema kScene{{{"nodes", Type::index_array}}};
const Schema kSparseIndices{{{"bufferView", Type::index}, {"byteOffset", Type::index}, {"componentType", Type::index}}};
const Schema kSparseValues{{{"bufferView", Type::index}, {"byteOffset", Type::index}}};
const Schema kSparse{
    {{"count", Type::index}, {"indices", Type::object, &kSparseIndices}, {"values", Type::object, &kSparseValues}}};
const Schema kAccessor{{{"bufferView", Type::index},
                        {"byteOffset", Type::index},
                        {"componentType", Type::index},
                        {"normalized", Type::boolean},
                        {"count", Type::index},
                        {"type", Type::string},
                        {"max", Type::number_array},
                        {"min", Type::number_array},
                        {"sparse", Type::object, &kSparse}}};
const Schema kBufferView{{{"buffer", Type::index},
                          {"byteOffset", Type::index},
                          {"byteLength", Type::index},
                          {"byteStride", Type::index},
                          {"target", Type::index}}};
const Schema kBuffer{{{"uri", Type::string}, {"byteLength", Type::index}}};
const Schema kPerspective{
    {{"aspectRatio", Type::number}, {"yfov", Type::number}, {"zfar", Type::number}, {"znear", Type::number}}};
const Schema kOrthographic{
    {{"xmag", Type::number}, {"ymag", Type::number}, {"zfar", Type::number}, {"znear", Type::number}}};
const Schema kCamera{{{"type", Type::string},
                      {"perspective", Type::object, &kPerspective},
                      {"orthographic", Type::object, &kOrthographic}}};
const Schema kImage{{{"uri", Type::string}, {"mimeType", Type::string}, {"bufferView", Type::index}}};
const Schema kTexture{{{"sampler", Type::index}, {"source", Type::index}}};
const Schema kSampler{
    {{"magFilter", Type::index}, {"minFilter", Type::index}, {"wrapS", Type::index}, {"wrapT", Type::index}}};
const Schema kSkin{{{"inverseBindMatrices", Type::index}, {"skeleton", Type::index}, {"joints", Type::index_array}}};
const Schema kChannelTarget{{{"node", Type::index}, {"path", Type::string}}};
const Schema kChannel{{{"sampler", Type::index}, {"target", Type::object, &kChannelTarget}}};
const Schema kAnimationSampler{{{"input", Type::index}, {"interpolation", Type::string}, {"output", Type::index}}};
const Schema kAnimation{
    {{"channels", Type::object_array, &kChannel}, {"samplers", Type::object_array, &kAnimationSampler}}};
const Schema kAsset{{{"version", Type::string},
                     {"generator", Type::string},
                     {"copyright", Type::string},
                     {"minVersion", Type::string}}};
const Schema kRoot{{{"asset", Type::object, &kAsset},
                    {"scene", Type::index},
                    {"scenes", Type::object_array, &kScene},
                    {"nodes", Type::object_array, &kNode},
                    {"meshes", Type::object_array, &kMesh},
                    {"materials", Type::object_array, &kMaterial},
                    {"accessors", Type::object_array, &kAccessor},
                    {"bufferViews", Type::object_array, &kBufferView},
                    {"buffers", Type::object_array, &kBuffer},
                    {"cameras", Type::object_array, &kCamera},
                    {"images", Type::object_array, &kImage},
                    {"textures", Type::object_array, &kTexture},
                    {"samplers", Type::object_array, &kSampler},
                    {"skins", Type::object_array, &kSkin},
                    {"animations", Type::object_array, &kAnimation},
                    {"extensionsUsed", Type::string_array},
                    {"extensionsRequired", Type::string_array}}};

// The extensions epi reads. KHR_lights_punctual has the light list at the root and a light index on nodes.
const Schema kSpot{{{"innerConeAngle", Type::number}, {"outerConeAngle", Type::number}}};
const Schema kLight{{{"type", Type::string},
                     {"color", Type::number_array, nullptr, 3},
                     {"intensity", Type::number},
                     {"range", Type::number},
                     {"spot", Type::object, &kSpot}}};
const Schema kLightsPunctual{{{"lights", Type::object_array, &kLight}, {"light", Type::index}}};
const Schema kEmissiveStrength{{{"emissiveStrength", Type::number}}};
const std::map<std::string, const Schema*> kKnownExtensions{{"KHR_lights_punctual", &kLightsPunctual},
                                                            {"KHR_materials_emissive_strength", &kEmissiveStrength}};

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw std::runtime_error(path + ": " + problem);
}

bool is_index(const json& v) {
  // glTF indices and counts: non-negative integers that fit tinygltf's int.
  return (v.is_number_unsigned() || v.is_number_integer()) && v.get<int64_t>() >= 0 &&
         v.get<int64_t>() <= int64_t(0x7fffffff);
}

void check_object(const json& value, const Schema& schema, const std::string& path);

void check_value(const json& value, Type type, const Schema* schema, size_t length, const std::string& path) {
  switch (type) {
    case Type::index:
      if (!is_index(value)) fail(path, std::string("expected a non-negative integer, got ") + describe_json(value));
      break;
    case Type::number:
      if (!value.is_number()) fail(path, std::string("expected a number, got ") + describe_json(value));
      break;
    case Type::string:
      if (!value.is_string()) fail(path, std::string("expected a string, got ") + describe_json(value));
      break;
    case Type::boolean:
      if (!value.is_boolean()) fail(path, std::string("expected a boolean, got ") + describe_json(value));
      break;
    case Type::object:
      if (!value.is_object()) fail(path, std::string("expected an object, got ") + describe_json(value));
      check_object(value, *schema, path);
      break;
    case Type::object_array:
    case Type::number_array:
    case Type::index_array:
    case Type::string_array: {
      if (!value.is_array()) fail(path, std::string("expected an array, got ") + describe_json(value));
      if (length != 0 && value.size() != length)
        fail(path, "expected " + std::to_string(length) + " numbers, got " + std::to_string(value.size()));
      const Type element = type == Type::object_array   ? Type::object
                           : type == Type::number_array ? Type::number
                           : type == Type::index_array  ? Type::index
                                                        : Type::string;
      for (size_t i = 0; i < value.size(); ++i)
        check_value(value[i], element, schema, 0, path + "[" + std::to_string(i) + "]");
      break;
    }
  }
}

void check_extensions(const json& extensions, const std::string& path) {
  if (!extensions.is_object()) fail(path, std::string("expected an object, got ") + describe_json(extensions));
  for (const auto& [name, value] : extensions.items()) {
    const std::string item_path = path + "." + name;
    if (!value.is_object()) fail(item_path, std::string("expected an object, got ") + describe_json(value));
    if (auto known = kKnownExtensions.find(name); known != kKnownExtensions.end())
      check_object(value, *known->second, item_path);
  }
}

void check_object(const json& value, const Schema& schema, const std::string& path) {
  for (const auto& [key, item] : value.items()) {
    const std::string item_path = path.empty() ? key : path + "." + key;
    if (key == "extras") continue;  // free-form; the loader checks the parts it reads
    if (key == "extensions") {
      check_extensions(item, item_path);
      continue;
    }
    bool known = false;
    for (const Property& property : schema.properties) {
      if (key != property.name) continue;
      check_value(item, property.type, property.schema, property.length, item_path);
      known = true;
      break;
    }
    if (known) continue;
    if (key == "name" && &schema != &kIndexMap) {
      if (!item.is_string()) fail(item_path, std::string("expected a string, got ") + describe_json(item));
    } else if (schema.other_values) {
      check_value(item, *schema.other_values, nullptr, 0, item_path);
    }
  }
}

void check_depth(const json& document) {
  std::vector<std::pair<const json*, int>> stack{{&document, 1}};
  while (!stack.empty()) {
    auto [value, depth] = stack.back();
    stack.pop_back();
    if (depth > kMaxJsonDepth) fail("JSON", "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    if (value->is_structured())
      for (const json& child : *value) stack.emplace_back(&child, depth + 1);
  }
}

}  // namespace

const char* json_type_name(const json& value) {
  switch (value.type()) {
    case json::value_t::null: return "null";
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "a string";
    case json::value_t::boolean: return "a boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned: return "an integer";
    case json::value_t::number_float: return "a number";
    default: return "binary data";
  }
}

std::string describe_json(const json& value) {
  std::string text = json_type_name(value);
  if (!value.is_structured()) {
    std::string dumped = value.dump();
    if (dumped.size() <= 24) text += " (" + dumped + ")";
  }
  return text;
}

void check_json_types(const json& document) {
  check_depth(document);
  if (!document.is_object())
    fail("JSON", std::string("the document must be an object, got ") + describe_json(document));
  check_object(document, kRoot, "");
}

}  // namespace epi::gltf

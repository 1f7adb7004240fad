// JSON type check of a glTF document against the parts of the glTF 2.0 schema that matter:
// tinygltf silently falls back to defaults on wrongly typed properties, so we check first.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace epi::gltf {

inline constexpr int kMaxJsonDepth = 64;

// Throws std::runtime_error("<json path>: <problem>") for the first property whose JSON type
// is not what glTF 2.0 defines (including textures, skins and animations, which epi ignores),
// for extension values that are not objects, and for nesting deeper than kMaxJsonDepth.
void check_json_types(const nlohmann::json& document);

// A value's JSON type in words ("an array", "a string (\"x\")"), for messages.
const char* json_type_name(const nlohmann::json& value);
std::string describe_json(const nlohmann::json& value);

}  // namespace epi::gltf

#include "engine/scene/gltf_types.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <utility>
#include <vector>

namespace ivgi::scene {

namespace {

using nlohmann::json;

const char* kindOf(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number()) return "a number";
  return "null";
}

bool isInteger(const json& v) {
  if (v.is_number_integer() || v.is_number_unsigned()) return true;
  return v.is_number_float() && std::floor(v.get<double>()) == v.get<double>();
}

// The problem found, thrown out of the walk to gltfTypeProblem.
struct Problem {
  std::string text;
};

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw Problem{(path.empty() ? std::string("the file's root") : path) + " " + what};
}

// A value as the message quotes it: its JSON, cut short where long.
std::string shown(const json& v) {
  const std::string text = v.dump();
  return text.size() <= 40 ? text : text.substr(0, 40) + "...";
}

std::string at(const std::string& path, size_t i) { return path + "[" + std::to_string(i) + "]"; }
std::string dot(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

// A check of the value at a path; each names what the schema asks for where the value differs.
using Check = std::function<void(const json&, const std::string&)>;

void object(const json& v, const std::string& path) {
  if (!v.is_object()) fail(path, std::string("is ") + kindOf(v) + ", not an object");
}
void number(const json& v, const std::string& path) {
  if (!v.is_number()) fail(path, std::string("is ") + kindOf(v) + ", not a number");
}
void boolean(const json& v, const std::string& path) {
  if (!v.is_boolean()) fail(path, std::string("is ") + kindOf(v) + ", not a boolean");
}
void string(const json& v, const std::string& path) {
  if (!v.is_string()) fail(path, std::string("is ") + kindOf(v) + ", not a string");
}
// An index into one of the file's arrays (the schema's glTFid), or a count or an offset.
void index(const json& v, const std::string& path) {
  if (!isInteger(v) || v.get<double>() < 0.0)
    fail(path, "is " + shown(v) + ", not an index (an integer of at least 0)");
}
void primitiveMode(const json& v, const std::string& path) {
  if (!isInteger(v) || v.get<double>() < 0.0 || v.get<double>() > 6.0)
    fail(path, "is " + shown(v) + ", not a primitive mode (0 to 6)");
}

// A number of at least 0; one above 0.
void atLeastZero(const json& v, const std::string& path) {
  if (!v.is_number() || v.get<double>() < 0.0) fail(path, "is " + shown(v) + ", not a number of at least 0");
}
void aboveZero(const json& v, const std::string& path) {
  if (!v.is_number() || !(v.get<double>() > 0.0)) fail(path, "is " + shown(v) + ", not a number above 0");
}
// One of the values the schema lists for the property.
Check oneOf(std::vector<json> values) {
  return [values](const json& v, const std::string& path) {
    for (const json& allowed : values)
      if (v == allowed) return;
    std::string listed;
    for (const json& allowed : values) listed += (listed.empty() ? "" : ", ") + allowed.dump();
    fail(path, "is " + shown(v) + ", not one of " + listed);
  };
}

// `count` numbers (0: any number of them), each passing `each`.
Check numbersOf(size_t count, Check each = number) {
  return [count, each](const json& v, const std::string& path) {
    if (!v.is_array() || (count && v.size() != count))
      fail(path, count ? "is not an array of " + std::to_string(count) + " numbers" : "is not an array of numbers");
    for (size_t i = 0; i < v.size(); ++i) each(v[i], at(path, i));
  };
}
// An array whose every item passes `item` (`atLeast`: the fewest items it may hold).
Check arrayOf(Check item, size_t atLeast = 0) {
  return [item, atLeast](const json& v, const std::string& path) {
    if (!v.is_array()) fail(path, std::string("is ") + kindOf(v) + ", not an array");
    if (v.size() < atLeast) fail(path, "is empty");
    for (size_t i = 0; i < v.size(); ++i) item(v[i], at(path, i));
  };
}
// An object whose every value passes `value` (a primitive's attributes, a morph target).
Check mapOf(Check value) {
  return [value](const json& v, const std::string& path) {
    object(v, path);
    for (const auto& [key, item] : v.items()) value(item, dot(path, key));
  };
}

// A property of an object: its key, the check of its value, whether the schema requires it.
struct Field {
  std::string key;
  Check check;
  bool isRequired = false;
};
Field required(std::string key, Check check) { return {std::move(key), std::move(check), true}; }

// An object whose properties among `fields` pass their checks; the others are not looked at.
Check objectOf(std::vector<Field> fields) {
  return [fields](const json& v, const std::string& path) {
    object(v, path);
    for (const Field& f : fields)
      if (const auto it = v.find(f.key); it != v.end())
        f.check(*it, dot(path, f.key));
      else if (f.isRequired)
        fail(dot(path, f.key), "is missing");
  };
}
// An object's extensions: each an object, those ivgi reads (`known`) checked by their fields.
Field extensions(std::vector<Field> known = {}) {
  const Check each = objectOf(std::move(known));
  return {"extensions", [each](const json& v, const std::string& path) {
            each(v, path);
            for (const auto& [name, extension] : v.items()) object(extension, dot(path, name));
          }};
}

// The glTF 2.0 schema, as far as ivgi reads it.

Check textureInfo() {
  return objectOf({required("index", index),
                   {"texCoord", index},
                   {"scale", number},
                   {"strength", number},
                   extensions({{"KHR_texture_transform", objectOf({{"offset", numbersOf(2)},
                                                                   {"scale", numbersOf(2)},
                                                                   {"rotation", number},
                                                                   {"texCoord", index}})}})});
}

Check material() {
  const Check texture = textureInfo();
  return objectOf({{"pbrMetallicRoughness", objectOf({{"baseColorFactor", numbersOf(4)},
                                                      {"metallicFactor", number},
                                                      {"roughnessFactor", number},
                                                      {"baseColorTexture", texture},
                                                      {"metallicRoughnessTexture", texture},
                                                      extensions()})},
                   {"normalTexture", texture},
                   {"occlusionTexture", texture},
                   {"emissiveTexture", texture},
                   {"emissiveFactor", numbersOf(3)},
                   {"alphaMode", string},
                   {"alphaCutoff", number},
                   {"doubleSided", boolean},
                   extensions({{"KHR_materials_emissive_strength", objectOf({{"emissiveStrength", number}})},
                               {"KHR_materials_ior", objectOf({{"ior", number}})},
                               {"KHR_materials_specular", objectOf({{"specularFactor", number},
                                                                    {"specularColorFactor", numbersOf(3)},
                                                                    {"specularTexture", texture},
                                                                    {"specularColorTexture", texture}})}})});
}

Check mesh() {
  const Check primitive = objectOf({required("attributes", mapOf(index)),
                                    {"indices", index},
                                    {"material", index},
                                    {"mode", primitiveMode},
                                    {"targets", arrayOf(mapOf(index))},
                                    extensions()});
  return objectOf({required("primitives", arrayOf(primitive, 1)), {"weights", numbersOf(0)}});
}

Check node() {
  return objectOf({{"children", arrayOf(index)},
                   {"mesh", index},
                   {"camera", index},
                   {"skin", index},
                   {"matrix", numbersOf(16)},
                   {"translation", numbersOf(3)},
                   {"rotation", numbersOf(4)},
                   {"scale", numbersOf(3)},
                   {"weights", numbersOf(0)},
                   extensions({{"KHR_lights_punctual", objectOf({required("light", index)})}})});
}

Check accessor() {
  const Check sparseIndices =
      objectOf({required("bufferView", index), {"byteOffset", index}, required("componentType", index)});
  const Check sparseValues = objectOf({required("bufferView", index), {"byteOffset", index}});
  return objectOf({{"bufferView", index},
                   {"byteOffset", index},
                   required("componentType", index),
                   {"normalized", boolean},
                   required("count", index),
                   required("type", string),
                   {"sparse", objectOf({required("count", index), required("indices", sparseIndices),
                                        required("values", sparseValues)})}});
}

Check camera() {
  return objectOf(
      {{"type", string},
       {"perspective", objectOf({{"aspectRatio", number}, {"yfov", number}, {"zfar", number}, {"znear", number}})},
       {"orthographic", objectOf({{"xmag", number}, {"ymag", number}, {"zfar", number}, {"znear", number}})}});
}

Check animation() {
  const Check channel =
      objectOf({required("sampler", index), required("target", objectOf({{"node", index}, required("path", string)}))});
  const Check sampler = objectOf({required("input", index),
                                  required("output", index),
                                  {"interpolation", oneOf({"LINEAR", "STEP", "CUBICSPLINE"})}});
  return objectOf({{"channels", arrayOf(channel)}, {"samplers", arrayOf(sampler)}});
}

Check light() {
  return objectOf({required("type", oneOf({"directional", "point", "spot"})),
                   {"color", numbersOf(3, atLeastZero)},
                   {"intensity", atLeastZero},
                   {"range", aboveZero},
                   {"spot", objectOf({{"innerConeAngle", atLeastZero}, {"outerConeAngle", aboveZero}})}});
}

Check gltfSchema() {
  return objectOf(
      {{"scene", index},
       {"scenes", arrayOf(objectOf({{"nodes", arrayOf(index)}}))},
       {"nodes", arrayOf(node())},
       {"meshes", arrayOf(mesh())},
       {"materials", arrayOf(material())},
       {"accessors", arrayOf(accessor())},
       {"bufferViews", arrayOf(objectOf({required("buffer", index),
                                         {"byteOffset", index},
                                         required("byteLength", index),
                                         {"byteStride", index},
                                         {"target", index}}))},
       {"buffers", arrayOf(objectOf({required("byteLength", index), {"uri", string}}))},
       {"images", arrayOf(objectOf({{"uri", string}, {"mimeType", string}, {"bufferView", index}}))},
       {"textures", arrayOf(objectOf({{"sampler", index}, {"source", index}}))},
       {"samplers", arrayOf(objectOf({{"magFilter", oneOf({9728, 9729})},
                                      {"minFilter", oneOf({9728, 9729, 9984, 9985, 9986, 9987})},
                                      {"wrapS", oneOf({33071, 33648, 10497})},
                                      {"wrapT", oneOf({33071, 33648, 10497})}}))},
       {"skins",
        arrayOf(objectOf({required("joints", arrayOf(index)), {"inverseBindMatrices", index}, {"skeleton", index}}))},
       {"cameras", arrayOf(camera())},
       {"animations", arrayOf(animation())},
       extensions({{"KHR_lights_punctual", objectOf({{"lights", arrayOf(light())}})}})});
}

}  // namespace

std::optional<std::string> gltfTypeProblem(const json& gltf) {
  static const Check check = gltfSchema();
  try {
    check(gltf, "");
  } catch (const Problem& p) {
    return p.text;
  }
  return std::nullopt;
}

namespace {

// The little-endian 32-bit word of a .glb at byte `at` (its header's and chunks' fields).
uint32_t glbWord(std::span<const unsigned char> file, size_t at) {
  return uint32_t(file[at]) | uint32_t(file[at + 1]) << 8 | uint32_t(file[at + 2]) << 16 | uint32_t(file[at + 3]) << 24;
}

// "<major>.<minor>" (glTF 1.0's files also wrote "1.0.2") as a pair; none where it is not one.
std::optional<std::pair<int, int>> versionOf(const json& v) {
  if (!v.is_string()) return std::nullopt;
  const std::string& text = v.get_ref<const std::string&>();
  std::pair<int, int> version;
  const char* end = text.data() + text.size();
  auto [dot, e1] = std::from_chars(text.data(), end, version.first);
  if (e1 != std::errc() || dot == end || *dot != '.') return std::nullopt;
  if (std::from_chars(dot + 1, end, version.second).ec != std::errc()) return std::nullopt;
  return version;
}

}  // namespace

std::optional<std::string> gltfVersionProblem(std::span<const unsigned char> file, bool binary, const json& gltf) {
  if (binary && file.size() >= 8)
    if (const uint32_t version = glbWord(file, 4); version != 2)
      return "is binary glTF of version " + std::to_string(version) + " (its header)";
  if (!gltf.is_object()) return std::nullopt;
  const json none;
  const auto asset = gltf.find("asset");
  const json& version = asset != gltf.end() && asset->is_object() ? asset->value("version", none) : none;
  if (auto v = versionOf(version)) {
    if (v->first != 2)
      return "is glTF " + std::to_string(v->first) + "." + std::to_string(v->second) + " (asset.version " +
             shown(version) + ")";
    if (auto least = versionOf(asset->value("minVersion", none)); least && *least > std::pair(2, 0))
      return "needs glTF " + std::to_string(least->first) + "." + std::to_string(least->second) +
             " at least (asset.minVersion)";
    return std::nullopt;
  }
  // glTF 1.0's drafts wrote no asset.version or a number; their collections were objects keyed by name.
  for (const char* collection : {"accessors", "bufferViews", "buffers", "meshes", "nodes", "scenes"})
    if (auto c = gltf.find(collection); c != gltf.end() && c->is_object())
      return std::string("is glTF 1.0 (its ") + collection + " are named rather than listed)";
  return std::nullopt;
}

json gltfJson(std::span<const unsigned char> file, bool binary) {
  if (!binary) return json::parse(file.begin(), file.end(), nullptr, false);
  // A .glb: a 12-byte header, then the JSON chunk's length and type, then the chunk.
  constexpr size_t kChunk = 20;
  if (file.size() < kChunk || std::memcmp(file.data() + 16, "JSON", 4) != 0) return json(json::value_t::discarded);
  const uint32_t length = glbWord(file, 12);
  if (length > file.size() - kChunk) return json(json::value_t::discarded);
  const auto chunk = file.subspan(kChunk, length);
  return json::parse(chunk.begin(), chunk.end(), nullptr, false);
}

}  // namespace ivgi::scene

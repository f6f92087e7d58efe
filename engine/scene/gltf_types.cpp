#include "engine/scene/gltf_types.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

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

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw Problem{path + " " + what}; }

// A value as the message quotes it: its JSON, cut short where long.
std::string shown(const json& v) {
  const std::string text = v.dump();
  return text.size() <= 40 ? text : text.substr(0, 40) + "...";
}

std::string at(const std::string& path, size_t i) { return path + "[" + std::to_string(i) + "]"; }
std::string dot(const std::string& path, const char* key) { return path.empty() ? key : path + "." + key; }

// Each check names what the schema asks for where the value differs.
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
// An index into one of the file's arrays (the schema's glTFid), or a count.
void index(const json& v, const std::string& path) {
  if (!isInteger(v) || v.get<double>() < 0.0)
    fail(path, "is " + shown(v) + ", not an index (an integer of at least 0)");
}
// `count` numbers (0: any number of them).
void numbers(const json& v, const std::string& path, size_t count = 0) {
  if (!v.is_array() || (count && v.size() != count))
    fail(path, count ? "is not an array of " + std::to_string(count) + " numbers" : "is not an array of numbers");
  for (size_t i = 0; i < v.size(); ++i) number(v[i], at(path, i));
}
// The check of an array of `count` numbers, for optional() and required().
auto numbersOf(size_t count) {
  return [count](const json& v, const std::string& path) { numbers(v, path, count); };
}
// An object whose every value is an index (a primitive's attributes, a morph target).
void indexObject(const json& v, const std::string& path) {
  object(v, path);
  for (const auto& [name, value] : v.items()) index(value, path + "." + name);
}
void indices(const json& v, const std::string& path) {
  if (!v.is_array()) fail(path, std::string("is ") + kindOf(v) + ", not an array of indices");
  for (size_t i = 0; i < v.size(); ++i) index(v[i], at(path, i));
}

// The optional property `key` of object `o` through `check`.
template <typename Check>
void optional(const json& o, const char* key, const std::string& path, Check check) {
  if (auto it = o.find(key); it != o.end()) check(*it, dot(path, key));
}
template <typename Check>
void required(const json& o, const char* key, const std::string& path, Check check) {
  auto it = o.find(key);
  if (it == o.end()) fail(dot(path, key), "is missing");
  check(*it, dot(path, key));
}
// An array whose every item is an object checked by `item` (`atLeast`: the fewest items it may hold).
template <typename Item>
void objects(const json& v, const std::string& path, Item item, size_t atLeast = 0) {
  if (!v.is_array()) fail(path, std::string("is ") + kindOf(v) + ", not an array");
  if (v.size() < atLeast) fail(path, "is empty");
  for (size_t i = 0; i < v.size(); ++i) {
    object(v[i], at(path, i));
    item(v[i], at(path, i));
  }
}

// An object's extensions: an object of objects.
void extensions(const json& o, const std::string& path) {
  optional(o, "extensions", path, [](const json& e, const std::string& p) {
    object(e, p);
    for (const auto& [name, value] : e.items()) object(value, p + "." + name);
  });
}

void textureInfo(const json& v, const std::string& path) {
  object(v, path);
  required(v, "index", path, index);
  optional(v, "texCoord", path, index);
  optional(v, "scale", path, number);
  optional(v, "strength", path, number);
  extensions(v, path);
  if (auto e = v.find("extensions"); e != v.end())
    optional(*e, "KHR_texture_transform", dot(path, "extensions"), [](const json& t, const std::string& p) {
      optional(t, "offset", p, numbersOf(2));
      optional(t, "scale", p, numbersOf(2));
      optional(t, "rotation", p, number);
      optional(t, "texCoord", p, index);
    });
}

void material(const json& m, const std::string& path) {
  optional(m, "pbrMetallicRoughness", path, [](const json& pbr, const std::string& p) {
    object(pbr, p);
    optional(pbr, "baseColorFactor", p, numbersOf(4));
    optional(pbr, "metallicFactor", p, number);
    optional(pbr, "roughnessFactor", p, number);
    optional(pbr, "baseColorTexture", p, textureInfo);
    optional(pbr, "metallicRoughnessTexture", p, textureInfo);
    extensions(pbr, p);
  });
  for (const char* texture : {"normalTexture", "occlusionTexture", "emissiveTexture"})
    optional(m, texture, path, textureInfo);
  optional(m, "emissiveFactor", path, numbersOf(3));
  optional(m, "alphaMode", path, string);
  optional(m, "alphaCutoff", path, number);
  optional(m, "doubleSided", path, boolean);
  extensions(m, path);
  if (auto e = m.find("extensions"); e != m.end()) {
    const std::string p = dot(path, "extensions");
    optional(*e, "KHR_materials_emissive_strength", p,
             [](const json& x, const std::string& q) { optional(x, "emissiveStrength", q, number); });
    optional(*e, "KHR_materials_ior", p, [](const json& x, const std::string& q) { optional(x, "ior", q, number); });
    optional(*e, "KHR_materials_specular", p, [](const json& x, const std::string& q) {
      optional(x, "specularFactor", q, number);
      optional(x, "specularColorFactor", q, numbersOf(3));
      optional(x, "specularTexture", q, textureInfo);
      optional(x, "specularColorTexture", q, textureInfo);
    });
  }
}

void primitive(const json& p, const std::string& path) {
  required(p, "attributes", path, indexObject);
  optional(p, "indices", path, index);
  optional(p, "material", path, index);
  optional(p, "mode", path, [](const json& m, const std::string& q) {
    if (!isInteger(m) || m.get<double>() < 0.0 || m.get<double>() > 6.0)
      fail(q, "is " + shown(m) + ", not a primitive mode (0 to 6)");
  });
  optional(p, "targets", path, [](const json& t, const std::string& q) { objects(t, q, indexObject); });
  extensions(p, path);
}

void node(const json& n, const std::string& path) {
  optional(n, "children", path, indices);
  optional(n, "mesh", path, index);
  optional(n, "camera", path, index);
  optional(n, "skin", path, index);
  optional(n, "matrix", path, numbersOf(16));
  optional(n, "translation", path, numbersOf(3));
  optional(n, "rotation", path, numbersOf(4));
  optional(n, "scale", path, numbersOf(3));
  optional(n, "weights", path, numbersOf(0));
  extensions(n, path);
  if (auto e = n.find("extensions"); e != n.end())
    optional(*e, "KHR_lights_punctual", dot(path, "extensions"),
             [](const json& x, const std::string& q) { required(x, "light", q, index); });
}

void light(const json& l, const std::string& path) {
  required(l, "type", path, string);
  optional(l, "color", path, numbersOf(3));
  optional(l, "intensity", path, number);
  optional(l, "range", path, number);
  optional(l, "spot", path, [](const json& s, const std::string& q) {
    object(s, q);
    optional(s, "innerConeAngle", q, number);
    optional(s, "outerConeAngle", q, number);
  });
}

void camera(const json& c, const std::string& path) {
  optional(c, "type", path, string);
  optional(c, "perspective", path, [](const json& p, const std::string& q) {
    object(p, q);
    for (const char* key : {"aspectRatio", "yfov", "zfar", "znear"}) optional(p, key, q, number);
  });
  optional(c, "orthographic", path, [](const json& o, const std::string& q) {
    object(o, q);
    for (const char* key : {"xmag", "ymag", "zfar", "znear"}) optional(o, key, q, number);
  });
}

void animation(const json& a, const std::string& path) {
  optional(a, "channels", path, [](const json& c, const std::string& q) {
    objects(c, q, [](const json& channel, const std::string& r) {
      required(channel, "sampler", r, index);
      required(channel, "target", r, [](const json& t, const std::string& s) {
        object(t, s);
        optional(t, "node", s, index);
        required(t, "path", s, string);
      });
    });
  });
  optional(a, "samplers", path, [](const json& c, const std::string& q) {
    objects(c, q, [](const json& sampler, const std::string& r) {
      required(sampler, "input", r, index);
      required(sampler, "output", r, index);
      optional(sampler, "interpolation", r, string);
    });
  });
}

// Where an accessor's or a sparse part's data lies: its buffer view and the offset into it.
void placed(const json& v, const std::string& path) {
  optional(v, "bufferView", path, index);
  optional(v, "byteOffset", path, index);
}

void accessor(const json& a, const std::string& path) {
  placed(a, path);
  required(a, "componentType", path, index);
  optional(a, "normalized", path, boolean);
  required(a, "count", path, index);
  required(a, "type", path, string);
  optional(a, "sparse", path, [](const json& sparse, const std::string& p) {
    object(sparse, p);
    required(sparse, "count", p, index);
    required(sparse, "indices", p, [](const json& i, const std::string& q) {
      object(i, q);
      placed(i, q);
      required(i, "componentType", q, index);
    });
    required(sparse, "values", p, [](const json& v, const std::string& q) {
      object(v, q);
      placed(v, q);
    });
  });
}

void bufferView(const json& v, const std::string& path) {
  required(v, "buffer", path, index);
  for (const char* key : {"byteOffset", "byteStride", "target"}) optional(v, key, path, index);
  required(v, "byteLength", path, index);
}

void root(const json& g) {
  object(g, "the file's root");
  optional(g, "scene", "", index);
  optional(g, "scenes", "", [](const json& v, const std::string& p) {
    objects(v, p, [](const json& s, const std::string& q) { optional(s, "nodes", q, indices); });
  });
  optional(g, "nodes", "", [](const json& v, const std::string& p) { objects(v, p, node); });
  optional(g, "accessors", "", [](const json& v, const std::string& p) { objects(v, p, accessor); });
  optional(g, "bufferViews", "", [](const json& v, const std::string& p) { objects(v, p, bufferView); });
  optional(g, "buffers", "", [](const json& v, const std::string& p) {
    objects(v, p, [](const json& b, const std::string& q) {
      required(b, "byteLength", q, index);
      optional(b, "uri", q, string);
    });
  });
  optional(g, "images", "", [](const json& v, const std::string& p) {
    objects(v, p, [](const json& i, const std::string& q) {
      optional(i, "uri", q, string);
      optional(i, "mimeType", q, string);
      optional(i, "bufferView", q, index);
    });
  });
  optional(g, "meshes", "", [](const json& v, const std::string& p) {
    objects(v, p, [](const json& m, const std::string& q) {
      required(m, "primitives", q, [](const json& list, const std::string& r) { objects(list, r, primitive, 1); });
      optional(m, "weights", q, numbersOf(0));
    });
  });
  optional(g, "materials", "", [](const json& v, const std::string& p) { objects(v, p, material); });
  optional(g, "textures", "", [](const json& v, const std::string& p) {
    objects(v, p, [](const json& t, const std::string& q) {
      optional(t, "sampler", q, index);
      optional(t, "source", q, index);
    });
  });
  optional(g, "samplers", "", [](const json& v, const std::string& p) {
    objects(v, p, [](const json& s, const std::string& q) {
      for (const char* key : {"magFilter", "minFilter", "wrapS", "wrapT"}) optional(s, key, q, index);
    });
  });
  optional(g, "skins", "", [](const json& v, const std::string& p) {
    objects(v, p, [](const json& s, const std::string& q) {
      required(s, "joints", q, indices);
      optional(s, "inverseBindMatrices", q, index);
      optional(s, "skeleton", q, index);
    });
  });
  optional(g, "cameras", "", [](const json& v, const std::string& p) { objects(v, p, camera); });
  optional(g, "animations", "", [](const json& v, const std::string& p) { objects(v, p, animation); });
  extensions(g, "");
  if (auto e = g.find("extensions"); e != g.end())
    optional(*e, "KHR_lights_punctual", "extensions", [](const json& x, const std::string& q) {
      optional(x, "lights", q, [](const json& list, const std::string& r) { objects(list, r, light); });
    });
}

}  // namespace

std::optional<std::string> gltfTypeProblem(const json& gltf) {
  try {
    root(gltf);
  } catch (const Problem& p) {
    return p.text;
  }
  return std::nullopt;
}

json gltfJson(const std::string& path, bool binary) {
  std::ifstream in(path, std::ios::binary);
  std::string text;
  if (!binary) {
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } else {
    // A .glb: a 12-byte header, then the JSON chunk's length and type, then the chunk.
    unsigned char head[20] = {};
    in.read(reinterpret_cast<char*>(head), sizeof head);
    if (in.gcount() != sizeof head || std::memcmp(head + 16, "JSON", 4) != 0) return json();
    const uint32_t length =
        uint32_t(head[12]) | uint32_t(head[13]) << 8 | uint32_t(head[14]) << 16 | uint32_t(head[15]) << 24;
    text.resize(length);
    in.read(text.data(), std::streamsize(length));
    if (in.gcount() != std::streamsize(length)) return json();
  }
  return json::parse(text, nullptr, false);
}

}  // namespace ivgi::scene

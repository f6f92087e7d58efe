#include "engine/scene/gltf.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/type_ptr.hpp>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <vector>

#include "engine/image/image_header.h"
#include "engine/scene/gltf_accessors.h"
#include "engine/scene/gltf_types.h"

namespace ivgi::scene {

namespace {

const std::set<std::string> kSupportedExtensions = {"KHR_lights_punctual",   "KHR_materials_emissive_strength",
                                                    "KHR_materials_ior",     "KHR_materials_specular",
                                                    "KHR_mesh_quantization", "KHR_texture_transform"};

// The first extension the model requires that ivgi does not read, or none.
std::optional<std::string> unsupportedRequirement(const tinygltf::Model& m) {
  for (const auto& e : m.extensionsRequired)
    if (!kSupportedExtensions.count(e)) return e;
  return std::nullopt;
}

template <class V, int N>
std::vector<V> toVectors(const std::vector<float>& flat) {
  std::vector<V> out(flat.size() / N);
  for (size_t i = 0; i < out.size(); ++i)
    for (int c = 0; c < N; ++c) out[i][c] = flat[i * N + c];
  return out;
}

const tinygltf::Value* extensionValue(const tinygltf::ExtensionMap& ext, const std::string& name,
                                      const std::string& key) {
  auto it = ext.find(name);
  if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return nullptr;
  return &it->second.Get(key);
}

class Converter {
 public:
  Converter(const tinygltf::Model& m, const std::string& source, const Limits& limits)
      : m_(m), read_(m, source), source_(source), limits_(limits) {
    scene_.source = source;
  }

  Scene convert() {
    if (auto e = unsupportedRequirement(m_)) read_.fail("requires the unsupported extension " + *e);
    for (const auto& e : m_.extensionsUsed)
      if (!kSupportedExtensions.count(e)) warn("extension " + e + " is not supported and is ignored");
    textures();
    materials();
    meshes();
    cameras();
    lights();
    nodes();
    skins();
    animations();
    return std::move(scene_);
  }

 private:
  void warn(const std::string& w) { scene_.warnings.push_back(w); }

  void textures() {
    for (size_t i = 0; i < m_.textures.size(); ++i) {
      const auto& t = m_.textures[i];
      Texture out;
      out.name = t.name;
      if (t.sampler >= 0 && size_t(t.sampler) < m_.samplers.size()) {
        out.wrapS = m_.samplers[t.sampler].wrapS;
        out.wrapT = m_.samplers[t.sampler].wrapT;
        out.nearest = m_.samplers[t.sampler].magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
      }
      if (t.source < 0 || size_t(t.source) >= m_.images.size() || m_.images[t.source].image.empty()) {
        warn("texture " + std::to_string(i) + " has no decodable image; its factor alone is used");
      } else {
        const auto& img = m_.images[t.source];
        out.width = img.width, out.height = img.height;
        out.rgba.resize(size_t(img.width) * img.height * 4);
        int bytes = img.bits / 8, comps = img.component;
        if ((bytes != 1 && bytes != 2) || comps < 1 || comps > 4 ||
            img.image.size() < size_t(img.width) * img.height * comps * bytes)
          read_.fail("image " + std::to_string(t.source) + " has an unsupported pixel layout");
        for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
          for (int c = 0; c < 4; ++c) {
            int src = comps >= 3 ? c : (c < 3 ? 0 : 1);  // grey(+alpha) to RGBA
            uint8_t v = 255;
            if (src < comps)
              v = img.image[(p * comps + src) * bytes + (bytes - 1)];  // 16-bit: high byte (little endian)
            out.rgba[p * 4 + c] = v;
          }
      }
      scene_.textures.push_back(std::move(out));
    }
  }

  // The texture `index` names (-1: none), read on coordinate set `texCoord`, which `transform` keeps.
  int textureIndex(int index, int texCoord, TextureTransform& transform, const std::string& what) {
    if (index < 0) return -1;
    if (size_t(index) >= scene_.textures.size())
      read_.fail(what + ": texture index " + std::to_string(index) + " out of range");
    transform.texCoord = texCoord == 1 ? 1 : 0;
    if (texCoord > 1) warn(what + " uses TEXCOORD_" + std::to_string(texCoord) + "; TEXCOORD_0 is used instead");
    return scene_.textures[index].rgba.empty() ? -1 : index;
  }

  // A texture reference: its index (-1: none), its coordinate set and its KHR_texture_transform,
  // whose texCoord overrides the reference's own.
  int textureReference(const tinygltf::TextureInfo& info, TextureTransform& transform, const std::string& what) {
    int texCoord = info.texCoord;
    const auto it = info.extensions.find("KHR_texture_transform");
    if (info.index >= 0 && it != info.extensions.end()) {
      const tinygltf::Value& ext = it->second;
      const std::string where = what + ": KHR_texture_transform ";
      auto number = [&](const tinygltf::Value& x, const char* key) {
        if (!x.IsNumber() || !std::isfinite(x.GetNumberAsDouble()) || std::abs(x.GetNumberAsDouble()) > 3.4e38)
          read_.fail(where + key + " is not a finite number");
        return float(x.GetNumberAsDouble());
      };
      auto pair = [&](const char* key, glm::vec2 otherwise) {
        if (!ext.Has(key)) return otherwise;
        const tinygltf::Value& v = ext.Get(key);
        if (!v.IsArray() || v.ArrayLen() != 2) read_.fail(where + key + " is not a pair of numbers");
        return glm::vec2(number(v.Get(0), key), number(v.Get(1), key));
      };
      transform.offset = pair("offset", glm::vec2(0.0f));
      transform.scale = pair("scale", glm::vec2(1.0f));
      if (ext.Has("rotation")) transform.rotation = number(ext.Get("rotation"), "rotation");
      if (ext.Has("texCoord")) texCoord = int(std::clamp(number(ext.Get("texCoord"), "texCoord"), 0.0f, 255.0f));
    }
    return textureIndex(info.index, texCoord, transform, what);
  }

  void materials() {
    for (const auto& m : m_.materials) {
      Material out;
      out.name = m.name;
      const auto& pbr = m.pbrMetallicRoughness;
      for (int c = 0; c < 4 && c < int(pbr.baseColorFactor.size()); ++c)
        out.baseColor[c] = float(pbr.baseColorFactor[c]);
      for (int c = 0; c < 3 && c < int(m.emissiveFactor.size()); ++c) out.emissive[c] = float(m.emissiveFactor[c]);
      out.baseColorTexture =
          textureReference(pbr.baseColorTexture, out.baseColorTransform, "material '" + m.name + "' base colour");
      out.emissiveTexture =
          textureReference(m.emissiveTexture, out.emissiveTransform, "material '" + m.name + "' emission");
      out.metallicRoughnessTexture = textureReference(pbr.metallicRoughnessTexture, out.metallicRoughnessTransform,
                                                      "material '" + m.name + "' metallic-roughness");
      out.metallic = unitFactor(pbr.metallicFactor, m.name, "metallicFactor");
      out.roughness = unitFactor(pbr.roughnessFactor, m.name, "roughnessFactor");
      specular(m, out);
      out.doubleSided = m.doubleSided;
      alphaMode(m, out);
      normalTexture(m, out);
      if (auto* v = extensionValue(m.extensions, "KHR_materials_emissive_strength", "emissiveStrength"))
        out.emissiveStrength = float(v->GetNumberAsDouble());
      auto finite = [](glm::vec4 v) { return glm::all(glm::lessThan(glm::abs(v), glm::vec4(3.4e38f))); };
      if (!finite(out.baseColor) || !finite(glm::vec4(out.emissive, out.emissiveStrength)) || out.emissiveStrength < 0)
        read_.fail("material '" + m.name + "' has a non-finite or negative factor");
      scene_.materials.push_back(out);
    }
  }

  // MASK cuts the surface where its alpha is below the cutoff; BLEND keeps alpha of it (gpu::presenceOf).
  void alphaMode(const tinygltf::Material& m, Material& out) {
    if (m.alphaMode == "MASK") {
      if (!std::isfinite(m.alphaCutoff) || m.alphaCutoff < 0.0)
        read_.fail("material '" + m.name + "': alphaCutoff " + std::to_string(m.alphaCutoff) +
                   " is not a finite number of 0 or more");
      out.alphaCutoff = float(std::min(m.alphaCutoff, 2.0));  // past 1 every point is cut: 2 says so
    } else if (m.alphaMode == "BLEND") {
      out.alphaCutoff = gpu::kAlphaBlended;
    } else if (m.alphaMode != "OPAQUE") {
      read_.fail("material '" + m.name + "': alphaMode '" + m.alphaMode + "' is not OPAQUE, MASK or BLEND");
    }
  }

  // The material's normal texture, read with its own coordinate set and transform.
  void normalTexture(const tinygltf::Material& m, Material& out) {
    const tinygltf::NormalTextureInfo& info = m.normalTexture;
    if (info.index < 0) return;
    if (!std::isfinite(info.scale) || std::abs(info.scale) > 3.4e38)
      read_.fail("material '" + m.name + "': normalTexture scale is not a finite number");
    // textureReference() reads a TextureInfo; a NormalTextureInfo adds the scale to the same fields.
    tinygltf::TextureInfo reference;
    reference.index = info.index, reference.texCoord = info.texCoord, reference.extensions = info.extensions;
    out.normalTexture = textureReference(reference, out.normalTransform, "material '" + m.name + "' normal");
    out.normalScale = float(info.scale);
  }

  // A factor the specification bounds to [0, 1]: one outside is clamped into it, with a warning.
  float unitFactor(double value, const std::string& material, const std::string& key) {
    if (!std::isfinite(value)) read_.fail("material '" + material + "': " + key + " is not a finite number");
    if (value < 0.0 || value > 1.0)
      warn("material '" + material + "': " + key + " " + std::to_string(value) + " is clamped to [0, 1]");
    return float(std::clamp(value, 0.0, 1.0));
  }

  // KHR_materials_specular's factor and colour and KHR_materials_ior's index, folded into the
  // dielectric's reflectance at normal incidence and at grazing (Material::specular).
  void specular(const tinygltf::Material& m, Material& out) {
    const std::string what = "material '" + m.name + "'";
    auto number = [&](const tinygltf::Value& v, const std::string& key) {
      if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
        read_.fail(what + ": " + key + " is not a finite number");
      return v.GetNumberAsDouble();
    };
    if (auto* v = extensionValue(m.extensions, "KHR_materials_ior", "ior")) {
      const double ior = number(*v, "KHR_materials_ior ior");
      if (ior != 0.0 && ior < 1.0) read_.fail(what + ": KHR_materials_ior ior " + std::to_string(ior) + " is below 1");
      out.ior = float(ior);
    }
    if (auto* v = extensionValue(m.extensions, "KHR_materials_specular", "specularFactor"))
      out.specular = unitFactor(number(*v, "specularFactor"), m.name, "specularFactor");
    if (auto* v = extensionValue(m.extensions, "KHR_materials_specular", "specularColorFactor")) {
      if (!v->IsArray() || v->ArrayLen() != 3) read_.fail(what + ": specularColorFactor is not three numbers");
      for (int c = 0; c < 3; ++c) {
        const double x = number(v->Get(c), "specularColorFactor");
        if (x < 0.0) read_.fail(what + ": specularColorFactor is negative");
        out.specularColor[c] = float(std::min(x, 3.4e38));
      }
    }
    for (const char* texture : {"specularTexture", "specularColorTexture"})
      if (extensionValue(m.extensions, "KHR_materials_specular", texture))
        warn(what + ": KHR_materials_specular " + texture + " is not supported; its factor alone is used");
  }

  // Refuses an attribute of `what` that has `count` elements where POSITION has n.
  void perVertex(const std::string& what, const std::string& name, size_t count, size_t n) {
    if (count != n)
      read_.fail(what + " " + name + " has " + std::to_string(count) + " elements, POSITION has " + std::to_string(n));
  }

  // The joints and weights of a skinned primitive's n vertices: JOINTS_0/WEIGHTS_0, and where an
  // exporter wrote more than four influences a vertex (JOINTS_1/WEIGHTS_1), the four heaviest of the
  // eight (the skinning pass takes four), with a warning where a weight left out was not zero. The
  // weights are normalised: the spec asks for it, and exporters are not always exact.
  void skinInfluences(const tinygltf::Primitive& p, const std::string& what, size_t n, Primitive& out) {
    std::vector<glm::uvec4> joints[2];
    std::vector<glm::vec4> weights[2];
    for (int set = 0; set < 2; ++set) {
      const std::string j = "JOINTS_" + std::to_string(set), w = "WEIGHTS_" + std::to_string(set);
      const auto ja = p.attributes.find(j), wa = p.attributes.find(w);
      if ((ja == p.attributes.end()) != (wa == p.attributes.end()))
        read_.fail(what + " has " + j + " without " + w + " or the reverse");
      if (ja == p.attributes.end() || (set == 1 && joints[0].empty())) continue;
      const auto ids = read_.uints(ja->second, 4, what + " " + j);
      for (size_t i = 0; i + 3 < ids.size(); i += 4)
        joints[set].push_back({ids[i], ids[i + 1], ids[i + 2], ids[i + 3]});
      weights[set] = toVectors<glm::vec4, 4>(read_.floats(wa->second, 4, what + " " + w));
      perVertex(what, j, joints[set].size(), n);
      perVertex(what, w, weights[set].size(), n);
    }
    if (joints[0].empty()) return;
    bool dropped = false;
    if (!joints[1].empty())
      for (size_t v = 0; v < n; ++v) {
        std::array<std::pair<float, uint32_t>, 8> all;
        for (int k = 0; k < 8; ++k) all[k] = {weights[k / 4][v][k % 4], joints[k / 4][v][k % 4]};
        // Heaviest first; of equal weights the earlier influence, so that the choice is the file's order.
        std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        for (int k = 0; k < 4; ++k) joints[0][v][k] = all[k].second, weights[0][v][k] = all[k].first;
        dropped = dropped || all[4].first > 0.0f;
      }
    if (dropped) warn(what + " has more than four joint influences a vertex; the four heaviest are kept");
    out.joints = std::move(joints[0]);
    out.weights = std::move(weights[0]);
    for (auto& w : out.weights) {
      float sum = w.x + w.y + w.z + w.w;
      if (sum > 0) w /= sum;
    }
  }

  // COLOR_0: RGB or RGBA, floats or normalized unsigned bytes or shorts (the glTF spec's choices).
  // A colour outside [0, 1] is clamped into it, as the spec's range says, with a warning.
  std::vector<glm::vec4> vertexColors(int accessor, const std::string& what) {
    read_.count(accessor, what);  // the index is checked
    const tinygltf::Accessor& a = m_.accessors[size_t(accessor)];
    const bool normalizedInteger = a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                    a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalizedInteger)
      read_.fail(what + " must be floats or normalized unsigned bytes or shorts");
    const int components = a.type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
    const std::vector<float> flat = read_.floats(accessor, components, what);
    std::vector<glm::vec4> colors(flat.size() / size_t(components), glm::vec4(1.0f));
    bool clamped = false;
    for (size_t i = 0; i < colors.size(); ++i)
      for (int c = 0; c < components; ++c) {
        const float v = flat[i * size_t(components) + size_t(c)];
        colors[i][c] = std::clamp(v, 0.0f, 1.0f);
        clamped = clamped || colors[i][c] != v;
      }
    if (clamped) warn(what + " holds values outside [0, 1]; they are clamped");
    return colors;
  }

  Primitive primitive(const tinygltf::Primitive& p, const std::string& what) {
    Primitive out;
    auto attr = [&](const char* name) {
      auto it = p.attributes.find(name);
      return it == p.attributes.end() ? -1 : it->second;
    };
    int pos = attr("POSITION");
    if (pos < 0) read_.fail(what + " has no POSITION attribute");
    out.positions = toVectors<glm::vec3, 3>(read_.floats(pos, 3, what + " POSITION"));
    size_t n = out.positions.size();
    auto sized = [&](size_t count, const std::string& name) { perVertex(what, name, count, n); };
    if (int a = attr("NORMAL"); a >= 0) {
      out.normals = toVectors<glm::vec3, 3>(read_.floats(a, 3, what + " NORMAL"));
      sized(out.normals.size(), "NORMAL");
    }
    for (auto [name, uvs] : {std::pair{"TEXCOORD_0", &out.uvs}, std::pair{"TEXCOORD_1", &out.uvs1}})
      if (int a = attr(name); a >= 0) {
        *uvs = toVectors<glm::vec2, 2>(read_.floats(a, 2, what + " " + name));
        sized(uvs->size(), name);
      }
    if (int a = attr("COLOR_0"); a >= 0) {
      out.colors = vertexColors(a, what + " COLOR_0");
      sized(out.colors.size(), "COLOR_0");
    }
    skinInfluences(p, what, n, out);
    // Targets may share one accessor: a small file can declare targets × vertices past any memory.
    morphDeltas_ += uint64_t(p.targets.size()) * n;
    if (morphDeltas_ > limits_.morphDeltas)
      read_.fail(what + ": the file's morph targets reach " + std::to_string(morphDeltas_) +
                 " deltas (targets × vertices), more than " + std::to_string(limits_.morphDeltas) +
                 " (--max-morph-deltas raises the limit)");
    for (size_t t = 0; t < p.targets.size(); ++t) {
      MorphTarget target;
      std::string tw = what + " morph target " + std::to_string(t);
      for (const auto& [name, index] : p.targets[t]) {
        if (name == "POSITION") target.positions = toVectors<glm::vec3, 3>(read_.floats(index, 3, tw + " POSITION"));
        if (name == "NORMAL") target.normals = toVectors<glm::vec3, 3>(read_.floats(index, 3, tw + " NORMAL"));
      }
      if (!target.positions.empty()) sized(target.positions.size(), "morph POSITION");
      if (!target.normals.empty()) sized(target.normals.size(), "morph NORMAL");
      out.targets.push_back(std::move(target));
    }
    std::vector<uint32_t> order;
    if (p.indices >= 0) {
      order = read_.uints(p.indices, 1, what + " indices");
      for (uint32_t i : order)
        if (i >= n)
          read_.fail(what + ": index " + std::to_string(i) + " out of range (" + std::to_string(n) + " vertices)");
    } else {
      order.resize(n);
      for (uint32_t i = 0; i < n; ++i) order[i] = i;
    }
    if (p.mode == TINYGLTF_MODE_TRIANGLES) {
      order.resize(order.size() / 3 * 3);
      out.indices = std::move(order);
    } else if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t i = 2; i < order.size(); ++i)
        if (i % 2 == 0)
          out.indices.insert(out.indices.end(), {order[i - 2], order[i - 1], order[i]});
        else
          out.indices.insert(out.indices.end(), {order[i - 1], order[i - 2], order[i]});
    } else if (p.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
      for (size_t i = 2; i < order.size(); ++i)
        out.indices.insert(out.indices.end(), {order[0], order[i - 1], order[i]});
    }
    if (p.material >= int(scene_.materials.size()))
      read_.fail(what + ": material index " + std::to_string(p.material) + " out of range");
    out.material = p.material;
    if (p.material >= 0 && out.uvs1.empty()) {
      const Material& m = scene_.materials[size_t(p.material)];
      for (const TextureTransform* t :
           {&m.baseColorTransform, &m.emissiveTransform, &m.metallicRoughnessTransform, &m.normalTransform})
        if (t->texCoord == 1) {
          warn(what + " has no TEXCOORD_1, which its material '" + m.name + "' reads; it reads (0, 0)");
          break;
        }
    }
    if (p.material >= 0 && scene_.materials[size_t(p.material)].normalTexture >= 0 && p.attributes.count("TANGENT") &&
        !tangentsWarned_) {
      warn(what + " has TANGENT: every normal texture is read in its triangles' own tangent frames instead");
      tangentsWarned_ = true;
    }
    return out;
  }

  void meshes() {
    for (size_t mi = 0; mi < m_.meshes.size(); ++mi) {
      const auto& m = m_.meshes[mi];
      Mesh out;
      out.name = m.name.empty() ? "mesh " + std::to_string(mi) : m.name;
      for (double w : m.weights) out.weights.push_back(float(w));
      for (size_t pi = 0; pi < m.primitives.size(); ++pi) {
        const auto& p = m.primitives[pi];
        std::string what = "mesh '" + out.name + "' primitive " + std::to_string(pi);
        if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            p.mode != TINYGLTF_MODE_TRIANGLE_FAN && p.mode != -1) {
          warn(what + " draws points or lines and is skipped");
          continue;
        }
        out.primitives.push_back(primitive(p, what));
        if (!out.weights.empty() && out.weights.size() != out.primitives.back().targets.size())
          read_.fail(what + ": mesh weights and morph targets differ in number");
      }
      scene_.meshes.push_back(std::move(out));
    }
  }

  void cameras() {
    for (const auto& c : m_.cameras) {
      Camera out;
      out.name = c.name;
      if (c.type == "perspective") {
        out.yfov = float(c.perspective.yfov);
        out.znear = float(c.perspective.znear);
        out.zfar = float(c.perspective.zfar);
        out.aspectRatio = float(c.perspective.aspectRatio);
        if (!(out.yfov > 0 && out.yfov < 3.14159f) || !(out.znear > 0) || !std::isfinite(out.zfar))
          read_.fail("camera '" + c.name + "' has an invalid field of view or clip range");
      } else {
        // The spec requires zfar > znear ≥ 0 here; ymag's sign only mirrors the view, its size matters.
        out.orthographic = true;
        out.ymag = float(std::abs(c.orthographic.ymag));
        out.znear = float(c.orthographic.znear);
        out.zfar = float(c.orthographic.zfar);
        if (!(out.ymag > 0 && out.ymag < 3.4e38f) || !(out.znear >= 0) || !(out.zfar > out.znear) ||
            !std::isfinite(out.zfar))
          read_.fail("camera '" + c.name + "' has an invalid orthographic extent or clip range");
      }
      scene_.cameras.push_back(out);
    }
  }

  void lights() {
    for (size_t i = 0; i < m_.lights.size(); ++i) {
      const auto& l = m_.lights[i];
      Light out;
      out.name = l.name;
      const std::string what = l.name.empty() ? "light " + std::to_string(i) : "light '" + l.name + "'";
      if (l.type == "spot" &&
          !(l.spot.innerConeAngle < l.spot.outerConeAngle && l.spot.outerConeAngle <= gpu::kPi / 2 + 1e-6))
        read_.fail(what + ": its cone's angles (inner " + std::to_string(l.spot.innerConeAngle) + ", outer " +
                   std::to_string(l.spot.outerConeAngle) + ") are not 0 <= inner < outer <= pi/2");
      out.type = l.type == "directional" ? Light::Type::Directional
                 : l.type == "spot"      ? Light::Type::Spot
                                         : Light::Type::Point;
      for (int c = 0; c < 3 && c < int(l.color.size()); ++c) out.color[c] = float(l.color[c]);
      out.intensity = float(l.intensity);
      out.range = float(l.range);
      out.innerCone = float(l.spot.innerConeAngle);
      out.outerCone = float(l.spot.outerConeAngle);
      scene_.lights.push_back(out);
    }
  }

  void nodes() {
    scene_.nodes.resize(m_.nodes.size());
    for (size_t i = 0; i < m_.nodes.size(); ++i) {
      const auto& n = m_.nodes[i];
      Node& out = scene_.nodes[i];
      out.name = n.name.empty() ? "node " + std::to_string(i) : n.name;
      if (n.matrix.size() == 16) {
        glm::mat4 m;
        for (int k = 0; k < 16; ++k) glm::value_ptr(m)[k] = float(n.matrix[k]);
        out.matrix = m;
      }
      if (n.translation.size() == 3) out.translation = {n.translation[0], n.translation[1], n.translation[2]};
      if (n.rotation.size() == 4) {
        // glTF asks for a unit quaternion. Taken as it is, one off by its exporter's rounding would
        // shear the node: it is taken at unit length (with a warning where it is off by more than
        // rounding); one of no length names no rotation and is refused.
        const glm::dvec4 q(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]);
        const double length = glm::length(q);
        if (!(length > 1e-3 && length < 1e3))
          read_.fail("node '" + out.name + "': rotation of length " + std::to_string(length) +
                     " is not a unit quaternion");
        if (std::abs(length - 1.0) > 1e-3)
          warn("node '" + out.name + "': rotation of length " + std::to_string(length) + " taken at unit length");
        const double scale = std::abs(length - 1.0) > 1e-6 ? 1.0 / length : 1.0;  // a unit one keeps its bits
        out.rotation = glm::quat(float(q.w * scale), float(q.x * scale), float(q.y * scale), float(q.z * scale));
      }
      if (n.scale.size() == 3) out.scale = {n.scale[0], n.scale[1], n.scale[2]};
      for (double w : n.weights) out.weights.push_back(float(w));
      auto checkIndex = [&](int v, size_t size, const char* kind) {
        if (v >= int(size))
          read_.fail("node '" + out.name + "': " + kind + " index " + std::to_string(v) + " out of range");
        return v;
      };
      out.mesh = checkIndex(n.mesh, scene_.meshes.size(), "mesh");
      out.skin = checkIndex(n.skin, m_.skins.size(), "skin");
      out.camera = checkIndex(n.camera, scene_.cameras.size(), "camera");
      if (auto* v = extensionValue(n.extensions, "KHR_lights_punctual", "light"))
        out.light = checkIndex(v->GetNumberAsInt(), scene_.lights.size(), "light");
      for (int c : n.children) {
        checkIndex(c, m_.nodes.size(), "child");
        if (c < 0 || scene_.nodes[c].parent >= 0 || c == int(i))
          read_.fail("node hierarchy is not a tree (node " + std::to_string(c) + ")");
        scene_.nodes[c].parent = int(i);
        out.children.push_back(c);
      }
    }
    // Cycles: every node must reach a root by parent links.
    for (size_t i = 0; i < scene_.nodes.size(); ++i) {
      size_t steps = 0;
      for (int p = int(i); p >= 0; p = scene_.nodes[p].parent)
        if (++steps > scene_.nodes.size()) read_.fail("node hierarchy has a cycle");
    }
    if (m_.defaultScene >= int(m_.scenes.size()))
      read_.fail("scene " + std::to_string(m_.defaultScene) + " is out of range (the file has " +
                 std::to_string(m_.scenes.size()) + " scenes)");
    if (!m_.scenes.empty()) {
      int s = m_.defaultScene >= 0 ? m_.defaultScene : 0;
      for (int r : m_.scenes[s].nodes) {
        if (r < 0 || r >= int(scene_.nodes.size()))
          read_.fail("scene node index " + std::to_string(r) + " out of range");
        if (scene_.nodes[r].parent >= 0) read_.fail("scene root node " + std::to_string(r) + " has a parent");
        scene_.roots.push_back(r);
      }
    } else {
      for (size_t i = 0; i < scene_.nodes.size(); ++i)
        if (scene_.nodes[i].parent < 0) scene_.roots.push_back(int(i));
    }
  }

  void skins() {
    for (size_t i = 0; i < m_.skins.size(); ++i) {
      const auto& s = m_.skins[i];
      Skin out;
      out.name = s.name;
      std::string what = "skin " + std::to_string(i);
      for (int j : s.joints) {
        if (j < 0 || j >= int(scene_.nodes.size()))
          read_.fail(what + ": joint node " + std::to_string(j) + " out of range");
        out.joints.push_back(j);
      }
      if (s.inverseBindMatrices >= 0) {
        auto f = read_.floats(s.inverseBindMatrices, 16, what + " inverseBindMatrices");
        if (f.size() / 16 < out.joints.size()) read_.fail(what + ": fewer inverse bind matrices than joints");
        for (size_t j = 0; j < out.joints.size(); ++j) {
          glm::mat4 m;
          std::memcpy(glm::value_ptr(m), &f[16 * j], 64);
          out.inverseBind.push_back(m);
        }
      } else {
        out.inverseBind.assign(out.joints.size(), glm::mat4(1.0f));
      }
      scene_.skins.push_back(std::move(out));
    }
    for (const auto& node : scene_.nodes) {
      if (node.mesh < 0) continue;
      for (const auto& p : scene_.meshes[node.mesh].primitives) {
        if (p.joints.empty()) continue;
        if (node.skin < 0) {
          warn("node '" + node.name + "' has skinning attributes but no skin; drawn unskinned");
          continue;
        }
        for (auto j : p.joints)
          if (glm::any(glm::greaterThanEqual(j, glm::uvec4(uint32_t(scene_.skins[node.skin].joints.size())))))
            read_.fail("node '" + node.name + "': a JOINTS_0 value exceeds the skin's joint count");
      }
    }
  }

  void animations() {
    for (size_t ai = 0; ai < m_.animations.size(); ++ai) {
      const auto& a = m_.animations[ai];
      Animation out;
      out.name = a.name.empty() ? "animation " + std::to_string(ai) : a.name;
      std::string what = "animation '" + out.name + "'";
      out.start = 1e30f, out.end = -1e30f;
      for (const auto& s : a.samplers) {
        Sampler smp;
        smp.input = read_.floats(s.input, 1, what + " sampler input");
        if (smp.input.empty()) read_.fail(what + ": a sampler has no keys");
        for (size_t k = 1; k < smp.input.size(); ++k)
          if (!(smp.input[k] > smp.input[k - 1])) read_.fail(what + ": key times are not strictly increasing");
        smp.interpolation = s.interpolation == "STEP"          ? Interpolation::Step
                            : s.interpolation == "CUBICSPLINE" ? Interpolation::CubicSpline
                                                               : Interpolation::Linear;
        if (s.output < 0 || size_t(s.output) >= m_.accessors.size())
          read_.fail(what + ": sampler output accessor out of range");
        int comps = tinygltf::GetNumComponentsInType(m_.accessors[s.output].type);
        smp.output = read_.floats(s.output, comps, what + " sampler output");
        size_t perKey = smp.interpolation == Interpolation::CubicSpline ? 3 : 1;
        size_t values = smp.output.size() / comps;
        if (values % (smp.input.size() * perKey) != 0)
          read_.fail(what + ": sampler output count does not match its keys");
        smp.components = int(smp.output.size() / (smp.input.size() * perKey));
        out.start = std::min(out.start, smp.input.front());
        out.end = std::max(out.end, smp.input.back());
        out.samplers.push_back(std::move(smp));
      }
      for (const auto& c : a.channels) {
        Channel ch;
        ch.node = c.target_node;
        ch.sampler = c.sampler;
        if (ch.sampler < 0 || ch.sampler >= int(out.samplers.size()))
          read_.fail(what + ": channel sampler out of range");
        if (ch.node < 0) {
          warn(what + ": a channel without a target node is ignored");
          continue;
        }
        if (ch.node >= int(scene_.nodes.size())) read_.fail(what + ": channel target node out of range");
        int comps = out.samplers[ch.sampler].components;
        if (c.target_path == "translation")
          ch.path = Path::Translation;
        else if (c.target_path == "rotation")
          ch.path = Path::Rotation;
        else if (c.target_path == "scale")
          ch.path = Path::Scale;
        else if (c.target_path == "weights")
          ch.path = Path::Weights;
        else {
          warn(what + ": channel path '" + c.target_path + "' is not supported and ignored");
          continue;
        }
        int expected = ch.path == Path::Rotation ? 4 : ch.path == Path::Weights ? comps : 3;
        if (comps != expected)
          read_.fail(what + ": channel '" + c.target_path + "' has " + std::to_string(comps) + " components per key");
        if (scene_.nodes[ch.node].matrix)
          warn(what + " animates node '" + scene_.nodes[ch.node].name + "', which is given by a matrix");
        out.channels.push_back(ch);
      }
      if (out.samplers.empty()) out.start = out.end = 0;
      scene_.animations.push_back(std::move(out));
    }
  }

  const tinygltf::Model& m_;
  AccessorReader read_;
  std::string source_;
  Limits limits_;
  uint64_t morphDeltas_ = 0;     // read so far
  bool tangentsWarned_ = false;  // once a file
  Scene scene_;
};

// tinygltf's image decoding (stb_image), after two checks it does not make: an image in a buffer
// view must lie within its buffer (tinygltf hands the decoder the view's bytes unchecked), and an
// image that declares more pixels than the limit is refused before its pixels are allocated.
struct ImageChecks {
  const tinygltf::Model& model;  // being loaded: its buffers and views are read before its images
  uint64_t texels;
  std::string refusal;  // set where an image was refused
};

bool decodeCheckedImage(tinygltf::Image* image, int index, std::string* err, std::string* warn, int width, int height,
                        const unsigned char* bytes, int size, void* user) {
  auto& checks = *static_cast<ImageChecks*>(user);
  const std::string name = "image " + std::to_string(index);
  if (image->bufferView >= 0) {  // tinygltf checked that the view and its buffer exist
    const tinygltf::BufferView& view = checks.model.bufferViews[size_t(image->bufferView)];
    const size_t held = checks.model.buffers[size_t(view.buffer)].data.size();
    if (view.byteOffset > held || view.byteLength > held - view.byteOffset)
      checks.refusal = name + "'s buffer view " + std::to_string(image->bufferView) +
                       " reaches past the end of buffer " + std::to_string(view.buffer) + " (" + std::to_string(held) +
                       " bytes)";
  }
  if (checks.refusal.empty()) {  // the bytes may be read
    const auto declared = ivgi::image::declaredSize({bytes, size_t(std::max(size, 0))});
    if (declared && uint64_t(declared->width) * uint64_t(declared->height) > checks.texels)
      checks.refusal = name + " declares " + std::to_string(declared->width) + "x" + std::to_string(declared->height) +
                       " pixels, more than --max-texels " + std::to_string(checks.texels) + " allows";
  }
  if (!checks.refusal.empty()) {
    if (err) *err += checks.refusal;
    return false;
  }
  return tinygltf::LoadImageData(image, index, err, warn, width, height, bytes, size, nullptr);
}

}  // namespace

Scene sceneFromModel(const tinygltf::Model& model, const std::string& source, const Limits& limits) {
  return Converter(model, source, limits).convert();
}

Scene loadGltf(const std::string& path, const Limits& limits) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw LoadError(path + ": no such file");
  if (fs::is_directory(path, ec)) throw LoadError(path + ": is a directory, not a glTF file");
  // A device or a pipe has no end to read to.
  if (!fs::is_regular_file(path, ec)) throw LoadError(path + ": not a regular file");
  // A .glb's lengths are 32 bits, and tinygltf takes a file's size as one: refused before reading.
  const auto tooLarge = [&](uintmax_t size) {
    if (size > std::numeric_limits<uint32_t>::max())
      throw LoadError(path + ": is " + std::to_string(size) + " bytes, more than a glTF file may hold (4 GiB)");
  };
  if (const uintmax_t size = fs::file_size(path, ec); !ec) tooLarge(size);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw LoadError(path + ": cannot be opened for reading");
  // Read once: tinygltf parses these bytes, and the checks below read their JSON again.
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  tooLarge(bytes.size());  // (it may have grown since)
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  const std::string invalid = path + ": " + (binary ? "invalid .glb: " : "invalid glTF: ");
  // Another version of glTF fails tinygltf's checks on whatever differs first: say what it is.
  const nlohmann::json doc = gltfJson(bytes, binary);
  if (auto problem = gltfVersionProblem(bytes, binary, doc))
    throw LoadError(path + ": " + *problem + "; ivgi reads glTF 2.0");

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  ImageChecks imageChecks{model, limits.texels, {}};
  loader.SetImageLoader(&decodeCheckedImage, &imageChecks);
  std::string err = bytes.empty() ? "the file is empty" : "", warn;
  // Relative URIs resolve against the file's folder, as tinygltf's own file loaders resolve them.
  const std::string folder = fs::path(path).parent_path().string();
  const auto size = static_cast<unsigned int>(bytes.size());
  const bool ok =
      !bytes.empty() && (binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), size, folder)
                                : loader.LoadASCIIFromString(
                                      &model, &err, &warn, reinterpret_cast<const char*>(bytes.data()), size, folder));
  if (!imageChecks.refusal.empty()) throw LoadError(path + ": " + imageChecks.refusal);
  if (!ok || !err.empty()) {
    // A file that needs an extension ivgi does not read (Draco's compressed meshes, say) often fails
    // tinygltf's checks for that reason: say so rather than what tinygltf tripped on.
    if (auto e = unsupportedRequirement(model)) throw LoadError(path + ": requires the unsupported extension " + *e);
    std::string why = err.empty() ? "not a valid glTF file" : err;
    std::replace(why.begin(), why.end(), '\n', ' ');
    // tinygltf quotes a failing data URI whole: keep the message to one readable line.
    // (No std::regex: it recurses per character and overflows the stack on a megabyte of base64.)
    for (size_t at = why.find("data:"); at != std::string::npos; at = why.find("data:", at + 1)) {
      size_t end = why.find(' ', at);
      why.replace(at, end == std::string::npos ? std::string::npos : end - at, "<embedded data URI>");
    }
    if (why.size() > 240) why = why.substr(0, 240) + "...";
    while (!why.empty() && why.back() == ' ') why.pop_back();
    throw LoadError(invalid + why);
  }
  // tinygltf reads a property of the wrong type as absent: refused instead, naming it.
  if (!doc.is_discarded())
    if (auto problem = gltfTypeProblem(doc)) throw LoadError(invalid + *problem);
  Scene scene = sceneFromModel(model, path, limits);
  if (!warn.empty()) {
    std::replace(warn.begin(), warn.end(), '\n', ' ');
    scene.warnings.insert(scene.warnings.begin(), "tinygltf: " + warn);
  }
  return scene;
}

}  // namespace ivgi::scene

#include "scenes/gltf_builder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "engine/image/atomic_file.h"

namespace ivgi::scenes {

void addQuad(MeshData& m, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, int nu, int nv, glm::vec3 facing) {
  glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p3 - p0));
  bool flip = glm::dot(n, facing - 0.25f * (p0 + p1 + p2 + p3)) < 0.0f;
  if (flip) n = -n;
  uint32_t base = uint32_t(m.positions.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      float u = float(i) / float(nu), v = float(j) / float(nv);
      m.positions.push_back(glm::mix(glm::mix(p0, p1, u), glm::mix(p3, p2, u), v));
      m.normals.push_back(n);
      m.uvs.push_back({u, v});
    }
  auto at = [&](int i, int j) { return base + uint32_t(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (flip)
        m.indices.insert(m.indices.end(), {a, c, b, a, d, c});
      else
        m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
}

void addBox(MeshData& m, glm::vec3 centre, glm::vec3 half, int cells) {
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-1.0f, 1.0f}) {
      glm::vec3 n(0.0f), u(0.0f), v(0.0f);
      n[axis] = side * half[axis];
      u[(axis + 1) % 3] = half[(axis + 1) % 3];
      v[(axis + 2) % 3] = half[(axis + 2) % 3];
      addQuad(m, centre + n - u - v, centre + n + u - v, centre + n + u + v, centre + n - u + v, cells, cells,
              centre + 2.0f * n);
    }
}

int cellsFor(float length, float cellsPerMetre) { return std::max(1, int(std::lround(length * cellsPerMetre))); }

GltfBuilder::GltfBuilder() {
  model_.asset.version = "2.0";
  model_.asset.generator = "ivgi";
  model_.buffers.emplace_back();
  model_.scenes.emplace_back();
  model_.defaultScene = 0;
}

int GltfBuilder::accessor(const void* data, size_t count, int componentType, int type, size_t elementBytes,
                          int target) {
  auto& buffer = model_.buffers[0].data;
  while (buffer.size() % 4) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = count * elementBytes;
  view.target = target;
  buffer.insert(buffer.end(), static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + view.byteLength);
  model_.bufferViews.push_back(view);
  tinygltf::Accessor a;
  a.bufferView = int(model_.bufferViews.size() - 1);
  a.componentType = componentType;
  a.count = count;
  a.type = type;
  model_.accessors.push_back(a);
  return int(model_.accessors.size() - 1);
}

int GltfBuilder::material(const std::string& name, glm::vec3 baseColor, glm::vec3 radiance) {
  tinygltf::Material m;
  m.name = name;
  m.pbrMetallicRoughness.baseColorFactor = {baseColor.r, baseColor.g, baseColor.b, 1.0};
  m.pbrMetallicRoughness.metallicFactor = 0.0;
  m.pbrMetallicRoughness.roughnessFactor = 1.0;
  m.extensions["KHR_materials_specular"] =
      tinygltf::Value(tinygltf::Value::Object{{"specularFactor", tinygltf::Value(0.0)}});
  useExtension("KHR_materials_specular");
  float strength = std::max({radiance.r, radiance.g, radiance.b});
  if (strength > 0.0f) {
    m.emissiveFactor = {radiance.r / strength, radiance.g / strength, radiance.b / strength};
    if (strength != 1.0f) {
      tinygltf::Value::Object ext{{"emissiveStrength", tinygltf::Value(double(strength))}};
      m.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(ext);
      useExtension("KHR_materials_emissive_strength");
    }
  }
  model_.materials.push_back(m);
  return int(model_.materials.size() - 1);
}

int GltfBuilder::glossyMaterial(const std::string& name, glm::vec3 baseColor, float metallic, float roughness) {
  tinygltf::Material m;
  m.name = name;
  m.pbrMetallicRoughness.baseColorFactor = {baseColor.r, baseColor.g, baseColor.b, 1.0};
  m.pbrMetallicRoughness.metallicFactor = metallic;
  m.pbrMetallicRoughness.roughnessFactor = roughness;
  model_.materials.push_back(m);
  return int(model_.materials.size() - 1);
}

void GltfBuilder::useExtension(const std::string& name) {
  auto& used = model_.extensionsUsed;
  if (std::find(used.begin(), used.end(), name) == used.end()) used.push_back(name);
}

int GltfBuilder::mesh(const std::string& name, const std::vector<std::pair<MeshData, int>>& primitives) {
  tinygltf::Mesh mesh;
  mesh.name = name;
  for (const auto& [data, material] : primitives) {
    tinygltf::Primitive p;
    int pos = accessor(data.positions.data(), data.positions.size(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                       12, TINYGLTF_TARGET_ARRAY_BUFFER);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (auto v : data.positions) lo = glm::min(lo, v), hi = glm::max(hi, v);
    model_.accessors[pos].minValues = {lo.x, lo.y, lo.z};
    model_.accessors[pos].maxValues = {hi.x, hi.y, hi.z};
    p.attributes["POSITION"] = pos;
    if (!data.normals.empty())
      p.attributes["NORMAL"] = accessor(data.normals.data(), data.normals.size(), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                        TINYGLTF_TYPE_VEC3, 12, TINYGLTF_TARGET_ARRAY_BUFFER);
    for (auto [name, uvs] : {std::pair{"TEXCOORD_0", &data.uvs}, std::pair{"TEXCOORD_1", &data.uvs1}})
      if (!uvs->empty())
        p.attributes[name] = accessor(uvs->data(), uvs->size(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 8,
                                      TINYGLTF_TARGET_ARRAY_BUFFER);
    if (!data.colors.empty())
      p.attributes["COLOR_0"] = accessor(data.colors.data(), data.colors.size(), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                         TINYGLTF_TYPE_VEC4, 16, TINYGLTF_TARGET_ARRAY_BUFFER);
    if (!data.indices.empty())
      p.indices = accessor(data.indices.data(), data.indices.size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                           TINYGLTF_TYPE_SCALAR, 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    p.material = material;
    p.mode = TINYGLTF_MODE_TRIANGLES;
    mesh.primitives.push_back(p);
  }
  model_.meshes.push_back(mesh);
  return int(model_.meshes.size() - 1);
}

int GltfBuilder::node(const std::string& name, int mesh, glm::vec3 t, glm::quat r, int parent) {
  tinygltf::Node n;
  n.name = name;
  n.mesh = mesh;
  if (t != glm::vec3(0.0f)) n.translation = {t.x, t.y, t.z};
  if (r != glm::quat(1, 0, 0, 0)) n.rotation = {r.x, r.y, r.z, r.w};
  model_.nodes.push_back(n);
  int index = int(model_.nodes.size() - 1);
  if (parent >= 0)
    model_.nodes[parent].children.push_back(index);
  else
    model_.scenes[0].nodes.push_back(index);
  return index;
}

int GltfBuilder::camera(const std::string& name, float yfov, float znear, glm::vec3 position, glm::quat rotation) {
  tinygltf::Camera c;
  c.name = name;
  c.type = "perspective";
  c.perspective.yfov = yfov;
  c.perspective.znear = znear;
  model_.cameras.push_back(c);
  int n = node(name, -1, position, rotation);
  model_.nodes[n].camera = int(model_.cameras.size() - 1);
  return n;
}

int GltfBuilder::light(const std::string& name, const std::string& type, float intensity, glm::vec3 position,
                       glm::quat rotation) {
  tinygltf::Light l;
  l.name = name;
  l.type = type;
  l.color = {1, 1, 1};
  l.intensity = intensity;
  model_.lights.push_back(l);
  const int n = node(name, -1, position, rotation);
  model_.nodes[n].extensions["KHR_lights_punctual"] =
      tinygltf::Value(tinygltf::Value::Object{{"light", tinygltf::Value(int(model_.lights.size() - 1))}});
  useExtension("KHR_lights_punctual");
  return n;
}

void GltfBuilder::animate(const std::string& name, int node, const std::string& path, const std::vector<float>& times,
                          const std::vector<float>& values, const std::string& interpolation) {
  auto it = std::find_if(model_.animations.begin(), model_.animations.end(), [&](auto& a) { return a.name == name; });
  if (it == model_.animations.end()) {
    model_.animations.emplace_back();
    model_.animations.back().name = name;
    it = model_.animations.end() - 1;
  }
  int type = path == "rotation" ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
  size_t comps = path == "rotation" ? 4 : 3;
  tinygltf::AnimationSampler s;
  s.input = accessor(times.data(), times.size(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, 4);
  model_.accessors[s.input].minValues = {times.front()};
  model_.accessors[s.input].maxValues = {times.back()};
  s.output = accessor(values.data(), values.size() / comps, TINYGLTF_COMPONENT_TYPE_FLOAT, type, comps * 4);
  s.interpolation = interpolation;
  it->samplers.push_back(s);
  tinygltf::AnimationChannel c;
  c.sampler = int(it->samplers.size() - 1);
  c.target_node = node;
  c.target_path = path;
  it->channels.push_back(c);
}

tinygltf::Model GltfBuilder::finish() {
  model_.buffers[0].uri.clear();
  return model_;
}

void writeModel(const tinygltf::Model& model, const std::string& path) {
  bool binary = path.size() >= 4 && path.substr(path.size() - 4) == ".glb";
  image::writeAtomically(path, [&](const std::string& temp) {
    tinygltf::TinyGLTF writer;
    tinygltf::Model copy = model;
    if (!writer.WriteGltfSceneToFile(&copy, temp, true, true, !binary, binary))
      throw std::runtime_error(path + ": cannot write glTF");
  });
}

}  // namespace ivgi::scenes

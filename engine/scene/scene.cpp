#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>

#include "engine/scene/scene.h"

namespace ivgi::scene {

// The extension's own example (offset (0, 1), rotation π/2, scale ½: "only the lower left quadrant of
// the source image, rotated clockwise 90°") fixes the rotation's sense: u' = cos·u + sin·v.
glm::vec3 TextureTransform::rowU() const {
  return {std::cos(rotation) * scale.x, std::sin(rotation) * scale.y, offset.x};
}
glm::vec3 TextureTransform::rowV() const {
  return {-std::sin(rotation) * scale.x, std::cos(rotation) * scale.y, offset.y};
}

glm::vec4 Material::dielectricReflectance() const {
  const float r = (ior - 1.0f) / (ior + 1.0f);
  const glm::vec3 f0 = glm::min(r * r * specularColor, glm::vec3(1.0f)) * specular;
  return {f0, specular};
}

std::optional<int> Scene::findAnimation(const std::string& key) const {
  for (size_t i = 0; i < animations.size(); ++i)
    if (animations[i].name == key) return int(i);
  if (!key.empty() && std::all_of(key.begin(), key.end(), ::isdigit) && std::stoul(key) < animations.size())
    return int(std::stoul(key));
  return std::nullopt;
}

std::vector<int> Scene::cameraNodes() const {
  std::vector<int> out;
  std::function<void(int)> visit = [&](int n) {
    if (nodes[n].camera >= 0) out.push_back(n);
    for (int c : nodes[n].children) visit(c);
  };
  for (int r : roots) visit(r);
  return out;
}

std::optional<int> Scene::findCameraNode(const std::string& key) const {
  auto list = cameraNodes();
  for (int n : list)
    if (cameras[nodes[n].camera].name == key || nodes[n].name == key) return n;
  if (!key.empty() && std::all_of(key.begin(), key.end(), ::isdigit) && std::stoul(key) < list.size())
    return list[std::stoul(key)];
  return std::nullopt;
}

DrawnSize drawnSize(const Scene& scene) {
  std::vector<DrawnSize> perMesh(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    for (const Primitive& p : scene.meshes[m].primitives) {
      perMesh[m].triangles += p.indices.size() / 3;
      perMesh[m].morphDeltas += uint64_t(p.targets.size()) * p.positions.size();
    }
  DrawnSize total;
  std::vector<int> pending(scene.roots.begin(), scene.roots.end());
  while (!pending.empty()) {  // a stack, not recursion: a chain of nodes may be long
    const Node& node = scene.nodes[size_t(pending.back())];
    pending.pop_back();
    if (node.mesh >= 0) {
      total.triangles += perMesh[size_t(node.mesh)].triangles;
      total.morphDeltas += perMesh[size_t(node.mesh)].morphDeltas;
    }
    pending.insert(pending.end(), node.children.begin(), node.children.end());
  }
  return total;
}

}  // namespace ivgi::scene

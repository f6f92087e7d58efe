#include "engine/scene/texture_sampling.h"

#include <glm/gtc/packing.hpp>

#include "engine/scene/geometry.h"

namespace ivgi::scene {

glm::vec4 sampleTexture(const Geometry& g, int index, glm::vec4 uvs) {
  if (index < 0 || size_t(index) >= g.textures.size()) return glm::vec4(1.0f);
  const gpu::Texture& t = g.textures[index];
  if (t.width == 0 || t.height == 0) return glm::vec4(1.0f);
  const glm::vec2 uv = gpu::transformedUv(t, uvs);
  float ax, ay;
  glm::ivec2 xs = gpu::texelPair(uv.x, int(t.width), t.wrap & 0xffffu, ax);
  glm::ivec2 ys = gpu::texelPair(uv.y, int(t.height), t.wrap >> 16, ay);
  ax = gpu::texelWeight(t, ax), ay = gpu::texelWeight(t, ay);
  auto texel = [&](int x, int y) {
    size_t at = 2 * (size_t(t.offset) + size_t(y) * t.width + size_t(x));
    return glm::vec4(glm::unpackHalf2x16(g.texels[at]), glm::unpackHalf2x16(g.texels[at + 1]));
  };
  return glm::mix(glm::mix(texel(xs.x, ys.x), texel(xs.y, ys.x), ax),
                  glm::mix(texel(xs.x, ys.y), texel(xs.y, ys.y), ax), ay);
}

float presenceAt(const Geometry& g, const gpu::Triangle& t, glm::vec3 w) {
  const gpu::Material& m = g.materials[t.material & ~gpu::kTriangleFlags];
  if (!gpu::alphaMatters(m.alphaCutoff)) return 1.0f;
  const glm::vec4 uvs = w.x * g.uvs[t.v0] + w.y * g.uvs[t.v1] + w.z * g.uvs[t.v2];
  const float color = w.x * g.colors[t.v0].a + w.y * g.colors[t.v1].a + w.z * g.colors[t.v2].a;
  return gpu::presenceOf(m.baseColor.a * color * sampleTexture(g, m.baseColorTexture, uvs).a, m.alphaCutoff);
}

glm::vec3 mappedNormalAt(const Geometry& g, const std::vector<WorldVertex>& world, const gpu::Triangle& t, glm::vec3 w,
                         glm::vec3 n) {
  const gpu::Material& m = g.materials[t.material & ~gpu::kTriangleFlags];
  if (m.normalTexture < 0) return n;
  const gpu::Texture& texture = g.textures[size_t(m.normalTexture)];
  const glm::vec4 uvs = w.x * g.uvs[t.v0] + w.y * g.uvs[t.v1] + w.z * g.uvs[t.v2];
  auto position = [&](uint32_t v) { return glm::vec3(world[v].position); };
  return gpu::mappedNormal(n, position(t.v0), position(t.v1), position(t.v2), gpu::transformedUv(texture, g.uvs[t.v0]),
                           gpu::transformedUv(texture, g.uvs[t.v1]), gpu::transformedUv(texture, g.uvs[t.v2]),
                           glm::vec3(sampleTexture(g, m.normalTexture, uvs)), m.normalScale);
}

}  // namespace ivgi::scene

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

}  // namespace ivgi::scene

#pragma once
// Bilinear texture lookup with glTF wrap modes over the linear half-float texels of Geometry, the
// host twin of sampleTexture() in shaders/resolve.comp.
#include <glm/glm.hpp>

#include <cmath>

namespace ivgi::scene {

struct Geometry;

inline float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
inline float linearToSrgb(float c) { return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

// The two texels and the weight of the second along one axis of a bilinear lookup under a glTF wrap
// mode (33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT, else REPEAT): texelPair() of common.glsl.
inline glm::ivec2 texelPair(float u, int size, uint32_t mode, float& weight) {
  if (mode == 33648u) {
    float t = glm::fract(u * 0.5f) * 2.0f;
    u = t < 1.0f ? t : 2.0f - t;
  } else if (mode != 33071u) {
    u = glm::fract(u);
  }
  float x = u * float(size) - 0.5f, f = std::floor(x);
  weight = x - f;
  int i = int(f), j = i + 1;
  if (mode == 33071u || mode == 33648u) return glm::clamp(glm::ivec2(i, j), 0, size - 1);
  return {i < 0 ? i + size : i, j >= size ? j - size : j};
}

// Linear RGBA at uv of texture `index` (-1: white).
glm::vec4 sampleTexture(const Geometry& g, int index, glm::vec2 uv);

}  // namespace ivgi::scene

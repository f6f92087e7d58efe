#pragma once
// Bilinear texture lookup with glTF wrap modes over the linear half-float texels of Geometry, as
// sampleTexture() in shaders/frame/resolve.comp does it (both address texels by gpu::texelPair).
#include <glm/glm.hpp>

namespace ivgi::scene {

struct Geometry;

// Linear RGBA at uv of texture `index` (-1: white).
glm::vec4 sampleTexture(const Geometry& g, int index, glm::vec2 uv);

}  // namespace ivgi::scene

#pragma once
// Bilinear texture lookup with glTF wrap modes over the linear half-float texels of Geometry, as
// sampleTexture() in shaders/frame/resolve.comp does it (both address texels by gpu::texelPair).
#include <vector>

#include <glm/glm.hpp>

#include "shaders/interface.h"

namespace ivgi::scene {

struct Geometry;

// Linear RGBA of texture `index` (-1: white) at a point whose coordinate sets are `uvs` (TEXCOORD_0
// in xy, TEXCOORD_1 in zw): the one its record reads.
glm::vec4 sampleTexture(const Geometry& g, int index, glm::vec4 uvs);
// The same where both sets are `uv`.
inline glm::vec4 sampleTexture(const Geometry& g, int index, glm::vec2 uv) {
  return sampleTexture(g, index, glm::vec4(uv, uv));
}

// How much of triangle t's surface is there at barycentric weights w (gpu::presenceOf: alphaMode MASK
// and BLEND, over the base colour's alpha, factor × texture × COLOR_0), as presenceAt() in
// shaders/frame/textures.glsl: 1 where its material is opaque.
float presenceAt(const Geometry& g, const gpu::Triangle& t, glm::vec3 w);

// The shading normal at barycentric weights w of triangle t, posed as `world`, whose unit normal
// there is n: n turned by its material's normal texture (gpu::mappedNormal), or n where it has none.
glm::vec3 mappedNormalAt(const Geometry& g, const std::vector<gpu::WorldVertex>& world, const gpu::Triangle& t,
                         glm::vec3 w, glm::vec3 n);

}  // namespace ivgi::scene

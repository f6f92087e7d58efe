#version 460
// The resolve pass, first the irradiance at the vertices, which it interpolates across each
// triangle. A solver gives a surfel's irradiance over its area, at its centroid; the resolve shows
// it at the vertex. Inside a regular grid the two coincide, but on a hard edge the vertex lies on
// the edge and the centroid a quarter of a cell inside, where a concave edge's light changes
// fastest: shown at the vertex as it is, the centroid's value would draw a bright line along every
// such edge. So each surfel's value is carried to its vertex along the gradient of a linear fit
// over its mesh neighbours on its side of the edge (normals within kReceiverNormalCos).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

// Texel views throughout: lavapipe gathers a texel load across lanes, a storage read lane by lane.
layout(binding = 0, rgba32ui) readonly uniform uimageBuffer surfelSources;  // SurfelSource
layout(binding = 1, r32ui) readonly uniform uimageBuffer surfelVertices;
layout(binding = 2, r32ui) readonly uniform uimageBuffer surfelTriangles;
layout(binding = 3, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(binding = 4, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 5, rgba32f) readonly uniform imageBuffer surfels;      // Surfel: positionArea, normal, shape
layout(binding = 6, r32ui) readonly uniform uimageBuffer vertexSurfel;  // int, -1: none
layout(binding = 7, rgba32f) readonly uniform imageBuffer surfelIrradiance;
layout(std430, binding = 8) writeonly buffer VertexIrradiance { vec4 vertexIrradiance[]; };
layout(binding = 9, rgba32f) readonly uniform imageBuffer surfelDirect;
// True where the resolve adds the depth maps' direct light per pixel (resolve.comp): the vertices
// then carry the surfels' irradiance less that direct light.
layout(constant_id = 0) const bool kDirectPixels = false;
// True where only the vertices the image shows are read (the reflections: mark_shown).
layout(constant_id = 1) const bool kShownOnly = false;
layout(std430, binding = 10) readonly buffer ShownSurfels { uint shownSurfels[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: surfels

// The irradiance the vertices carry: the solver's, or what the depth maps' direct light leaves of it.
vec4 shown(int s) {
  const vec4 e = imageLoad(surfelIrradiance, s);
  return kDirectPixels ? vec4(e.rgb - imageLoad(surfelDirect, s).rgb, e.a) : e;
}

void main() {
  const uint s = itemIndex();
  if (s >= push.count || (kShownOnly && (shownSurfels[s] & kShownVertex) == 0u)) return;
  const uvec4 src = imageLoad(surfelSources, int(s));  // firstVertex, vertexCount, firstTriangle, triangleCount
  const vec4 own = shown(int(s)), positionArea = imageLoad(surfels, int(3u * s));
  const vec3 c = positionArea.xyz, n = imageLoad(surfels, int(3u * s + 1u)).xyz;
  const uint vertex = imageLoad(surfelVertices, int(src.x)).x;
  const vec3 toVertex = imageLoad(world, int(2u * vertex)).xyz - c;
  vec3 t1, t2;
  tangentFrame(n, t1, t2);
  const vec2 d = vec2(dot(toVertex, t1), dot(toVertex, t2));
  if (positionArea.w <= 0.0 || dot(d, d) == 0.0) {
    vertexIrradiance[s] = kDirectPixels ? vec4(max(own.rgb, vec3(0.0)), own.a) : own;
    return;
  }
  // Weighted least squares for the gradient g of each channel: Σ w (ΔE − g·o)² over the neighbours'
  // offsets o in the tangent plane (a neighbour met in two triangles counts twice, as on both sides).
  mat2 a = mat2(0.0);
  mat3x2 b = mat3x2(0.0);  // Σ w o ΔEᵀ, a column per channel
  for (uint k = 0; k < src.w; ++k) {
    const uvec4 t = imageLoad(triangles, int(imageLoad(surfelTriangles, int(src.z + k)).x));
    for (uint j = 0; j < 3; ++j) {
      const int other = int(imageLoad(vertexSurfel, int(t[j])).x);
      if (other < 0 || uint(other) == s) continue;
      const vec4 at = imageLoad(surfels, 3 * other);
      const float agree =
          (dot(n, imageLoad(surfels, 3 * other + 1).xyz) - kReceiverNormalCos) / (1.0 - kReceiverNormalCos);
      if (at.w <= 0.0 || agree <= 0.0) continue;
      const vec3 e = at.xyz - c;
      const vec2 o = vec2(dot(e, t1), dot(e, t2));
      const float w = agree * agree;
      a += w * outerProduct(o, o);
      b += w * outerProduct(o, shown(other).rgb - own.rgb);
    }
  }
  // Regularised, so that neighbours in a line (a strip one surfel wide) leave the gradient across
  // them at zero instead of undetermined.
  const float ridge = 1e-3 * (a[0][0] + a[1][1]) + 1e-30;
  a[0][0] += ridge, a[1][1] += ridge;
  const vec3 change = (d * inverse(a)) * b;  // dᵀ A⁻¹ B: g·d for each channel
  vertexIrradiance[s] = vec4(max(own.rgb + change, vec3(0.0)), own.a);
}

#version 460
// The resolve pass, first the irradiance at the vertices, which it interpolates across each
// triangle. A solver gives a surfel's irradiance over its area, at its centroid; the resolve shows
// it at the vertex. Inside a regular grid the two coincide, but on a hard edge the vertex lies on
// the edge and the centroid a quarter of a cell inside, where a concave edge's light changes
// fastest: shown at the vertex as it is, the centroid's value would draw a bright line along every
// such edge. So each surfel's value is carried to its vertex along the gradient of a linear fit
// over its mesh neighbours on its side of the edge (normals within kReceiverNormalCos).
// A surfel inside another object (buried_surfels: a floor under a block standing on it) stands for
// no surface the image shows, but the triangles reaching out from under the block share its vertex:
// it takes the fit of its neighbours outside, value and gradient, carried to its vertex (one ring
// of them gives no slope across the contact: their light as it is across, continued along), and
// its neighbours outside leave it out of theirs. So the light along a contact is the surface's own
// outside, not drawn down toward the darkness under the block.
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
layout(binding = 11, r32ui) readonly uniform uimageBuffer surfelBuried;  // not 0: buried (kBuried, kBuriedInItself)
layout(push_constant) uniform Push { CountPush push; };                  // count: surfels

// The irradiance the vertices carry: the solver's, or what the depth maps' direct light leaves of it.
vec4 shown(int s) {
  const vec4 e = imageLoad(surfelIrradiance, s);
  return kDirectPixels ? vec4(e.rgb - imageLoad(surfelDirect, s).rgb, e.a) : e;
}

// The inverse of a fit's matrix m, regularised by a share of the offsets' own spread (a's trace,
// a = Σ w o oᵀ), so that neighbours in a line (a strip one surfel wide, a column beside a contact)
// leave the gradient across them at zero instead of undetermined.
mat2 regularised(mat2 m, mat2 a) {
  const float ridge = 1e-3 * (a[0][0] + a[1][1]) + 1e-30;
  m[0][0] += ridge, m[1][1] += ridge;
  return inverse(m);
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
  const bool buried = imageLoad(surfelBuried, int(s)).x != 0u;
  if (positionArea.w <= 0.0 || (dot(d, d) == 0.0 && !buried)) {
    vertexIrradiance[s] = kDirectPixels ? vec4(max(own.rgb, vec3(0.0)), own.a) : own;
    return;
  }
  // Weighted least squares for the gradient g of each channel: Σ w (ΔE − g·o)² over the neighbours'
  // offsets o in the tangent plane (a neighbour met in two triangles counts twice, as on both sides).
  // A buried surfel fits the value at its centroid too: Σ w (E − e − g·o)², over those outside.
  mat2 a = mat2(0.0);
  mat3x2 b = mat3x2(0.0);                   // Σ w o ΔEᵀ, a column per channel
  vec3 sumE = vec3(0.0), sumO = vec3(0.0);  // buried: Σ w E, and Σ w o with Σ w in z
  for (uint k = 0; k < src.w; ++k) {
    const uvec4 t = imageLoad(triangles, int(imageLoad(surfelTriangles, int(src.z + k)).x));
    for (uint j = 0; j < 3; ++j) {
      const int other = int(imageLoad(vertexSurfel, int(t[j])).x);
      if (other < 0 || uint(other) == s) continue;
      const vec4 at = imageLoad(surfels, 3 * other);
      const float agree =
          (dot(n, imageLoad(surfels, 3 * other + 1).xyz) - kReceiverNormalCos) / (1.0 - kReceiverNormalCos);
      if (at.w <= 0.0 || agree <= 0.0 || imageLoad(surfelBuried, other).x != 0u) continue;
      const vec3 e = at.xyz - c;
      const vec2 o = vec2(dot(e, t1), dot(e, t2));
      const float w = agree * agree;
      const vec3 value = shown(other).rgb;
      a += w * outerProduct(o, o);
      b += w * outerProduct(o, buried ? value : value - own.rgb);
      sumE += w * value, sumO += w * vec3(o, 1.0);
    }
  }
  if (!buried) {
    const vec3 change = (d * regularised(a, a)) * b;  // dᵀ A⁻¹ B: g·d for each channel
    vertexIrradiance[s] = vec4(max(own.rgb + change, vec3(0.0)), own.a);
    return;
  }
  if (sumO.z <= 0.0) {  // nothing outside beside it: its own light
    vertexIrradiance[s] = vec4(max(own.rgb, vec3(0.0)), own.a);
    return;
  }
  // The value and gradient together: the 3×3 normal equations of (e, g) in block form, solved for g
  // with e eliminated (the Schur complement, the offsets' spread about their mean), then
  // e = (Σ w E − Σ w o·g) / Σ w.
  const vec2 mean = sumO.xy / sumO.z;
  const mat3x2 g = regularised(a - sumO.z * outerProduct(mean, mean), a) * (b - outerProduct(mean, sumE));
  const vec3 value = sumE / sumO.z + (d - mean) * g;  // e + g·d
  vertexIrradiance[s] = vec4(max(value, vec3(0.0)), own.a);
}

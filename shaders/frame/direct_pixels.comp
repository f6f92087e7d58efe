#version 460
// Direct light at the pixels, first: each pixel takes its share of the emitter samples (interleaved
// over blocks of pixels, shadowBlock) at the point its central sample sees, with their shadows
// from the depth maps and without, and every punctual light with its shadow. The resolve then scales the light
// the vertices carry unshadowed by the share its neighbours on the same surface see (the ratio of the two summed over
// them), so that the shadows are the pixels' own at a fraction of the lookups. Where the pixel's
// material is glossy (kGlossy), also what its specular lobe reflects of that light toward the
// camera, which the resolve averages over the same neighbours. Where a normal texture turns the
// shading normal (kNormalMapped), the lobe reflects about the pixel's, and the pixel keeps its
// light's vectors, by which the resolve turns the light to each sample's (pixelTurn).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(binding = 2, rg32ui) readonly uniform uimageBuffer visibility;   // 64-bit keys, low word first
layout(binding = 3, rgba32f) readonly uniform imageBuffer lightPoints;  // LightPoint
layout(binding = 4, rgba32f) readonly uniform imageBuffer lightViews;   // Camera
layout(binding = 5, r32ui) readonly uniform uimageBuffer lightDepth;    // depths' float bits
layout(std430, binding = 6) writeonly buffer PixelLights { PixelLight pixelLights[]; };
layout(binding = 7, rgba32ui) readonly uniform uimageBuffer materials;  // Material
layout(binding = 8, rgba32f) readonly uniform imageBuffer uvs;          // TEXCOORD_0 (xy), TEXCOORD_1 (zw)
layout(binding = 9, rgba32f) readonly uniform imageBuffer colors;       // COLOR_0 per vertex
layout(std430, binding = 10) readonly buffer Textures { Texture textures[]; };
layout(binding = 11, rg32ui) readonly uniform uimageBuffer texels;  // two packHalf2x16 words a texel
// Per pixel: the lobe's reflection of its share of the emitter samples, then of the punctual lights.
layout(std430, binding = 12) writeonly buffer PixelSpecular { vec4 pixelSpecular[]; };
// Per pixel (kNormalMapped): the luminance vectors (PointsLight) of its emitter samples' unshadowed
// light and of the punctual lights' seen light.
layout(std430, binding = 13) writeonly buffer PixelTurn { vec4 pixelTurn[]; };
layout(push_constant) uniform Push { ResolvePush push; };
// As the resolve's: some material has a texture; some primitive has COLOR_0; some material is glossy.
layout(constant_id = 0) const bool kTextured = true;
layout(constant_id = 1) const bool kColored = false;
layout(constant_id = 2) const bool kGlossy = false;
// Some material has a normal texture.
layout(constant_id = 3) const bool kNormalMapped = false;
// Some blended surface (alphaMode BLEND) is in the maps: their lookups take four texels' share.
layout(constant_id = 4) const bool kBlendedMaps = false;
#include "direct_light.glsl"
#include "surface_hit.glsl"
#include "surface_material.glsl"

void main() {
  const uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= push.size.x || px.y >= push.size.y) return;
  const uint o = px.y * push.size.x + px.x;
  const SurfaceHit h = surfaceHit(push.camera, px * push.samples + push.samples / 2u, push.size * push.samples);
  const float len = h.hit ? length(h.normal) : 0.0;
  if (!(len > 0.0)) {
    pixelLights[o] = PixelLight(vec4(0.0), vec4(0.0), vec4(0.0));
    if (kGlossy) pixelSpecular[2u * o] = pixelSpecular[2u * o + 1u] = vec4(0.0);
    if (kNormalMapped) pixelTurn[2u * o] = pixelTurn[2u * o + 1u] = vec4(0.0);
    return;
  }
  const vec3 n = h.normal / len, p = h.position;
  const uint block = shadowBlock(push.samples), stride = max(min(block * block, push.lightSamples), 1u),
             first = ((px.y % block) * block + px.x % block) % stride;
  // The nearest texel: the resolve's window filters the emitter samples' shadows. The point and
  // spot lights are few: every pixel takes them all, their shadows its own.
  const vec3 v = normalize(towardEye(cameraEye(push.camera), p));
  const vec3 shading = shadingNormalAt(h, n, faceNormalOf(h, n), v);
  Lobe lobe = noLobe(shading);
  if (kGlossy) {
    lobe.brdf = materialAt(h.triangle, h.weights).brdf;
    lobe.glossy = !isLambertian(lobe.brdf);
    tangentFrame(shading, lobe.t1, lobe.t2);
    lobe.view = vec3(dot(v, lobe.t1), dot(v, lobe.t2), abs(dot(v, shading)));
  }
  const uint lookup = kBlendedMaps ? kBlendedPixelLookup : kPixelLookup;
  const PointsLight emitters =
      lightAt(p, n, first, push.lightSamples, stride, float(stride), push.shadowMap, lookup, lobe, 0.0);
  const PointsLight punctual = lightAt(p, n, push.lightSamples, push.lightSamples + push.punctualLights, 1u, 1.0,
                                       push.shadowMap, lookup, lobe, 0.0);
  if (kGlossy)
    pixelSpecular[2u * o] = vec4(emitters.reflected, 0.0), pixelSpecular[2u * o + 1u] = vec4(punctual.reflected, 0.0);
  // The shadows' share is found at n, which the pixel's neighbours on its surface share; the
  // resolve turns the light to each sample's shading normal by the light's vectors.
  if (kNormalMapped) {
    pixelTurn[2u * o] = vec4(emitters.unshadowedVector, 0.0);
    pixelTurn[2u * o + 1u] = vec4(punctual.seenVector, 0.0);
  }
  pixelLights[o] = PixelLight(vec4(emitters.seen, uintBitsToFloat(packUnitVector(n))),
                              vec4(emitters.unshadowed, dot(n, p)), vec4(punctual.seen, 1.0));
}

#version 460
// The resolve pass: per output pixel, average its samples' channels (albedo, normal, depth,
// emission, radiance) from the visibility buffer.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(binding = 2, rg32ui) readonly uniform uimageBuffer visibility;   // 64-bit keys, low word first
layout(binding = 3, rg32f) readonly uniform imageBuffer uvs;
layout(binding = 4, rgba32ui) readonly uniform uimageBuffer materials;  // Material: base colour, emission, textures
layout(std430, binding = 5) readonly buffer Textures { Texture textures[]; };
layout(std430, binding = 6) readonly buffer Texels { uint texels[]; };
layout(std430, binding = 7) writeonly buffer Radiance { vec4 radiance[]; };
layout(std430, binding = 8) writeonly buffer Albedo { vec4 albedoOut[]; };
layout(std430, binding = 9) writeonly buffer NormalDepth { vec4 normalDepth[]; };
layout(std430, binding = 10) writeonly buffer Emission { vec4 emissionOut[]; };
layout(binding = 11, r32ui) readonly uniform uimageBuffer vertexSurfel;       // int, -1: none
layout(binding = 12, rgba32f) readonly uniform imageBuffer vertexIrradiance;  // per surfel, at its vertex
layout(binding = 13, rgba32f) readonly uniform imageBuffer colors;            // COLOR_0 per vertex
layout(std430, binding = 14) readonly buffer LightPoints { LightPoint lightPoints[]; };
layout(std430, binding = 15) readonly buffer LightViews { Camera lightViews[]; };
layout(std430, binding = 16) readonly buffer LightDepth { uint lightDepth[]; };
layout(push_constant) uniform Push { ResolvePush push; };
// False for scenes without textures: the lookups are compiled out. lavapipe runs a branch inside
// the sample loop masked, so even untaken lookups cost a third of the pass.
layout(constant_id = 0) const bool kTextured = true;
// True when a solver computed the irradiance at the surfels: pixel radiance = Le + ρ·E/π, with the
// irradiance E interpolated from the triangle's vertices and ρ the pixel's own (textured) albedo.
layout(constant_id = 1) const bool kLit = false;
// True where some primitive has vertex colours (COLOR_0), which multiply the base colour.
layout(constant_id = 2) const bool kColored = false;
// True where the emitters' direct light comes from depth maps (gi::DirectLight): the vertices then
// carry only the rest of the irradiance, and each sample adds the maps' direct light at its own
// point, sample k of a pixel's n² taking the emitter samples k, k + n², … (interleaved: a pixel
// takes them all).
layout(constant_id = 3) const bool kDirectPixels = false;
#include "direct_light.glsl"

vec3 irradianceAt(uint vertex) {
  int surfel = int(imageLoad(vertexSurfel, int(vertex)).x);
  return surfel >= 0 ? imageLoad(vertexIrradiance, surfel).rgb : vec3(0.0);
}
vec3 positionOf(uint vertex) { return imageLoad(world, int(2u * vertex)).xyz; }
vec3 normalOf(uint vertex) { return imageLoad(world, int(2u * vertex + 1u)).xyz; }
vec2 uvOf(uint vertex) { return imageLoad(uvs, int(vertex)).xy; }
vec3 colorOf(uint vertex) { return imageLoad(colors, int(vertex)).rgb; }

vec4 texel(Texture t, int x, int y) {
  uint at = 2u * (t.offset + uint(y) * t.width + uint(x));
  return vec4(unpackHalf2x16(texels[at]), unpackHalf2x16(texels[at + 1u]));
}

vec4 sampleTexture(int index, vec2 uv) {
  if (index < 0) return vec4(1.0);
  Texture t = textures[index];
  if (t.width == 0u || t.height == 0u) return vec4(1.0);
  uv = transformedUv(t, uv);
  float ax, ay;
  ivec2 xs = texelPair(uv.x, int(t.width), t.wrap & 0xffffu, ax), ys = texelPair(uv.y, int(t.height), t.wrap >> 16, ay);
  return mix(mix(texel(t, xs.x, ys.x), texel(t, xs.y, ys.x), ax), mix(texel(t, xs.x, ys.y), texel(t, xs.y, ys.y), ax),
             ay);
}

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= push.size.x || px.y >= push.size.y) return;
  uint samples = push.samples;
  uvec2 fine = push.size * samples;
  vec3 albedo = vec3(0.0), normal = vec3(0.0), emission = vec3(0.0), reflected = vec3(0.0);
  float depth = 0.0, hits = 0.0;
  for (uint sy = 0; sy < samples; ++sy)
    for (uint sx = 0; sx < samples; ++sx) {
      uvec2 s = px * samples + uvec2(sx, sy);
      uvec2 words = imageLoad(visibility, int(s.y * fine.x + s.x)).xy;
      uint64_t key = packUint2x32(words);
      if (key == kEmptyVisibility) continue;
      uvec4 t = imageLoad(triangles, int(keyId(key)));  // v0, v1, v2, material
      vec3 a = positionOf(t.x), b = positionOf(t.y), c = positionOf(t.z);
      float tHit;
      vec2 bc;
      const vec3 ray = cameraRay(push.camera, vec2(s) + 0.5, fine);
      intersectTriangle(push.camera.origin.xyz, ray, a, b, c, tHit, bc);
      vec3 w = vec3(1.0 - bc.x - bc.y, bc.x, bc.y);
      vec3 n = cross(b - a, c - a);
      if ((t.w & kFlatShaded) == 0u) n = w.x * normalOf(t.x) + w.y * normalOf(t.y) + w.z * normalOf(t.z);
      float len = length(n);
      uint mi = t.w & ~kFlatShaded;
      vec3 base = uintBitsToFloat(imageLoad(materials, int(3u * mi)).rgb),
           emit = uintBitsToFloat(imageLoad(materials, int(3u * mi + 1u)).rgb);
      if (kColored) base *= w.x * colorOf(t.x) + w.y * colorOf(t.y) + w.z * colorOf(t.z);
      if (kTextured) {
        vec2 uv = w.x * uvOf(t.x) + w.y * uvOf(t.y) + w.z * uvOf(t.z);
        ivec2 textures = ivec2(imageLoad(materials, int(3u * mi + 2u)).xy);  // base colour, emissive; -1: none
        base *= sampleTexture(textures.x, uv).rgb;
        emit *= sampleTexture(textures.y, uv).rgb;
      }
      albedo += base;
      emission += emit;
      if (kLit) {
        vec3 e = w.x * irradianceAt(t.x) + w.y * irradianceAt(t.y) + w.z * irradianceAt(t.z);
        if (kDirectPixels && len > 0.0) {
          const uint stride = min(samples * samples, push.lightSamples), first = (sy * samples + sx) % stride;
          e += directIrradiance(push.camera.origin.xyz + tHit * ray, n / len, push.lightSamples, push.shadowMap, first,
                                stride);
        }
        reflected += base * e / kPi;
      }
      normal += len > 0.0 ? n / len : vec3(0.0);
      depth += keyDepth(key);
      hits += 1.0;
    }
  float all = float(samples * samples);
  float nlen = length(normal);
  uint o = px.y * push.size.x + px.x;
  radiance[o] = vec4((emission + reflected) / all, hits / all);
  albedoOut[o] = vec4(albedo / all, 1.0);
  normalDepth[o] = vec4(nlen > 0.0 ? normal / nlen : vec3(0.0), hits > 0.0 ? depth / hits : 0.0);
  emissionOut[o] = vec4(emission / all, 0.0);
}

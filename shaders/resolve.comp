#version 460
// Pass 7b, resolve: per output pixel, average its samples' channels (albedo, normal, depth,
// emission, radiance) from the visibility buffer.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer World { WorldVertex world[]; };
layout(std430, binding = 1) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = 2) readonly buffer Visibility { uint64_t visibility[]; };
layout(std430, binding = 3) readonly buffer Uvs { vec2 uvs[]; };
layout(std430, binding = 4) readonly buffer Materials { Material materials[]; };
layout(std430, binding = 5) readonly buffer Textures { Texture textures[]; };
layout(std430, binding = 6) readonly buffer Texels { uint texels[]; };
layout(std430, binding = 7) writeonly buffer Radiance { vec4 radiance[]; };
layout(std430, binding = 8) writeonly buffer Albedo { vec4 albedoOut[]; };
layout(std430, binding = 9) writeonly buffer NormalDepth { vec4 normalDepth[]; };
layout(std430, binding = 10) writeonly buffer Emission { vec4 emissionOut[]; };
layout(std430, binding = 11) readonly buffer VertexSurfel { int vertexSurfel[]; };
layout(std430, binding = 12) readonly buffer SurfelIrradiance { vec4 surfelIrradiance[]; };
layout(push_constant) uniform Push { Camera cam; uvec2 size; uint samples; uint unused; };
// False for scenes without textures: the lookups are compiled out. lavapipe runs a branch inside
// the sample loop masked, so even untaken lookups cost a third of the pass.
layout(constant_id = 0) const bool kTextured = true;
// True when a solver computed the irradiance at the surfels: pixel radiance = Le + ρ·E/π, with the
// irradiance E interpolated from the triangle's vertices and ρ the pixel's own (textured) albedo.
layout(constant_id = 1) const bool kLit = false;

vec3 irradianceAt(int surfel) { return surfel >= 0 ? surfelIrradiance[surfel].rgb : vec3(0.0); }

vec4 texel(Texture t, int x, int y) {
  uint at = 2u * (t.offset + uint(y) * t.width + uint(x));
  return vec4(unpackHalf2x16(texels[at]), unpackHalf2x16(texels[at + 1u]));
}

vec4 sampleTexture(int index, vec2 uv) {
  if (index < 0) return vec4(1.0);
  Texture t = textures[index];
  if (t.width == 0u || t.height == 0u) return vec4(1.0);
  float ax, ay;
  ivec2 xs = texelPair(uv.x, int(t.width), t.wrap & 0xffffu, ax), ys = texelPair(uv.y, int(t.height), t.wrap >> 16, ay);
  return mix(mix(texel(t, xs.x, ys.x), texel(t, xs.y, ys.x), ax), mix(texel(t, xs.x, ys.y), texel(t, xs.y, ys.y), ax), ay);
}

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= size.x || px.y >= size.y) return;
  uvec2 fine = size * samples;
  vec3 albedo = vec3(0.0), normal = vec3(0.0), emission = vec3(0.0), reflected = vec3(0.0);
  float depth = 0.0, hits = 0.0;
  for (uint sy = 0; sy < samples; ++sy)
    for (uint sx = 0; sx < samples; ++sx) {
      uvec2 s = px * samples + uvec2(sx, sy);
      uint64_t key = visibility[s.y * fine.x + s.x];
      if (key == kEmptyVisibility) continue;
      Triangle t = triangles[keyId(key)];
      vec3 a = world[t.v0].position.xyz, b = world[t.v1].position.xyz, c = world[t.v2].position.xyz;
      float tHit;
      vec2 bc;
      intersectTriangle(cam.origin.xyz, cameraRay(cam, vec2(s) + 0.5, fine), a, b, c, tHit, bc);
      vec3 w = vec3(1.0 - bc.x - bc.y, bc.x, bc.y);
      vec3 n = cross(b - a, c - a);
      if ((t.material & kFlatShaded) == 0u)
        n = w.x * world[t.v0].normal.xyz + w.y * world[t.v1].normal.xyz + w.z * world[t.v2].normal.xyz;
      float len = length(n);
      vec2 uv = w.x * uvs[t.v0] + w.y * uvs[t.v1] + w.z * uvs[t.v2];
      uint mi = t.material & ~kFlatShaded;
      vec3 base = materials[mi].baseColor.rgb, emit = materials[mi].emission.rgb;
      if (kTextured) {
        base *= sampleTexture(materials[mi].baseColorTexture, uv).rgb;
        emit *= sampleTexture(materials[mi].emissiveTexture, uv).rgb;
      }
      albedo += base;
      emission += emit;
      if (kLit) {
        vec3 e = w.x * irradianceAt(vertexSurfel[t.v0]) + w.y * irradianceAt(vertexSurfel[t.v1]) + w.z * irradianceAt(vertexSurfel[t.v2]);
        reflected += base * e / kPi;
      }
      normal += len > 0.0 ? n / len : vec3(0.0);
      depth += keyDepth(key);
      hits += 1.0;
    }
  float all = float(samples * samples);
  float nlen = length(normal);
  uint o = px.y * size.x + px.x;
  radiance[o] = vec4((emission + reflected) / all, hits / all);
  albedoOut[o] = vec4(albedo / all, 1.0);
  normalDepth[o] = vec4(nlen > 0.0 ? normal / nlen : vec3(0.0), hits > 0.0 ? depth / hits : 0.0);
  emissionOut[o] = vec4(emission / all, 0.0);
}

#version 460
// The resolve pass: per output pixel, average its samples' channels (albedo, normal, depth,
// emission, roughness and metallic, radiance) from the visibility buffer.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(binding = 2, rg32ui) readonly uniform uimageBuffer visibility;   // 64-bit keys, low word first
layout(binding = 3, rgba32f) readonly uniform imageBuffer uvs;          // TEXCOORD_0 (xy), TEXCOORD_1 (zw)
layout(binding = 4, rgba32ui) readonly uniform uimageBuffer materials;  // Material: base colour, emission, textures
layout(std430, binding = 5) readonly buffer Textures { Texture textures[]; };
layout(binding = 6, rg32ui) readonly uniform uimageBuffer texels;  // two packHalf2x16 words a texel
layout(std430, binding = 7) writeonly buffer Radiance { vec4 radiance[]; };
layout(std430, binding = 8) writeonly buffer Albedo { vec4 albedoOut[]; };
layout(std430, binding = 9) writeonly buffer NormalDepth { vec4 normalDepth[]; };
layout(std430, binding = 10) writeonly buffer Emission { vec4 emissionOut[]; };
layout(binding = 11, r32ui) readonly uniform uimageBuffer vertexSurfel;       // int, -1: none
layout(binding = 12, rgba32f) readonly uniform imageBuffer vertexIrradiance;  // per surfel, at its vertex
layout(binding = 13, rgba32f) readonly uniform imageBuffer colors;            // COLOR_0 per vertex
layout(binding = 14, rgba32f) readonly uniform imageBuffer pixelLights;       // PixelLight: 3 texels a pixel
layout(binding = 15, rgba32f) readonly uniform imageBuffer vertexUnshadowed;  // per surfel, at its vertex
layout(std430, binding = 16) writeonly buffer RoughnessMetallic { vec4 roughnessMetallic[]; };
layout(binding = 17, rgba32f) readonly uniform imageBuffer specularAlbedo;  // (A, B), brdf.h
layout(binding = 18, rgba32f) readonly uniform imageBuffer pixelSpecular;   // 2 texels a pixel (direct_pixels)
layout(binding = 19, rgba32f) readonly uniform imageBuffer vertexLobe;      // per surfel, at its vertex
layout(binding = 20, rgba32f) readonly uniform imageBuffer pixelTurn;       // 2 texels a pixel (direct_pixels)
layout(push_constant) uniform Push { ResolvePush push; };
// False for scenes without textures: the lookups are compiled out. lavapipe runs a branch inside
// the sample loop masked, so even untaken lookups cost a third of the pass.
layout(constant_id = 0) const bool kTextured = true;
// True when a solver computed the irradiance at the surfels: pixel radiance = Le + ρ·E/π, with the
// irradiance E interpolated from the triangle's vertices and ρ the pixel's own (textured) albedo.
layout(constant_id = 1) const bool kLit = false;
// True where some primitive has vertex colours (COLOR_0), which multiply the base colour.
layout(constant_id = 2) const bool kColored = false;
// True where the pixels take the emitters' direct light from depth maps (gi::DirectLight): the
// vertices then carry the rest of the irradiance and, apart, the direct light unshadowed, which each
// sample scales by the share its neighbours on its surface see (direct_pixels).
layout(constant_id = 3) const bool kDirectPixels = false;
// True where some material is not Lambertian: a lit glossy sample then reflects the direct light
// through its lobe (direct_pixels' sums, kDirectPixels) and the rest as its material reflects
// uniform light toward the camera (brdf.h's base and lobe reflectances), not by its base colour.
layout(constant_id = 4) const bool kGlossy = false;
// True where the solver reflects the indirect light through the glossy surfels' lobes toward the
// camera (Solver::recordReflections): a glossy sample's lobe then takes that, carried to the
// vertices and across the triangle, instead of the indirect light as if it arrived evenly.
layout(constant_id = 5) const bool kReflections = false;
// True where some material has a normal texture: a sample shades with the normal it turns the
// surface's to, and (kDirectPixels) the direct light turns with it by its pixel's vectors (pixelTurn).
layout(constant_id = 6) const bool kNormalMapped = false;
#include "surface_hit.glsl"
#include "surface_material.glsl"

#include "common/specular_albedo.glsl"

vec3 irradianceAt(uint vertex) {
  int surfel = int(imageLoad(vertexSurfel, int(vertex)).x);
  return surfel >= 0 ? imageLoad(vertexIrradiance, surfel).rgb : vec3(0.0);
}
vec3 unshadowedAt(uint vertex) {
  int surfel = int(imageLoad(vertexSurfel, int(vertex)).x);
  return surfel >= 0 ? imageLoad(vertexUnshadowed, surfel).rgb : vec3(0.0);
}
vec3 lobeAt(uint vertex) {
  int surfel = int(imageLoad(vertexSurfel, int(vertex)).x);
  return surfel >= 0 ? imageLoad(vertexLobe, surfel).rgb : vec3(0.0);
}
// Whether point p lies on the surface of `plane` (unit normal, n·p) whose normal is n: the normals
// within kShadowNormalCos, p within `tolerance` of the plane.
bool onPlane(vec4 plane, vec3 p, vec3 n, float tolerance) {
  return dot(plane.xyz, n) >= kShadowNormalCos && abs(dot(plane.xyz, p) - plane.w) <= tolerance;
}

// Whether the point pixel `at` (its first texel in pixelLights) sees lies on p's surface.
bool pixelOnPlane(int at, vec3 p, vec3 n, float tolerance) {
  const vec4 shadowed = imageLoad(pixelLights, at), unshadowed = imageLoad(pixelLights, at + 1);
  return imageLoad(pixelLights, at + 2).w != 0.0 &&
         onPlane(vec4(unpackUnitVector(floatBitsToUint(shadowed.w)), unshadowed.w), p, n, tolerance);
}

// How light `light` whose luminance vector is `vector` (PointsLight) changes where the normal
// turns by `turn`: its colour, at the luminance the vector gives along the turn.
vec3 turnedBy(vec3 light, vec3 vector, vec3 turn) {
  const float weight = luminance(light);
  return weight > 0.0 ? light * (dot(vector, turn) / weight) : vec3(0.0);
}

// The direct light around a point on a surface: the share of the emitter samples' light that
// reaches it (per channel), the punctual lights' light, and (kGlossy) what the specular lobe
// reflects of both toward the camera.
struct DirectAround {
  vec3 share, punctual, specular;
};

// Sums over pixels of the direct light they found (direct_pixels): the emitter samples' shadowed and
// unshadowed light, the punctual lights', and the lobe's reflections of the two (kGlossy).
struct LightSums {
  vec3 seen, all, punctual, specular, punctualSpecular;
  float weight;
};

// Adds to `sums` those of the pixels from `nearest` to `farthest` pixels from px (along either
// axis) whose points lie on p's surface, each weighted ½ along an axis where it lies on the rim
// `rim` (> 0), else 1; whether any lay on it.
bool sumAround(uvec2 px, vec3 p, vec3 n, float tolerance, int nearest, int farthest, int rim, inout LightSums sums) {
  bool found = false;
  for (int dy = -farthest; dy <= farthest; ++dy)
    for (int dx = -farthest; dx <= farthest; ++dx) {
      const ivec2 q = ivec2(px) + ivec2(dx, dy);
      if (max(abs(dx), abs(dy)) < nearest || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(push.size))))
        continue;
      const int at = 3 * (q.y * int(push.size.x) + q.x);
      if (!pixelOnPlane(at, p, n, tolerance)) continue;
      const float w = (rim > 0 && abs(dx) == rim ? 0.5 : 1.0) * (rim > 0 && abs(dy) == rim ? 0.5 : 1.0);
      sums.seen += w * imageLoad(pixelLights, at).rgb, sums.all += w * imageLoad(pixelLights, at + 1).rgb;
      sums.punctual += w * imageLoad(pixelLights, at + 2).rgb, sums.weight += w;
      if (kGlossy) {
        const int lobe = 2 * (q.y * int(push.size.x) + q.x);
        sums.specular += w * imageLoad(pixelSpecular, lobe).rgb;
        sums.punctualSpecular += w * imageLoad(pixelSpecular, lobe + 1).rgb;
      }
      found = true;
    }
  return found;
}

// The direct light around point p (unit normal n) seen in pixel px. The share: over the pixels within
// half a block of px (shadowBlock) whose points lie on p's surface, their shadowed light summed over
// their unshadowed. The weights (½ at the window's rim, else 1, along each axis: ½, 1, 1, 1, ½ for
// blocks of 4) give each pixel of a block's interleaving (direct_pixels) the same weight, so that on
// a plane the sums hold every emitter sample once. The punctual lights, which every pixel
// takes whole: px's own where p lies on its surface, else their weighted mean. The lobe's
// reflection of the emitter samples: the weighted mean of the pixels' (each an estimate from its
// share of the samples); of the punctual lights: as their light. Where no pixel lies on
// p's surface (a sample on a thin sliver, or across an edge from its pixel's centre), the next ring
// of pixels out.
DirectAround directAround(uvec2 px, vec3 p, vec3 n, float tolerance) {
  const int reach = int(shadowBlock(push.samples) / 2u);
  LightSums s = LightSums(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), 0.0);
  const int ownPixel = int(px.y * push.size.x + px.x), own = 3 * ownPixel;
  const bool ownOnPlane = pixelOnPlane(own, p, n, tolerance);
  if (!sumAround(px, p, n, tolerance, 0, reach, reach, s)) sumAround(px, p, n, tolerance, reach + 1, reach + 1, 0, s);
  DirectAround d;
  d.share = vec3(s.all.r > 0.0 ? s.seen.r / s.all.r : 0.0, s.all.g > 0.0 ? s.seen.g / s.all.g : 0.0,
                 s.all.b > 0.0 ? s.seen.b / s.all.b : 0.0);
  const float weight = max(s.weight, 1e-30);  // 0 only where every sum is
  d.punctual = ownOnPlane ? imageLoad(pixelLights, own + 2).rgb : (s.weight > 0.0 ? s.punctual / s.weight : vec3(0.0));
  d.specular = vec3(0.0);
  if (kGlossy)
    d.specular = s.specular / weight +
                 (ownOnPlane ? imageLoad(pixelSpecular, 2 * ownPixel + 1).rgb : s.punctualSpecular / weight);
  return d;
}

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= push.size.x || px.y >= push.size.y) return;
  uint samples = push.samples;
  uvec2 fine = push.size * samples;
  vec3 albedo = vec3(0.0), normal = vec3(0.0), emission = vec3(0.0), reflected = vec3(0.0);
  vec2 roughMetal = vec2(0.0);
  float depth = 0.0, hits = 0.0;
  // kDirectPixels: the direct light last found around a sample and the plane it was found for, which
  // the pixel's other samples on that plane take as it is.
  DirectAround around = DirectAround(vec3(0.0), vec3(0.0), vec3(0.0));
  vec4 aroundPlane = vec4(0.0);
  for (uint sy = 0; sy < samples; ++sy)
    for (uint sx = 0; sx < samples; ++sx) {
      uvec2 s = px * samples + uvec2(sx, sy);
      const SurfaceHit h = surfaceHit(push.camera, s, fine);
      if (!h.hit) continue;
      const uvec4 t = h.triangle;
      const vec3 w = h.weights, n = h.normal;
      float len = length(n);
      const vec3 toEye = normalize(towardEye(cameraEye(push.camera), h.position));
      const vec3 face = len > 0.0 ? faceNormalOf(h, n / len) : vec3(0.0);
      const vec3 shading = len > 0.0 ? shadingNormalAt(h, n / len, face, toEye) : vec3(0.0);
      const SurfaceMaterial m = materialAt(t, w);
      const vec3 base = m.brdf.base.rgb;
      albedo += base;
      // An emitter glows on its front alone (its light leaves from there), as pt's do.
      if (dot(n, toEye) > 0.0) emission += m.emission;
      roughMetal += vec2(m.roughness, m.brdf.metallic);
      if (kLit) {
        const vec3 carried = w.x * irradianceAt(t.x) + w.y * irradianceAt(t.y) + w.z * irradianceAt(t.z);
        vec3 e = carried, direct = vec3(0.0);
        // The light the vertices carry keeps no direction: turned to the shading normal as light
        // arriving evenly over the surface's side would be, the share of that side above the
        // shading normal's horizon (a uniform sky's exactly).
        if (kNormalMapped && len > 0.0) e *= 0.5 + 0.5 * dot(n / len, shading);
        if (kDirectPixels && len > 0.0) {
          // Neighbours count within kShadowPlanePixels pixels' width of the plane, at p's distance.
          const float pixelWidth =
              2.0 * length(push.camera.up.xyz) / float(push.size.y) *
              (push.camera.up.w == kOrthographic ? 1.0
                                                 : dot(h.position - push.camera.origin.xyz, push.camera.forward.xyz));
          const float tolerance = kShadowPlanePixels * pixelWidth;
          if (!onPlane(aroundPlane, h.position, n / len, tolerance)) {
            around = directAround(px, h.position, n / len, tolerance);
            aroundPlane = vec4(n / len, dot(n / len, h.position));
          }
          vec3 unshadowed = w.x * unshadowedAt(t.x) + w.y * unshadowedAt(t.y) + w.z * unshadowedAt(t.z);
          vec3 punctual = around.punctual;
          if (kNormalMapped) {
            // The pixel's light turned from the sample's normal to its shading normal.
            const int own = int(px.y * push.size.x + px.x);
            const vec3 turn = shading - n / len;
            unshadowed = max(
                unshadowed + turnedBy(imageLoad(pixelLights, 3 * own + 1).rgb, imageLoad(pixelTurn, 2 * own).xyz, turn),
                0.0);
            punctual = max(punctual + turnedBy(imageLoad(pixelLights, 3 * own + 2).rgb,
                                               imageLoad(pixelTurn, 2 * own + 1).xyz, turn),
                           0.0);
          }
          direct = unshadowed * around.share + punctual;
        }
        if (kGlossy && !isLambertian(m.brdf) && len > 0.0) {
          // The base reflects all the light as it does uniform light; the lobe the direct light as
          // direct_pixels found it toward the camera, the rest as the solver's reflections give it
          // or as if it arrived evenly.
          const float mu = abs(dot(shading, toEye));
          const vec2 table = specularAlbedoAt(m.brdf, mu);
          // Where a normal texture turns the shading normal from the mesh's, the face's plane hides
          // part of the turned lobe: it keeps its share above the plane of the light the vertices
          // carry, or of what the solver's reflections found (at the mesh's normal, by its Fresnel).
          const float share = kNormalMapped ? lobeShareAt(face, shading, toEye, m.brdf.alpha) : 1.0;
          const vec3 indirect = share * (kReflections ? w.x * lobeAt(t.x) + w.y * lobeAt(t.y) + w.z * lobeAt(t.z)
                                                      : lobeReflectanceOf(m.brdf, table) * carried / kPi);
          reflected += baseReflectanceOf(m.brdf, table) * (e + direct) / kPi + indirect + around.specular;
        } else {
          reflected += base * (e + direct) / kPi;
        }
      }
      normal += shading;
      depth += h.depth;
      hits += 1.0;
    }
  float all = float(samples * samples);
  float nlen = length(normal);
  uint o = px.y * push.size.x + px.x;
  radiance[o] = vec4((emission + reflected) / all, hits / all);
  albedoOut[o] = vec4(albedo / all, 1.0);
  normalDepth[o] = vec4(nlen > 0.0 ? normal / nlen : vec3(0.0), hits > 0.0 ? depth / hits : 0.0);
  emissionOut[o] = vec4(emission / all, 0.0);
  roughnessMetallic[o] = vec4(roughMetal / all, 0.0, 0.0);
}

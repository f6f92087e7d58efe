#version 460
// ar, the local pass (docs/design.md §2.2): per surfel, K reflects the incident light into radiance
// (on a radiance step; an antiradiance step keeps it) and J lets the incident light go through. A
// surfel is flat: what it sends toward ω is exitance · cos⁺ − antiradiance · |cos| with its own
// normal, so it keeps its exitance (area · L) and, per bin, its antiradiance times its area, and the
// cosines are applied exactly where they are read. Where the emitters' light comes from depth maps
// (inside the irradiance), the emission is not sent: only the light the surfels reflect travels.
// A glossy leaf sends what its lobe reflects of that direct light along the lobe
// (common/send_lobe.glsl): toward each bin in front of it, the lobe's excess over that light sent
// evenly, taken off its antiradiance there, so that the clusters' tables carry it; a surfel sender
// adds it itself (ar_gather). A glossy dielectric's base leaves by its exit angle, likewise.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint kDirs = 4;  // --dirs: a constant, so that finding a bin's opposite is cheap

layout(std430, binding = 1) readonly buffer LeafOfSurfel { uint leafOfSurfel[]; };
layout(std430, binding = 2) readonly buffer Albedo { vec4 albedo[]; };
layout(std430, binding = 3) readonly buffer Emission { vec4 emission[]; };  // Le
layout(std430, binding = 4) readonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 5) buffer Radiance { vec4 radiance[]; };
layout(binding = 6, rgba32f) readonly uniform imageBuffer incident;          // per surfel and bin (looking)
layout(binding = 7, rgba32f) writeonly uniform imageBuffer intensity;        // per node and bin (travel)
layout(std430, binding = 8) writeonly buffer Exitance { vec4 exitance[]; };  // per node, area · L
layout(std430, binding = 9) readonly buffer SurfelDirect { vec4 surfelDirect[]; };
layout(std430, binding = 10) readonly buffer SurfelArrival { vec4 surfelArrival[]; };
layout(std430, binding = 11) readonly buffer SurfelBrdf { SurfaceBrdf surfelBrdf[]; };
layout(binding = 12, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(std430, binding = 13) writeonly buffer SenderLobes { vec4 senderLobes[]; };
layout(binding = 14, rgba32f) readonly uniform imageBuffer binTable;  // per bin ∫ω dω, Ω
layout(push_constant) uniform Push { ArLocalPush push; };
layout(constant_id = 28) const bool kSenderLobes = false;  // some lobe sends by direction
#include "common/send_lobe.glsl"
#include "common/sender_lobes.glsl"
#include "common/specular_albedo.glsl"

// Bin c's ∫cos dω toward normal n (its ∫ω dω against n), zero behind.
float frontOf(uint c, vec3 n) { return max(dot(n, imageLoad(binTable, int(c)).xyz), 0.0); }

// π·f(l, w)/a(l) of the leaf's lobe (send_lobe.glsl's `lobe` and `light`) toward a bin's centre w.
float lobeWeight(vec4 lobe, vec4 light, vec3 n, vec3 w, float binSolidAngle) {
  return excessAlong(vec4(1.0, 1.0, 1.0, lobe.w), light.xyz, light.w, n, w, binSolidAngle, 0.0).x + 1.0;
}

void main() {
  uint s = itemIndex();
  if (s >= push.surfelCount) return;
  const uint leaf = leafOfSurfel[s], bins = 6u * kDirs * kDirs;
  float area = nodePositionArea(leaf).w;
  vec3 L = radiance[s].rgb;
  if (push.updateRadiance != 0u) {
    L = albedo[s].rgb * irradiance[s].rgb / kPi;
    if (push.emittersByMaps == 0u) L += emission[s].rgb;
    radiance[s] = vec4(L, 0.0);
  }
  exitance[leaf] = vec4(area * L, 0.0);
  vec4 lobe = vec4(0.0), light = vec4(0.0);
  const vec3 n = nodeNormalCone(leaf).xyz;
  if (kSenderLobes) sendLobe(s, leaf, n, lobe, light);
  // What the surfel sends toward each bin in front beyond its radiance sent evenly: the lobe's
  // excess (lobeWeight's π·f/a over 1) and a glossy dielectric's base's (baseBeyondEven), each
  // scaled so that over the bins, weighed by their ∫cos dω (frontOf), it sends no more and no less:
  // taken at the bins' centres, a lobe about as wide as a bin sums to more or less than it holds as
  // its peak lies on a centre or between them.
  const SurfaceBrdf brdf = surfelBrdf[s];
  const vec4 baseShare = baseShareOf(brdf);  // the per-surfel part of baseBeyondEven, once
  const bool baseByAngle = baseShare.w > 0.0;
  const bool lobeByAngle = kSenderLobes && lobe.w > 0.0;
  const float binSolidAngle = 4.0 * kPi / float(bins);
  float front = 0.0, lobeSum = 0.0;
  vec3 baseSum = vec3(0.0);
  for (uint c = 0u; (lobeByAngle || baseByAngle) && c < bins; ++c) {
    const vec3 w = normalize(binDirection(c, kDirs));
    const float f = frontOf(c, n);
    front += f;
    if (lobeByAngle) lobeSum += lobeWeight(lobe, light, n, w, binSolidAngle) * f;
    if (baseByAngle) baseSum += (baseBeyondEven(brdf, baseShare, dot(n, w)) + 1.0) * f;
  }
  const float lobeScale = lobeSum > 0.0 ? front / lobeSum : 0.0;
  const vec3 baseScale = front / max(baseSum, vec3(1e-6));
  const vec3 reflected = max(L - (push.emittersByMaps == 0u ? emission[s].rgb : vec3(0.0)), vec3(0.0));
  for (uint c = 0u; c < bins; ++c) {
    // Antiradiance toward c: the light that arrived travelling along c, from the opposite bin.
    vec3 through =
        s < push.firstBackSurfel ? imageLoad(incident, int(s * bins + oppositeBin(c, kDirs))).rgb : vec3(0.0);
    // Less what it sends beyond even there (radiance), toward the bins in front.
    if ((lobeByAngle || baseByAngle) && frontOf(c, n) > 0.0) {
      const vec3 w = normalize(binDirection(c, kDirs));
      if (lobeByAngle) through -= lobe.rgb * (lobeScale * lobeWeight(lobe, light, n, w, binSolidAngle) - 1.0) / kPi;
      if (baseByAngle) through -= reflected * (baseScale * (baseBeyondEven(brdf, baseShare, dot(n, w)) + 1.0) - 1.0);
    }
    imageStore(intensity, int(leaf * bins + c), vec4(area * through, 0.0));
  }
}

#version 460
// iv, once a frame before the bounces (a scene with a metal), at every surfel whose lobe reflects
// most of its light (gpu::lobeDominates): the first bounce's arriving light per class of direction
// (arrival_lobes.comp), interpolated from its receivers as its irradiance is; what its lobe
// reflects of each class, sent along the lobe from the class's mean direction and widened by the
// directions' spread about it, as the direct light's is (send_lobe.glsl). Written at its leaf for
// the kArrivalLobes classes it reflects most, strongest first (common/sender_lobes.glsl's
// arrivalLobes); the others' stays in its radiosity, sent evenly, as all of a dielectric's does.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 1, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(binding = 2, r32ui) readonly uniform uimageBuffer tapCounts;
layout(binding = 3, rg32ui) readonly uniform uimageBuffer taps;  // InterpolationTap
layout(binding = 4, rgba32f) readonly uniform imageBuffer receiverArrival;
layout(binding = 5, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(std430, binding = 6) readonly buffer SurfelBrdf { SurfaceBrdf surfelBrdf[]; };
layout(std430, binding = 7) writeonly buffer ArrivalLobes { vec4 arrivalLobes[]; };  // per node
layout(push_constant) uniform Push { GatherPush push; };
#include "common/specular_albedo.glsl"

// What a class's lobe sends, and its place among the classes by that (ties by class).
float strengthOf(vec4 lobe) { return dot(lobe.rgb, vec3(1.0)); }
uint rankOf(vec4 lobes[kArrivalClasses], uint c) {
  uint rank = 0u;
  for (uint o = 0u; o < kArrivalClasses; ++o) {
    const float other = strengthOf(lobes[o]), mine = strengthOf(lobes[c]);
    rank += other > mine || (other == mine && o < c) ? 1u : 0u;
  }
  return rank;
}

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount) return;
  const SurfaceBrdf brdf = surfelBrdf[s];
  if (!lobeDominates(brdf, specularAlbedoAt(brdf, 1.0))) return;  // its texels stay zero
  const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
  const vec3 n = nodeNormalCone(leaf).xyz;
  const uint count = imageLoad(tapCounts, int(s)).x;
  vec4 irradiance[kArrivalClasses], sums[kArrivalClasses], lobes[kArrivalClasses], directions[kArrivalClasses];
  for (uint c = 0u; c < kArrivalClasses; ++c) irradiance[c] = vec4(0.0), sums[c] = vec4(0.0);
  for (uint t = 0u; t < count; ++t) {
    const uvec2 tap = imageLoad(taps, int(s * kInterpolationTaps + t)).xy;
    const float weight = uintBitsToFloat(tap.y);
    for (uint c = 0u; c < kArrivalClasses; ++c) {
      const uint from = 2u * kArrivalClasses * tap.x + 2u * c;
      irradiance[c] += weight * imageLoad(receiverArrival, int(from));
      sums[c] += weight * imageLoad(receiverArrival, int(from + 1u));
    }
  }
  for (uint c = 0u; c < kArrivalClasses; ++c) {
    const vec3 e = max(irradiance[c].rgb, vec3(0.0));  // the fit's coefficients may be negative
    const vec4 d = sums[c];
    const float r = d.w > 0.0 ? length(d.xyz) / d.w : 0.0;
    const vec3 l = r > 0.0 ? normalize(d.xyz) : n;
    const float mu = dot(n, l);
    const vec3 sent = mu > 0.0 ? lobeReflectanceOf(brdf, specularAlbedoAt(brdf, mu)) * e : vec3(0.0);
    lobes[c] = vec4(sent, any(greaterThan(sent, vec3(0.0))) ? widenedLobe(brdf, 1.0 - min(r, 1.0)).alpha : 0.0);
    directions[c] = vec4(l, 0.0);
  }
  // The classes ranked by what the lobe reflects of them, the strongest kept. The weakest kept
  // sends along its lobe only what it sends beyond the strongest left out (the rest evenly), so
  // that two classes trading places across the cut change nothing.
  const uint at = 2u * kArrivalLobes * leaf;
  uint ranks[kArrivalClasses];
  float firstLeftOut = 0.0;
  for (uint c = 0u; c < kArrivalClasses; ++c) {
    ranks[c] = rankOf(lobes, c);
    if (ranks[c] == kArrivalLobes) firstLeftOut = strengthOf(lobes[c]);
  }
  for (uint c = 0u; c < kArrivalClasses; ++c) {
    const uint rank = ranks[c];
    if (rank >= kArrivalLobes) continue;
    const float mine = strengthOf(lobes[c]);
    const float kept = rank + 1u == kArrivalLobes && mine > 0.0 ? (mine - firstLeftOut) / mine : 1.0;
    arrivalLobes[at + 2u * rank] = vec4(lobes[c].rgb * kept, lobes[c].w);
    arrivalLobes[at + 2u * rank + 1u] = directions[c];
  }
}

#version 460
// iv, once a frame before the bounces (a scene with a metal, gpu::lobeDominates), at the receivers
// the metal surfels interpolate from (mark_arrival.comp): the first
// bounce's light arriving over their surviving links (the radiosity the bounces start from, less
// the emission where the depth maps give the emitters' light), split into kArrivalClasses classes
// by the half-axis nearest its direction: per class its irradiance and the sum of its directions
// weighed by their luminance. send_arrival.comp turns them into what each glossy surfel sends along
// its lobe of that light, which would otherwise leave evenly (only the direct light's share goes
// by the lobe, send_lobe.glsl). What glossy senders send along their own lobes is taken as even
// here: on the glossy Cornell box it changed no region by 0.001.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
#include "common/parted_texels.glsl"
layout(local_size_x = kReceiverGroup) in;

layout(binding = 1, r32ui) readonly uniform uimageBuffer receivers;
layout(std430, binding = 2) readonly buffer ReceiverCounts { uint receiverCounts[]; };
layout(binding = 3, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(binding = 4, rg32ui) readonly uniform uimageBuffer ranges;                  // LeafRange
layout(binding = 5, rg32ui) readonly uniform uimageBuffer leafLinks[kTexelParts];  // LeafLink
layout(binding = 6, rg32ui) readonly uniform uimageBuffer staticRanges;            // LeafRange
layout(binding = 7, rg32ui) readonly uniform uimageBuffer staticLinks[kTexelParts];
layout(binding = 8, r32ui) readonly uniform uimageBuffer staticBins[kTexelParts];  // StaticBin
layout(binding = 9, r32ui) readonly uniform uimageBuffer overrides;                // per leaf and mask word
layout(binding = 10, rgba32f) readonly uniform imageBuffer radiosityA;             // where the bounces start
layout(binding = 11, rgba32f) readonly uniform imageBuffer nodeEmission;           // π·Le per node
// per surfel, at receivers: 2 per class, (irradiance, 0) and (Σ luminance·direction, Σ luminance)
layout(std430, binding = 12) writeonly buffer ReceiverArrival { vec4 receiverArrival[]; };
layout(binding = 13, r32ui) readonly uniform uimageBuffer arrivalTaps;  // per surfel: 1 where a metal surfel taps it
layout(push_constant) uniform Push { GatherPush push; };
#define LINK_LANES
#include "receiver_links.glsl"

// The lane's sums over the links it walks.
vec3 irradiance[kArrivalClasses];
vec4 directions[kArrivalClasses];
shared vec4 laneSumsOfClasses[kReceiverGroup][2u * kArrivalClasses];

// Files the light a link to sender q brings (f: its form factor) under its class of direction.
void file(uint q, float f, vec3 x) {
  vec3 b = imageLoad(radiosityA, int(q)).rgb;
  if (push.emittersByMaps != 0u) b -= imageLoad(nodeEmission, int(q)).rgb;
  const vec3 e = f * max(b, vec3(0.0));
  const vec3 d = nodePositionArea(q).xyz - x;
  if (!(dot(d, d) > 0.0)) return;
  const vec3 w = normalize(d), a = abs(w);
  const uint axis = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 1u : 2u);
  const uint c = 2u * axis + (w[axis] < 0.0 ? 1u : 0u);
  const vec4 direction = luminance(e) * vec4(w, 1.0);
  // Every class with a constant index, so that the sums stay in registers.
  for (uint i = 0u; i < kArrivalClasses; ++i) {
    const float on = i == c ? 1.0 : 0.0;
    irradiance[i] += on * e;
    directions[i] += on * direction;
  }
}

// The workgroup's lanes walk each tapped receiver's links together (receiver_links.glsl's
// LINK_LANES): a lane a receiver waited on the longest list of eight, and ran for the receivers
// no metal taps.
void main() {
  const uint count = receiverCounts[kReceiverCount];
  FOR_GROUP_RECEIVERS(k, 0u, count) {
    const uint s = imageLoad(receivers, int(k)).x;
    if (imageLoad(arrivalTaps, int(s)).x == 0u) continue;
    const vec3 x = nodePositionArea(imageLoad(leafOfSurfel, int(s)).x).xyz;
    for (uint c = 0u; c < kArrivalClasses; ++c) irradiance[c] = vec3(0.0), directions[c] = vec4(0.0);
    const uvec2 range = imageLoad(ranges, int(s)).xy, staticRange = imageLoad(staticRanges, int(s)).xy;
    for (uint i = range.x + linkLane(); i < range.x + range.y; i += kReceiverGroup) {
      const uvec2 link = loadParted(leafLinks, i).xy;
      file(link.x, uintBitsToFloat(link.y), x);
    }
    for (uint i = staticRange.x + linkLane(); i < staticRange.x + staticRange.y; i += kReceiverGroup) {
      const uvec2 link = loadParted(staticLinks, i).xy;
      if (staticLinkStands(s, i, push.maskWords)) file(link.x, uintBitsToFloat(link.y), x);
    }
    // The lanes' sums, in lane order: each lane sums texels `lane` and `lane` + kReceiverGroup.
    for (uint c = 0u; c < kArrivalClasses; ++c) {
      laneSumsOfClasses[linkLane()][2u * c] = vec4(irradiance[c], 0.0);
      laneSumsOfClasses[linkLane()][2u * c + 1u] = directions[c];
    }
    barrier();
    for (uint t = linkLane(); t < 2u * kArrivalClasses; t += kReceiverGroup) {
      vec4 sum = vec4(0.0);
      for (uint l = 0u; l < kReceiverGroup; ++l) sum += laneSumsOfClasses[l][t];
      receiverArrival[2u * kArrivalClasses * s + t] = sum;
    }
    barrier();
  }
}

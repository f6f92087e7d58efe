#version 460
// iv, once a frame before the bounces (a glossy scene): what the glossy leaves among each
// receiver's senders send toward it along their lobes beyond their radiosity sent evenly
// (sender_lobes.glsl), Σ F·S·(π f/a − 1) over its surviving links. It comes from the direct
// light alone, which the bounces do not change, so the gather adds it to every bounce's
// irradiance rather than weighing each link again. Also before each of the receivers' refinement
// rounds' estimates, at the round's new receivers (GatherPush::newOnly).
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
layout(binding = 10, rg32f) readonly uniform imageBuffer specularAlbedo;
layout(std430, binding = 11) writeonly buffer LobeExcess { vec4 lobeExcess[]; };  // per surfel, at receivers
layout(push_constant) uniform Push { GatherPush push; };
#include "common/specular_albedo.glsl"
#include "receiver_links.glsl"
#define SENDER_LOBES 12
#include "common/sender_lobes.glsl"

void main() {
  const uint k = (push.newOnly != 0u ? receiverCounts[kReceiverRound] : 0u) + itemIndex();
  if (k >= receiverCounts[kReceiverCount]) return;
  const uint s = imageLoad(receivers, int(k)).x;
  const vec3 at = nodePositionArea(imageLoad(leafOfSurfel, int(s)).x).xyz;
  vec3 excess = vec3(0.0);
  const uvec2 range = imageLoad(ranges, int(s)).xy, staticRange = imageLoad(staticRanges, int(s)).xy;
  for (uint i = range.x; i < range.x + range.y; ++i) {
    const uvec2 link = loadParted(leafLinks, i).xy;
    excess += uintBitsToFloat(link.y) * excessToward(link.x, at, 0.0, push.leastSpread);
  }
  for (uint i = staticRange.x; i < staticRange.x + staticRange.y; ++i) {
    const uvec2 link = loadParted(staticLinks, i).xy;
    if (staticLinkStands(s, i, push.maskWords))
      excess += uintBitsToFloat(link.y) * excessToward(link.x, at, 0.0, push.leastSpread);
  }
  lobeExcess[s] = vec4(excess, 0.0);
}

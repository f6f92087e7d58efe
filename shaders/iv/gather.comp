#version 460
// iv's gather at the receivers: irradiance G = external + Σ F·B_sender over their surviving
// links, from the radiosity the last bounce left (or, for the receivers' refinement, an estimate of
// it). A static leaf also has the links pruned once against static senders, less those its frame
// links override.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
#include "common/parted_texels.glsl"
layout(local_size_x = kReceiverGroup) in;

layout(binding = 0, r32ui) readonly uniform uimageBuffer receivers;
layout(std430, binding = 1) buffer ReceiverCounts { uint receiverCounts[]; };
layout(binding = 2, rg32ui) readonly uniform uimageBuffer ranges;                  // LeafRange
layout(binding = 3, rg32ui) readonly uniform uimageBuffer leafLinks[kTexelParts];  // LeafLink: sender, form-factor bits
layout(binding = 4, rgba32f) readonly uniform imageBuffer externalLight;
layout(binding = 5, rgba32f) readonly uniform imageBuffer radiosityIn;
layout(std430, binding = 6) writeonly buffer Gathered { vec4 gathered[]; };          // per surfel
layout(binding = 7, rg32ui) readonly uniform uimageBuffer staticRanges;              // LeafRange
layout(binding = 8, rg32ui) readonly uniform uimageBuffer staticLinks[kTexelParts];  // LeafLink
layout(binding = 9, r32ui) readonly uniform uimageBuffer staticBins[kTexelParts];    // StaticBin
layout(binding = 10, r32ui) readonly uniform uimageBuffer overrides;                 // per leaf and mask word
layout(std430, binding = 11) readonly buffer FrameCounters { uint frameCounters[]; };
layout(std430, binding = 12) readonly buffer StaticCounters { uint staticCounters[]; };
layout(push_constant) uniform Push { GatherPush push; };
#include "receiver_links.glsl"

void main() {
  const uint first = push.newOnly != 0u ? receiverCounts[kReceiverRound] : 0u;
  const uint k = first + itemIndex();
  // A frame that overflowed (links, leaf links, a prune's loop budget) is redone: its bounces would be wasted.
  if (k >= receiverCounts[kReceiverCount] || (frameCounters[kCounterOverflow] | staticCounters[kCounterOverflow]) != 0u)
    return;
  const uint s = imageLoad(receivers, int(k)).x;
  uvec2 range = imageLoad(ranges, int(s)).xy;
  vec3 g = imageLoad(externalLight, int(s)).rgb;
  for (uint i = range.x; i < range.x + range.y; ++i) {
    uvec2 link = loadParted(leafLinks, i).xy;
    g += uintBitsToFloat(link.y) * imageLoad(radiosityIn, int(link.x)).rgb;
  }
  uvec2 staticRange = imageLoad(staticRanges, int(s)).xy;
  for (uint i = staticRange.x; i < staticRange.x + staticRange.y; ++i) {
    uvec2 link = loadParted(staticLinks, i).xy;
    if (staticLinkStands(s, i, push.maskWords)) g += uintBitsToFloat(link.y) * imageLoad(radiosityIn, int(link.x)).rgb;
  }
  gathered[s] = vec4(g, 0.0);
  // The largest estimate, for the receivers' refinement (non-negative float bits order as integers;
  // one counter every thread shares, so the bounces leave it).
  if (push.newOnly != 0u)
    atomicMax(receiverCounts[kReceiverScale], floatBitsToUint(dot(g, vec3(0.2126, 0.7152, 0.0722))));
}

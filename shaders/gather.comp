#version 460
// Pass 6b, gather at the leaves: irradiance G = external + Σ F·B_sender over the surviving links,
// radiosity B = π·Le + ρ·G. Reads last bounce's radiosity, writes the next (no race). A static leaf
// also has the links pruned once against static senders, less those its frame links override.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 15
#include "common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(binding = 1, rg32ui) readonly uniform uimageBuffer ranges;     // LeafRange
layout(binding = 2, rg32ui) readonly uniform uimageBuffer leafLinks;  // LeafLink: sender, form-factor bits
layout(binding = 3, rgba32f) readonly uniform imageBuffer externalLight;
layout(binding = 4, rgba32f) readonly uniform imageBuffer albedo;
layout(binding = 5, rgba32f) readonly uniform imageBuffer emission;
layout(binding = 6, rgba32f) readonly uniform imageBuffer radiosityIn;
layout(std430, binding = 7) writeonly buffer RadiosityOut { vec4 radiosityOut[]; };
layout(std430, binding = 8) writeonly buffer Irradiance { vec4 irradiance[]; };
layout(binding = 9, rg32ui) readonly uniform uimageBuffer staticRanges;  // LeafRange
layout(binding = 10, rg32ui) readonly uniform uimageBuffer staticLinks;  // LeafLink
layout(binding = 11, r32ui) readonly uniform uimageBuffer staticBins;    // StaticBin
layout(binding = 12, r32ui) readonly uniform uimageBuffer overrides;     // per leaf and mask word
layout(std430, binding = 13) readonly buffer FrameCounters { uint frameCounters[]; };
layout(std430, binding = 14) readonly buffer StaticCounters { uint staticCounters[]; };
layout(std430, binding = 16) writeonly buffer BounceSums { BounceSum bounceSums[]; };  // per workgroup
layout(push_constant) uniform Push { GatherPush push; };

shared BounceSum partial[64];

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// Leaves the workgroup's sum for bounce_check, added in a fixed order.
void sumBounce(BounceSum mine) {
  const uint lid = gl_LocalInvocationID.x;
  partial[lid] = mine;
  barrier();
  if (lid == 0u) {
    BounceSum sum = BounceSum(0.0, 0.0);
    for (uint i = 0u; i < 64u; ++i) sum.total += partial[i].total, sum.change += partial[i].change;
    bounceSums[groupIndex()] = sum;
  }
}

// The leaf's new radiosity and irradiance; none (zeros for the sums) past the surfels or in a frame
// that overflowed.
BounceSum gatherLeaf(uint s) {
  // A frame that overflowed (links, leaf links, a prune's loop budget) is redone: its bounces would be wasted.
  if (s >= push.surfelCount || (frameCounters[kCounterOverflow] | staticCounters[kCounterOverflow]) != 0u)
    return BounceSum(0.0, 0.0);
  uvec2 range = imageLoad(ranges, int(s)).xy;
  vec3 g = imageLoad(externalLight, int(s)).rgb;
  for (uint k = range.x; k < range.x + range.y; ++k) {
    uvec2 link = imageLoad(leafLinks, int(k)).xy;
    g += uintBitsToFloat(link.y) * imageLoad(radiosityIn, int(link.x)).rgb;
  }
  uvec2 staticRange = imageLoad(staticRanges, int(s)).xy;
  for (uint k = staticRange.x; k < staticRange.x + staticRange.y; ++k) {
    uvec2 link = imageLoad(staticLinks, int(k)).xy;
    uint bin = staticBinOf(imageLoad(staticBins, int(k)).x);
    uint overridden = imageLoad(overrides, int(s * push.maskWords + bin / 32u)).x & (1u << (bin & 31u));
    if (overridden == 0u) g += uintBitsToFloat(link.y) * imageLoad(radiosityIn, int(link.x)).rgb;
  }
  const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
  const vec3 b = kPi * imageLoad(emission, int(s)).rgb + imageLoad(albedo, int(s)).rgb * g;
  radiosityOut[leaf] = vec4(b, 0.0);
  irradiance[s] = vec4(g, 0.0);
  const float area = nodePositionArea(leaf).w;
  return BounceSum(area * luminance(b), area * abs(luminance(b) - luminance(imageLoad(radiosityIn, int(leaf)).rgb)));
}

void main() { sumBounce(gatherLeaf(itemIndex())); }

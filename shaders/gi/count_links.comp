#version 460
// Link creation, after the refinement: links per receiver node, to sort the links by receiver.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = kLinkGroup) in;

layout(binding = 0, rg32ui) readonly uniform uimageBuffer links;  // receiver, sender
layout(std430, binding = 1) buffer Counts { uint counts[]; };
layout(std430, binding = 2) readonly buffer Counters { uint counters[]; };
layout(push_constant) uniform Push { SortLinksPush push; };

void main() {
  uint total = min(counters[kCounterLinks], push.linkCapacity);
  uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint k = gl_GlobalInvocationID.x; k < total; k += stride) atomicAdd(counts[imageLoad(links, int(k)).x], 1u);
}

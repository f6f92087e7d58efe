#version 460
// Link creation, last: senders sorted by receiver. The order inside a receiver's list varies run to
// run; the pruning after it keeps the nearest per bin by key, which does not depend on that order.
// A sender that emits is marked (kEmitterBit), so that the pruning lists it without reading its
// emission.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = kLinkGroup) in;

layout(binding = 0, rg32ui) readonly uniform uimageBuffer links;    // receiver, sender
layout(std430, binding = 1) buffer Counts { uint cursors[]; };      // the scan made the counts cursors
layout(binding = 2, r32ui) writeonly uniform uimageBuffer senders;  // texels: past one storage binding
layout(std430, binding = 3) readonly buffer Counters { uint counters[]; };
layout(binding = 4, rgba32f) readonly uniform imageBuffer emitters;  // nonzero: the node emits
layout(push_constant) uniform Push { SortLinksPush push; };

void main() {
  uint total = min(counters[kCounterLinks], push.linkCapacity);
  uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint k = gl_GlobalInvocationID.x; k < total; k += stride) {
    uvec2 link = imageLoad(links, int(k)).xy;
    bool emits = any(greaterThan(imageLoad(emitters, int(link.y)).rgb, vec3(0.0)));
    imageStore(senders, int(atomicAdd(cursors[link.x], 1u)), uvec4(link.y | (emits ? kEmitterBit : 0u)));
  }
}

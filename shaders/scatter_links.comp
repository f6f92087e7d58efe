#version 460
// Pass 4d: senders sorted by receiver. The order inside a receiver's list varies run to run; the
// pruning after it keeps the nearest per bin by key, which does not depend on that order.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 256) in;

layout(binding = 0, rg32ui) readonly uniform uimageBuffer links;  // receiver, sender
layout(std430, binding = 1) buffer Cursors { uint cursors[]; };
layout(std430, binding = 2) writeonly buffer Senders { uint senders[]; };
layout(std430, binding = 3) readonly buffer Counters { uint counters[]; };
layout(push_constant) uniform Push { uint linkCapacity; };

void main() {
  uint total = min(counters[kCounterLinks], linkCapacity);
  uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint k = gl_GlobalInvocationID.x; k < total; k += stride) senders[atomicAdd(cursors[imageLoad(links, int(k)).x], 1u)] = imageLoad(links, int(k)).y;
}

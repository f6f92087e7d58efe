#version 460
// Worklist bookkeeping between two refinement levels: the indirect dispatch size for the list just
// written, the longest list so far, and a zeroed counter for the next one.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 1) in;

layout(std430, binding = 0) buffer Counters { uint counters[]; };
layout(std430, binding = 1) writeonly buffer Args { uvec4 args[]; };
layout(push_constant) uniform Push { LinkArgsPush push; };

void main() {
  uint items = counters[push.source];
  // A worklist's length, counted past its capacity too: the room the next frame's lists need.
  if (push.source == kCounterWorklistA || push.source == kCounterWorklistB)
    counters[kCounterWorklistPeak] = max(counters[kCounterWorklistPeak], items);
  args[push.slot] = uvec4(min((items + push.groupSize - 1u) / push.groupSize, 65535u), 1u, 1u, 0u);
  if (push.clear != kNoCounter) counters[push.clear] = 0u;
}

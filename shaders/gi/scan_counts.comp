#version 460
// Link creation, after count_links: exclusive prefix sum of the per-node link counts (one
// workgroup: nodes are few), giving each receiver's first slot; the counts become write cursors.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 256) in;

layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 1) writeonly buffer Starts { uint starts[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: nodes

shared uint partial[256];

void main() {
  uint t = gl_LocalInvocationID.x;
  uint nodeCount = push.count, chunk = (nodeCount + 255u) / 256u, begin = t * chunk,
       end = min(begin + chunk, nodeCount);
  uint sum = 0u;
  for (uint i = begin; i < end; ++i) sum += counts[i];
  partial[t] = sum;
  barrier();
  if (t == 0u) {
    uint running = 0u;
    for (uint i = 0u; i < 256u; ++i) {
      uint v = partial[i];
      partial[i] = running;
      running += v;
    }
  }
  barrier();
  uint running = partial[t];
  for (uint i = begin; i < end; ++i) {
    uint c = counts[i];
    starts[i] = running;
    counts[i] = running;  // cursor for the scatter
    running += c;
  }
  if (t == 255u) starts[nodeCount] = running;
}

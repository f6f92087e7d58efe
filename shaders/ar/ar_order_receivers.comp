#version 460
// ar: the order the global pass takes its receivers in. An invocation walks its receiver's list,
// and the lanes that run together wait for the longest among them; so within each workgroup's
// nodes (kept together: neighbouring nodes read the same senders' tables), longest list first.
// One workgroup a block of the global pass's workgroup size; a node's place is the number of nodes
// of its block before it in that order (ties by index).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = kArGatherGroup) in;

layout(std430, binding = 0) readonly buffer StaticStarts { uint staticStarts[]; };
layout(std430, binding = 1) readonly buffer Starts { uint starts[]; };
layout(std430, binding = 2) writeonly buffer GatherOrder { uint gatherOrder[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: nodes

shared uint links[kArGatherGroup];

void main() {
  uint lid = gl_LocalInvocationID.x, first = groupIndex() * kArGatherGroup, node = first + lid;
  uint size = min(kArGatherGroup, push.count - min(first, push.count));
  if (size == 0u) return;
  links[lid] = node < push.count ? staticStarts[node + 1u] - staticStarts[node] + starts[node + 1u] - starts[node] : 0u;
  barrier();
  if (lid >= size) return;
  uint place = 0u, mine = links[lid];
  for (uint j = 0u; j < size; ++j) place += links[j] > mine || (links[j] == mine && j < lid) ? 1u : 0u;
  gatherOrder[first + place] = node;
}

#version 460
// The nodes the image sees: those above a surfel whose value it reads (kShownFit). The receivers'
// refinement judges the rest at --unseen-tol: their light reaches the image only after a bounce.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(std430, binding = 2) readonly buffer ShownSurfels { uint shownSurfels[]; };
layout(std430, binding = 3) buffer SeenNodes { uint seenNodes[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: surfels

void main() {
  const uint s = itemIndex();
  if (s >= push.count || (shownSurfels[s] & kShownFit) == 0u) return;
  // A node marked already has its ancestors marked, or being marked by the surfel that marked it.
  for (int node = int(imageLoad(leafOfSurfel, int(s)).x); node >= 0; node = int(imageLoad(tree, node).x))
    if (atomicExchange(seenNodes[node], 1u) != 0u) break;
}

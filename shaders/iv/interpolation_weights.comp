#version 460
// Interpolation weights, step 2, per surfel (docs/design.md §2.4): the linear fit through the
// receivers of the sampled nodes whose support holds it, weighed by their roles (receivers.glsl; a
// receiver is all but its own value), among the nodes its group lists (neighbour_lists.comp), or
// where the group has too many to list, found by its own walk of the trees. A surfel that none holds
// takes the irradiance of a receiver made for it (a fill, listed for the prune where it was not
// one): the coarsest node between it and the sampled ancestor that missed it whose support holds
// it, else its own.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 3
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, rg32f) readonly uniform imageBuffer reach;     // reach, least cosine
layout(binding = 9, r32ui) readonly uniform uimageBuffer skip;
layout(binding = 2, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(std430, binding = 4) buffer ReceiverRadius { uint receiverRadius[]; };
layout(std430, binding = 5) buffer ReceiverCounts { uint receiverCounts[]; };
layout(std430, binding = 6) writeonly buffer Receivers { uint receivers[]; };
layout(std430, binding = 7) writeonly buffer TapCounts { uint tapCounts[]; };
layout(binding = 8, rg32ui) writeonly uniform uimageBuffer taps;  // InterpolationTap
layout(binding = 10, r32ui) readonly uniform uimageBuffer groupOfSurfel;
layout(binding = 11, r32ui) readonly uniform uimageBuffer neighbourCounts;
layout(binding = 12, r32ui) readonly uniform uimageBuffer neighbours;
layout(binding = 13, r32ui) readonly uniform uimageBuffer representatives;
layout(binding = 14, r32f) readonly uniform imageBuffer roles;
layout(binding = 15, r32ui) readonly uniform uimageBuffer surfelBuried;  // not 0: buried (kBuried, kBuriedInItself)
layout(binding = 16, r32f) readonly uniform imageBuffer presences;       // 0 where not sampled
layout(push_constant) uniform Push { ReceiverPush push; };

#include "receivers.glsl"

// Whether the surfel interpolated lies inside another object (buried_surfels).
bool buriedHere = false;

// Node q's receiver, weighing for x (normal n; t1, t2 its tangents) with q's support and role. A
// receiver inside another object (under a block standing on the floor) weighs only for surfels
// inside too: its light is not that of the surface outside.
void considerNode(uint q, vec3 x, vec3 n, vec3 t1, vec3 t2) {
  const uint s = imageLoad(representatives, int(q)).x;
  if (!buriedHere && imageLoad(surfelBuried, int(s)).x != 0u) return;
  considerReceiver(s, imageLoad(leafOfSurfel, int(s)).x, kReceiverReach * nodeRadius(q), imageLoad(roles, int(q)).x, x,
                   n, t1, t2);
}

// Every node whose receiver may weigh for x (normal n), in the trees' order.
void gatherTaps(vec3 x, vec3 n, vec3 t1, vec3 t2) {
  for (uint node = 0u; node < push.nodeCount;) {
    const vec2 r = imageLoad(reach, int(node)).xy;  // reach, least cosine
    if (r.x < 0.0 || distance(nodePositionArea(node).xyz, x) > r.x || dot(n, nodeNormalCone(node).xyz) < r.y) {
      node = imageLoad(skip, int(node)).x;
      continue;
    }
    if (imageLoad(roles, int(node)).x > 0.0) considerNode(node, x, n, t1, t2);
    const uvec4 t = imageLoad(tree, int(node));  // parent, firstChild, childCount, surfel
    node = t.z != 0u ? t.y : imageLoad(skip, int(node)).x;
  }
}

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount) return;
  const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
  tapCount = 0u;
  buriedHere = imageLoad(surfelBuried, int(s)).x != 0u;
  const vec3 x = nodePositionArea(leaf).xyz, n = nodeNormalCone(leaf).xyz;
  vec3 t1, t2;
  tangentFrame(n, t1, t2);
  const uint k = imageLoad(groupOfSurfel, int(s)).x, listed = imageLoad(neighbourCounts, int(k)).x;
  if (listed <= kGroupNeighbours)
    for (uint i = 0u; i < listed; ++i)
      considerNode(imageLoad(neighbours, int(k * kGroupNeighbours + i)).x, x, n, t1, t2);
  else
    gatherTaps(x, n, t1, t2);
  if (tapCount > 0u) {
    fitCoefficients(true);
    FOR_TAPS(t)
    imageStore(taps, int(s * kInterpolationTaps + t), uvec4(tapReceiver[t], floatBitsToUint(tapWeight[t]), 0u, 0u));
    tapCounts[s] = tapCount;
    return;
  }
  // No receiver weighs for it. The refinement left it to a sampled ancestor whose support misses
  // it (on a curved surface, its normal turned past the kernel's or its place off the receiver's
  // plane): a node between the two, the coarsest whose own support holds it, stands for it as a
  // receiver (its representative), so that the surfels it holds share one prune; where none does,
  // the surfel takes its own irradiance.
  uint r = s, node = imageLoad(tree, int(leaf)).x;
  float support = kReceiverReach * nodeRadius(leaf);
  for (; node != 0xFFFFFFFFu && imageLoad(presences, int(node)).x <= 0.0; node = imageLoad(tree, int(node)).x) {
    const uint q = imageLoad(representatives, int(node)).x, at = imageLoad(leafOfSurfel, int(q)).x;
    const float reach = kReceiverReach * nodeRadius(node);
    if ((imageLoad(surfelBuried, int(q)).x != 0u) == buriedHere &&
        receiverWeight(x, n, nodePositionArea(at).xyz, nodeNormalCone(at).xyz, reach) > 0.0)
      r = q, support = reach;
  }
  if (atomicMin(receiverRadius[r], floatBitsToUint(support)) == kNotReceiver) {
    receivers[atomicAdd(receiverCounts[kReceiverCount], 1u)] = r;
    atomicAdd(receiverCounts[kReceiverFills], 1u);
  }
  imageStore(taps, int(s * kInterpolationTaps), uvec4(r, floatBitsToUint(1.0), 0u, 0u));
  tapCounts[s] = 1u;
}

#version 460
// Receivers' refinement, step 1 of a round (docs/design.md §2.4): the representative surfel of every
// child of a candidate node becomes a receiver, standing for the child, and the child gets its
// presence; the receiver's support reaches kReceiverReach times the child's radius (the least where
// it stands for several nested nodes). Each receiver is listed once, where it first becomes one.
// The last workgroup sizes the dispatches over the receivers listed.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 5
#include "common/common.glsl"
layout(local_size_x = kReceiverGroup) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, r32ui) readonly uniform uimageBuffer representatives;
layout(binding = 2, r32ui) readonly uniform uimageBuffer candidatesIn;
layout(std430, binding = 3) coherent buffer ReceiverCounts { uint receiverCounts[]; };
layout(std430, binding = 4) buffer ReceiverRadius { uint receiverRadius[]; };  // float bits; kNotReceiver
layout(std430, binding = 6) writeonly buffer Receivers { uint receivers[]; };
layout(binding = 7, r32f) readonly uniform imageBuffer needs;
layout(std430, binding = 8) buffer Presences { float presences[]; };
layout(std430, binding = 9) writeonly buffer ReceiverArgs { uvec4 receiverArgs[]; };
layout(push_constant) uniform Push { ReceiverPush push; };
#include "receiver_args.glsl"

void selectChildren() {
  const uint k = itemIndex();
  if (k >= receiverCounts[push.source]) return;
  const uint node = imageLoad(candidatesIn, int(k)).x;
  const uvec4 t = imageLoad(tree, int(node));
  // The children's presence: the candidate's share of its own (a root passes all of its on).
  const float presence = t.x == 0xFFFFFFFFu ? 1.0 : presences[node] * refinementShare(imageLoad(needs, int(node)).x);
  for (uint c = t.y; c < t.y + t.z; ++c) {
    presences[c] = presence;
    const uint s = imageLoad(representatives, int(c)).x;
    if (atomicMin(receiverRadius[s], floatBitsToUint(kReceiverReach * nodeRadius(c))) == kNotReceiver)
      receivers[atomicAdd(receiverCounts[kReceiverCount], 1u)] = s;
  }
}

void main() {
  selectChildren();
  ONLY_IN_THE_LAST_WORKGROUP(receiverCounts[kReceiverGroupsDone]);
  receiversListed(push.batch, push.leavesPerGroup, push.maxGroups, push.batches);
}

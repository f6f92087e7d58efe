#version 460
// Receivers' bookkeeping where no step of a round writes it (receiver_args.glsl): the fills, and
// every surfel a receiver.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 1) in;

layout(std430, binding = 0) buffer ReceiverCounts { uint receiverCounts[]; };
layout(std430, binding = 1) writeonly buffer ReceiverArgs { uvec4 receiverArgs[]; };
layout(push_constant) uniform Push { ReceiverArgsPush push; };
#include "receiver_args.glsl"

void main() {
  if ((push.mode & kArgsStartRound) != 0u) startRound(push.source, push.target);
  if ((push.mode & kArgsListed) != 0u) receiversListed(push.batch, push.leavesPerGroup, push.maxGroups, push.batches);
}

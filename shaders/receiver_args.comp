#version 460
// Receivers' bookkeeping between the steps of a refinement round (docs/design.md §2.4): the dispatch
// sizes for the round's candidates, for its new receivers (one prune batch after another) and for
// every receiver; where a round starts, its receivers are those listed from here on.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 1) in;

layout(std430, binding = 0) buffer ReceiverCounts { uint receiverCounts[]; };
layout(std430, binding = 1) writeonly buffer ReceiverArgs { uvec4 receiverArgs[]; };
layout(push_constant) uniform Push { ReceiverArgsPush push; };

void main() {
  if ((push.mode & kArgsStartRound) != 0u) {
    receiverArgs[kArgsCandidates] = groupsFor(receiverCounts[push.source], kReceiverGroup);
    receiverCounts[push.target] = 0u;
    receiverCounts[kReceiverRound] = receiverCounts[kReceiverCount];
  }
  if ((push.mode & kArgsListed) != 0u) {
    const uint all = receiverCounts[kReceiverCount], fresh = all - receiverCounts[kReceiverRound];
    receiverArgs[kArgsNewReceivers] = groupsFor(fresh, kReceiverGroup);
    receiverArgs[kArgsReceivers] = groupsFor(all, kReceiverGroup);
    for (uint b = 0u; b < push.batches; ++b) {
      const uint left = fresh > b * push.batch ? min(fresh - b * push.batch, push.batch) : 0u;
      receiverArgs[kArgsPruneBatches + b] =
          uvec4(min((left + push.leavesPerGroup - 1u) / push.leavesPerGroup, push.maxGroups), 1u, 1u, 0u);
    }
  }
}

#version 460
// iv, once a frame before the bounces (where some lobe sends by direction): what the glossy leaves
// among each receiver's senders send toward it along their lobes beyond their radiosity sent evenly
// (sender_lobes.glsl), Σ F·S·(π f/a − 1) over its surviving links. It comes from the direct
// light alone, which the bounces do not change, so the gather adds it to every bounce's
// irradiance rather than weighing each link again. Also before each of the receivers' refinement
// rounds' estimates, at the round's new receivers (GatherPush::newOnly). With kArrival (once a
// frame), also the same of what they send along their lobes of the first bounce's light
// (send_arrival.comp), which the gather adds from the second bounce on.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#define NODE_TEXELS 0
#include "common/common.glsl"
#include "common/parted_texels.glsl"
layout(local_size_x = kReceiverGroup) in;

layout(binding = 1, r32ui) readonly uniform uimageBuffer receivers;
layout(std430, binding = 2) readonly buffer ReceiverCounts { uint receiverCounts[]; };
layout(binding = 3, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(binding = 4, rg32ui) readonly uniform uimageBuffer ranges;                  // LeafRange
layout(binding = 5, rg32ui) readonly uniform uimageBuffer leafLinks[kTexelParts];  // LeafLink
layout(binding = 6, rg32ui) readonly uniform uimageBuffer staticRanges;            // LeafRange
layout(binding = 7, rg32ui) readonly uniform uimageBuffer staticLinks[kTexelParts];
layout(binding = 8, r32ui) readonly uniform uimageBuffer staticBins[kTexelParts];  // StaticBin
layout(binding = 9, r32ui) readonly uniform uimageBuffer overrides;                // per leaf and mask word
layout(binding = 10, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(std430, binding = 11) writeonly buffer LobeExcess { vec4 lobeExcess[]; };        // per surfel, at receivers
layout(std430, binding = 14) writeonly buffer ArrivalExcess { vec4 arrivalExcess[]; };  // the same, kArrival
layout(push_constant) uniform Push { GatherPush push; };
#include "common/specular_albedo.glsl"
#define LINK_LANES
#include "receiver_links.glsl"
#define SENDER_LOBES 12
#define ARRIVAL_LOBES 13
#include "common/sender_lobes.glsl"
layout(constant_id = 27) const bool kArrival = false;

// Adds what sender q sends toward x along its lobes, weighed by form factor f.
void addLobes(uint q, vec3 x, float f, inout vec3 excess, inout vec3 arrival) {
  if (!kArrival) {
    excess += f * excessToward(q, x, 0.0, push.leastSpread);
    return;
  }
  const vec4 lobe = imageLoad(senderLobes, int(2u * q)), first = imageLoad(arrivalLobes, int(2u * kArrivalLobes * q));
  vec3 n, w;
  float widening;
  if (!(lobe.w > 0.0 || first.w > 0.0) || !senderToward(q, x, 0.0, n, w, widening)) return;
  if (lobe.w > 0.0) {
    const vec4 light = imageLoad(senderLobes, int(2u * q + 1u));
    excess += f * excessAlong(lobe, light.xyz, light.w, n, w, widening, push.leastSpread);
  }
  arrival += f * arrivalAlong(q, first, n, w, widening, push.leastSpread);
}

// A CPU device runs the body of a branch for all of a subgroup's lanes, masked, whichever take it:
// weighed in the walk, every link would cost the lobes. So the walk gathers the links whose sender
// sends by direction into a batch, in lane order, and a loop of their own weighs them, a lane each.
const uint kLobeBatch = 32u * kReceiverGroup;
shared uvec2 lobeBatch[kLobeBatch];
// Where the workgroup spans subgroups: the lanes that batched a link in a round, a word a round,
// three in turn, so that the word of the round after next is cleared while this round's is read.
shared uint batchedLanes[3];

bool sendsByDirection(uint q) {
  return (kSenderLobes && imageLoad(senderLobes, int(2u * q)).w > 0.0) ||
         (kArrival && imageLoad(arrivalLobes, int(2u * kArrivalLobes * q)).w > 0.0);
}

// The lanes' writes to the batch seen by every lane; every lane calls it.
void batchBarrier() {
  if (groupInOneSubgroup) {
    subgroupMemoryBarrierShared();
    subgroupBarrier();
  } else {
    barrier();
  }
}

// Adds link to the batch where `lobed`; `batched` (the same in every lane) grows by the lanes that
// did. Every lane calls it, `round` counting its calls.
void batchLink(bool lobed, uvec2 link, inout uint batched, inout uint round) {
  uint before, count;
  if (groupInOneSubgroup) {
    const uvec4 lanes = subgroupBallot(lobed);
    before = subgroupBallotExclusiveBitCount(lanes), count = subgroupBallotBitCount(lanes);
  } else {
    const uint word = round++ % 3u, lane = linkLane();
    if (lobed) atomicOr(batchedLanes[word], 1u << lane);
    if (lane == 0u) batchedLanes[(word + 1u) % 3u] = 0u;
    barrier();
    const uint lanes = batchedLanes[word];
    before = bitCount(lanes & ((1u << lane) - 1u)), count = bitCount(lanes);
  }
  if (lobed) lobeBatch[batched + before] = link;
  batched += count;
}

void main() {
  if (linkLane() < 3u) batchedLanes[linkLane()] = 0u;
  barrier();
  uint round = 0u;
  const uint count = receiverCounts[kReceiverCount];
  FOR_GROUP_RECEIVERS(k, push.newOnly != 0u ? receiverCounts[kReceiverRound] : 0u, count) {
    const uint s = imageLoad(receivers, int(k)).x;
    const vec3 at = nodePositionArea(imageLoad(leafOfSurfel, int(s)).x).xyz;
    vec3 excess = vec3(0.0), arrival = vec3(0.0);
    const uvec2 range = imageLoad(ranges, int(s)).xy, staticRange = imageLoad(staticRanges, int(s)).xy;
    const uint end = range.x + range.y, staticEnd = staticRange.x + staticRange.y;
    uint next = range.x, nextStatic = staticRange.x;
    while (next < end || nextStatic < staticEnd) {
      uint batched = 0u;
      for (; next < end && batched + kReceiverGroup <= kLobeBatch; next += kReceiverGroup) {
        const uint i = next + linkLane();
        const uvec2 link = i < end ? loadParted(leafLinks, i).xy : uvec2(0u);
        batchLink(i < end && sendsByDirection(link.x), link, batched, round);
      }
      for (; nextStatic < staticEnd && batched + kReceiverGroup <= kLobeBatch; nextStatic += kReceiverGroup) {
        const uint i = nextStatic + linkLane();
        const uvec2 link = i < staticEnd ? loadParted(staticLinks, i).xy : uvec2(0u);
        const bool lobed = i < staticEnd && sendsByDirection(link.x) && staticLinkStands(s, i, push.maskWords);
        batchLink(lobed, link, batched, round);
      }
      batchBarrier();
      for (uint j = linkLane(); j < batched; j += kReceiverGroup) {
        const uvec2 link = lobeBatch[j];
        addLobes(link.x, at, uintBitsToFloat(link.y), excess, arrival);
      }
      batchBarrier();  // read before the next batch overwrites it
    }
    sumLanes(excess, arrival);
    if (linkLane() == 0u) {
      lobeExcess[s] = vec4(excess, 0.0);
      if (kArrival) arrivalExcess[s] = vec4(arrival, 0.0);
    }
  }
}

#version 460
// iv (where some lobe sends by direction): what the glossy leaves among each receiver's senders send
// toward it along their lobes beyond their radiosity sent evenly (sender_lobes.glsl), Σ F·S·(π f/a
// − 1) over its surviving links. It comes from the direct light alone, which the bounces do not
// change, so the gather adds it to every bounce's irradiance rather than weighing each link again.
// At each of the receivers' refinement rounds' estimates, at the round's new receivers
// (GatherPush::newOnly); where no round ran (every surfel a receiver), once before the bounces.
// With kArrival (once a frame before the bounces), also the same of what they send along their
// lobes of the first bounce's light (send_arrival.comp), which the gather adds from the second
// bounce on: that alone where the estimates left the rest (GatherPush::directKnown).
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
#define LINK_BATCHES
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
  if (lobe.w > 0.0 && push.directKnown == 0u) {
    const vec4 light = imageLoad(senderLobes, int(2u * q + 1u));
    excess += f * excessAlong(lobe, light.xyz, light.w, n, w, widening, push.leastSpread);
  }
  arrival += f * arrivalAlong(q, first, n, w, widening, push.leastSpread);
}

// The lane's sums over the links it weighs, of the receiver being walked, toward its centre.
vec3 excessSum, arrivalSum, receiverAt;

// Only the links whose sender sends by direction weigh a lobe: batched.
bool visitLink(uvec2 link) {
  return (kSenderLobes && push.directKnown == 0u && imageLoad(senderLobes, int(2u * link.x)).w > 0.0) ||
         (kArrival && imageLoad(arrivalLobes, int(2u * kArrivalLobes * link.x)).w > 0.0);
}
void batchedLink(uvec2 link) { addLobes(link.x, receiverAt, uintBitsToFloat(link.y), excessSum, arrivalSum); }

void main() {
  const uint count = receiverCounts[kReceiverCount];
  FOR_GROUP_RECEIVERS(k, push.newOnly != 0u ? receiverCounts[kReceiverRound] : 0u, count) {
    const uint s = imageLoad(receivers, int(k)).x;
    receiverAt = nodePositionArea(imageLoad(leafOfSurfel, int(s)).x).xyz;
    excessSum = arrivalSum = vec3(0.0);
    walkLinksInBatches(s);
    sumLanes(excessSum, arrivalSum);
    if (linkLane() == 0u) {
      if (push.directKnown == 0u) lobeExcess[s] = vec4(excessSum, 0.0);
      if (kArrival) arrivalExcess[s] = vec4(arrivalSum, 0.0);
    }
  }
}

#version 460
// iv's gather at the receivers: irradiance G = external + Σ F·B_sender over their surviving
// links, from the radiosity the last bounce left (or, for the receivers' refinement, an estimate of
// it). A static leaf also has the links pruned once against static senders, less those its frame
// links override. With the estimate, its rotation gradient (Ward and Heckbert 1992): how G changes
// as the receiver's normal turns, Σ F/cos θ·B·(n × ω) over the senders' directions ω, so that a
// surfel whose normal differs from its receivers' takes the light its own normal faces. The
// estimate is the first bounce (or, where the bins carry the emitters, the direct light), most of
// what turns; the later bounces' light, smoother, is taken as it is.
// Emitters are left out of the gradient where the depth maps give their light; the environment
// through the empty bins comes with the light from outside the links (prune_bins.comp).
// Glossy leaves send what their lobes reflect of the direct light along the lobes: the irradiance
// that adds, the same every bounce, lobe_excess.comp found (kSenderLobes); from the second bounce
// on, also what they send so of the first bounce's light (GatherPush::arrival).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 13
#include "common/common.glsl"
#include "common/parted_texels.glsl"
layout(local_size_x = kReceiverGroup) in;

layout(binding = 0, r32ui) readonly uniform uimageBuffer receivers;
layout(std430, binding = 1) buffer ReceiverCounts { uint receiverCounts[]; };
layout(binding = 2, rg32ui) readonly uniform uimageBuffer ranges;                  // LeafRange
layout(binding = 3, rg32ui) readonly uniform uimageBuffer leafLinks[kTexelParts];  // LeafLink: sender, form-factor bits
layout(binding = 4, rgba32f) readonly uniform imageBuffer externalLight;
layout(binding = 5, rgba32f) readonly uniform imageBuffer radiosityIn;
layout(std430, binding = 6) writeonly buffer Gathered { vec4 gathered[]; };          // per surfel
layout(binding = 7, rg32ui) readonly uniform uimageBuffer staticRanges;              // LeafRange
layout(binding = 8, rg32ui) readonly uniform uimageBuffer staticLinks[kTexelParts];  // LeafLink
layout(binding = 9, r32ui) readonly uniform uimageBuffer staticBins[kTexelParts];    // StaticBin
layout(binding = 10, r32ui) readonly uniform uimageBuffer overrides;                 // per leaf and mask word
layout(std430, binding = 11) readonly buffer FrameCounters { uint frameCounters[]; };
layout(std430, binding = 12) readonly buffer StaticCounters { uint staticCounters[]; };
layout(binding = 14, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(binding = 15, rgba32f) readonly uniform imageBuffer nodeEmission;
layout(binding = 17, rgba32f) readonly uniform imageBuffer binTable;
layout(std430, binding = 16) writeonly buffer RotationGradients { vec4 rotationGradients[]; };  // 3 a surfel: r, g, b
layout(binding = 18, rgba32f) readonly uniform imageBuffer lobeExcess;     // per surfel, at receivers
layout(binding = 20, rgba32f) readonly uniform imageBuffer arrivalExcess;  // the same of the first bounce's light
// per surfel: the light of every static link, overrides left aside, and their Σ F (a): what a
// receiver's still senders bring, which a surfel by a crease takes its own of (gather_creases.comp)
layout(std430, binding = 21) writeonly buffer StillGathered { vec4 stillGathered[]; };
layout(std430, binding = 22) readonly buffer StaticLeaves { StaticLeaf staticLeaves[]; };
// per node: kNodeRigid, its object; then per object its pose (prune_bins.comp)
layout(binding = 19, r32ui) readonly uniform uimageBuffer nodeFlags;
layout(push_constant) uniform Push { GatherPush push; };
layout(constant_id = 28) const bool kSenderLobes = false;  // some lobe sends by direction
layout(constant_id = 0) const bool kCreases = false;       // some surfel by a crease reads stillGathered
#include "object_pose.glsl"
#include "receiver_links.glsl"

// Adds the turn `axis` (n × ω times F/cos θ) of a link to a sender of radiosity b.
void addTurn(inout mat3 turn, vec3 axis, vec3 b, uint sender) {
  if (push.emittersByMaps != 0u) b -= imageLoad(nodeEmission, int(sender)).rgb;
  turn += outerProduct(axis, b);
}

// A frame link's turn, toward its sender's centre (its bin is not kept). F/cos θ, the bin's covered
// solid angle over π, is held below a bin's where the centre lies nearer the horizon than the bin.
vec3 towardSender(uvec2 link, vec3 x, vec3 n) {
  const vec3 d = nodePositionArea(link.x).xyz - x;
  if (!(dot(d, d) > 0.0)) return vec3(0.0);
  const vec3 w = normalize(d);
  return cross(n, w) * min(uintBitsToFloat(link.y) / max(dot(n, w), 1e-6), push.largestBin / kPi);
}

// A static link's turn, along its bin (binTable: the bin's ∫ω dω) in the receiver's bin frame, which
// turns with its object where it moves rigidly (`toWorld`: from that frame at its rest pose to now).
vec3 alongBin(uint bin, float f, vec3 n, mat3 toWorld) {
  const vec3 v = toWorld * imageLoad(binTable, int(bin)).xyz;
  const float c = dot(n, v);
  return c > 0.0 ? cross(n, v) * (f / c) : vec3(0.0);
}

void main() {
  const uint first = push.newOnly != 0u ? receiverCounts[kReceiverRound] : 0u;
  const uint k = first + itemIndex();
  // A frame that overflowed (links, leaf links, a prune's loop budget) is redone: its bounces would be wasted.
  if (k >= receiverCounts[kReceiverCount] || (frameCounters[kCounterOverflow] | staticCounters[kCounterOverflow]) != 0u)
    return;
  const uint s = imageLoad(receivers, int(k)).x;
  uvec2 range = imageLoad(ranges, int(s)).xy, staticRange = imageLoad(staticRanges, int(s)).xy;
  vec3 g = imageLoad(externalLight, int(kExternalTexels * s)).rgb;
  if (kSenderLobes) g += imageLoad(lobeExcess, int(s)).rgb;
  if (kSenderLobes && push.arrival != 0u) g += imageLoad(arrivalExcess, int(s)).rgb;
  for (uint i = range.x; i < range.x + range.y; ++i) {
    uvec2 link = loadParted(leafLinks, i).xy;
    g += uintBitsToFloat(link.y) * imageLoad(radiosityIn, int(link.x)).rgb;
  }
  vec3 still = vec3(0.0);
  float covered = 0.0;
  for (uint i = staticRange.x; i < staticRange.x + staticRange.y; ++i) {
    uvec2 link = loadParted(staticLinks, i).xy;
    const vec3 sent = uintBitsToFloat(link.y) * imageLoad(radiosityIn, int(link.x)).rgb;
    if (kCreases) still += sent, covered += uintBitsToFloat(link.y);
    if (staticLinkStands(s, i, push.maskWords)) g += sent;
  }
  gathered[s] = vec4(g, 0.0);
  // The emitters' own light, which the depth maps give, out as the external light takes it out of g.
  if (kCreases)
    stillGathered[s] = vec4(still + (staticRange.y > 0u ? staticLeaves[s].correction.rgb : vec3(0.0)), covered);
  // The first bounce's rotation gradient, with the refinement's estimate: the links again (a loop of
  // its own keeps the bounces' gathers as they were).
  if (push.newOnly != 0u) {
    const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
    const vec3 x = nodePositionArea(leaf).xyz, n = nodeNormalCone(leaf).xyz;
    const uint flags = imageLoad(nodeFlags, int(leaf)).x;
    const mat3 fromRest = (flags & kNodeRigid) != 0u ? restTurn(flags >> kNodeRootShift) : mat3(1.0);
    const mat3 toWorld =
        transpose(binFrameOf(uvec2(staticLeaves[s].frameNormal, staticLeaves[s].frameTangent)) * fromRest);
    mat3 turn;  // columns: d/dθ of r, g and b for a turn about each axis
    for (uint c = 0u; c < 3u; ++c) turn[c] = imageLoad(externalLight, int(kExternalTexels * s + 1u + c)).xyz;
    for (uint i = range.x; i < range.x + range.y; ++i) {
      uvec2 link = loadParted(leafLinks, i).xy;
      addTurn(turn, towardSender(link, x, n), imageLoad(radiosityIn, int(link.x)).rgb, link.x);
    }
    for (uint i = staticRange.x; i < staticRange.x + staticRange.y; ++i) {
      uvec2 link = loadParted(staticLinks, i).xy;
      if (!staticLinkStands(s, i, push.maskWords)) continue;
      const vec3 along = alongBin(staticBinOf(loadParted(staticBins, i).x), uintBitsToFloat(link.y), n, toWorld);
      addTurn(turn, along, imageLoad(radiosityIn, int(link.x)).rgb, link.x);
    }
    for (uint c = 0u; c < 3u; ++c) rotationGradients[3u * s + c] = vec4(turn[c], 0.0);
  }
  // The largest estimate, for the receivers' refinement (non-negative float bits order as integers;
  // one counter every thread shares, so the bounces leave it).
  if (push.newOnly != 0u) atomicMax(receiverCounts[kReceiverScale], floatBitsToUint(luminance(g)));
}

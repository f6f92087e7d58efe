// What a glossy surfel's specular lobe reflects toward the eye of the light a receiver's links
// bring (reflect_receivers). The links keep the nearest sender per direction:
// each sender's radiosity, less its emission (the depth maps give the emitters' direct light per
// pixel), and a glossy leaf's as its lobe sends it (sender_lobes.glsl), arrives along the
// sender's own direction, through the lobe widened by the sender's
// extent and at least a bin's (between the bins' senders lies what the bins did not keep). The
// light from outside the links (the environment through empty bins) is reflected as if it arrived
// evenly. Declares what it reads at bindings 1 to 15 (0: the nodes, NODE_TEXELS; lobe.glsl the
// lobe's own); a pass adds its own after them.

#include "lobe.glsl"
layout(binding = 4, rg32ui) readonly uniform uimageBuffer ranges;                  // LeafRange
layout(binding = 5, rg32ui) readonly uniform uimageBuffer leafLinks[kTexelParts];  // LeafLink
layout(binding = 6, rg32ui) readonly uniform uimageBuffer staticRanges;            // LeafRange
layout(binding = 7, rg32ui) readonly uniform uimageBuffer staticLinks[kTexelParts];
layout(binding = 8, r32ui) readonly uniform uimageBuffer staticBins[kTexelParts];  // StaticBin
layout(binding = 9, r32ui) readonly uniform uimageBuffer overrides;                // per leaf and mask word
layout(binding = 10, rgba32f) readonly uniform imageBuffer externalLight;
layout(binding = 11, rgba32f) readonly uniform imageBuffer radiosityA;  // the bounces' two solutions
layout(binding = 12, rgba32f) readonly uniform imageBuffer radiosityB;
layout(binding = 13, rgba32f) readonly uniform imageBuffer nodeEmission;  // π·Le per node
layout(std430, binding = 14) readonly buffer BounceStates { BounceState state; };
#define LINK_LANES
#define LINK_BATCHES
#include "receiver_links.glsl"
#define SENDER_LOBES 15
#include "common/sender_lobes.glsl"
layout(binding = 20, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode: a leaf's surfel
layout(binding = 21, r32ui) readonly uniform uimageBuffer nodeFlags;

// What leaf q of normal n sends toward unit w of its reflected light `reflected` beyond it sent
// evenly (baseBeyondEven); zero for any other node.
vec3 baseTowardBeyondEven(uint q, vec3 n, vec3 w, vec3 reflected) {
  const uvec4 node = imageLoad(tree, int(q));
  return node.z != 0u ? vec3(0.0) : reflected * baseBeyondEven(surfelBrdf[node.w], dot(n, w));
}

// Whether sender q sends anything other than its radiosity evenly: a lobe by direction, or a glossy
// dielectric leaf's base by its exit angle.
bool sendsBeyondEven(uint q) {
  return (kSenderLobes && imageLoad(senderLobes, int(2u * q)).w > 0.0) ||
         (kBasesByAngle && (imageLoad(nodeFlags, int(q)).x & kNodeBaseByAngle) != 0u);
}

// The receiver being walked (reflectedAt): its lobe, the bounces' last solution (`lastB`: it is
// radiosityB, Bounces::solution(), the one before it in the other), the factor of the bounces not
// run (`tail`: BounceState::gain, which the irradiance takes as its last change times it,
// bounce_tail.comp; the radiosity takes its own last change so), and the lane's sums.
Lobe walkLobe;
bool walkLastB;
float walkTail;
vec3 walkReflected, walkEmitted;

// What the lobe reflects of the light of sender q, which gives the receiver irradiance f times its
// radiosity: its emission's share in walkEmitted, the rest through the lobe. `beyondEven`: with what
// a glossy sender sends toward it beyond its radiosity sent evenly (sendsBeyondEven).
vec3 reflectedFrom(uint q, float f, bool beyondEven) {
  const Lobe lobe = walkLobe;
  const vec3 emission = imageLoad(nodeEmission, int(q)).rgb;
  const vec4 last = walkLastB ? imageLoad(radiosityB, int(q)) : imageLoad(radiosityA, int(q));
  vec3 radiosity = last.rgb;
  if (walkTail > 0.0) {
    const vec4 before = walkLastB ? imageLoad(radiosityA, int(q)) : imageLoad(radiosityB, int(q));
    radiosity = max(radiosity + walkTail * (last.rgb - before.rgb), vec3(0.0));
  }
  walkEmitted += f * emission;
  const vec4 positionArea = nodePositionArea(q), cone = nodeNormalCone(q);
  const vec3 d = positionArea.xyz - lobe.x;
  const float d2 = dot(d, d);
  if (!(d2 > 0.0)) return vec3(0.0);
  const vec3 l = d * inversesqrt(d2);
  // Its solid angle from the surfel (a disk's on its axis, finite when near; a curved sender faces it).
  const float facing = cone.w >= 0.5 * kPi ? 1.0 : max(dot(cone.xyz, -l), 0.0);
  const float solidAngle = min(positionArea.w * facing / (d2 + positionArea.w / kPi), 2.0 * kPi);
  const vec3 lt = vec3(dot(l, lobe.t1), dot(l, lobe.t2), dot(l, lobe.n));
  vec3 sent = radiosity;
  if (beyondEven)
    sent += excessToward(q, lobe.x, 0.0, push.leastSpread) +
            baseTowardBeyondEven(q, cone.xyz, -l, max(radiosity - emission, vec3(0.0)));
  return f * max(sent - emission, vec3(0.0)) *
         widenedSpecular(lobe.brdf, lt, lobe.view, max(solidAngle / (4.0 * kPi), push.leastSpread));
}

// The walk (receiver_links.glsl's LINK_BATCHES): the senders that send only their radiosity evenly
// in it, the others in batches.
bool visitLink(uvec2 link) {
  if (sendsBeyondEven(link.x)) return true;
  walkReflected += reflectedFrom(link.x, uintBitsToFloat(link.y), false);
  return false;
}
void batchedLink(uvec2 link) { walkReflected += reflectedFrom(link.x, uintBitsToFloat(link.y), true); }

// What the lobe reflects of the light receiver r's links and its external light bring, in every
// lane of the workgroup, which walks the links together (receiver_links.glsl); every lane calls it.
vec3 reflectedAt(Lobe lobe, uint r) {
  walkLobe = lobe;
  // Read once: a storage buffer, read a lane at a time.
  walkLastB = state.gathers % 2u == 1u;
  walkTail = state.gain;
  walkReflected = walkEmitted = vec3(0.0);
  walkLinksInBatches(r);
  sumLanes(walkReflected, walkEmitted);
  // The external light gives back what it took of the emitters' credit in the bins.
  return walkReflected +
         lobe.evenShare * max(imageLoad(externalLight, int(kExternalTexels * r)).rgb + walkEmitted, vec3(0.0));
}

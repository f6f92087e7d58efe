#version 460
// Receivers' refinement, last step of a round (docs/design.md §2.4). Each child of a candidate node
// has been sampled (its representative is a receiver, its direct irradiance estimated) and gets a
// need, the largest of three tests' statistic over its threshold:
// - its support against how near what its receiver sees is: kReceiverReach·radius over `proximity`
//   times the harmonic mean distance of the surfaces around it (light changes near corners, contacts
//   and occluders; after Ward's irradiance cache);
// - its radius against the largest a cell may have (a shadow's edge between samples spaced wider
//   might go unseen);
// - its sample against the prediction from the other samples nearby of its level or coarser, over
//   --receiver-tol of its own irradiance (against a share of the largest where it is darker).
// A child whose need passes kRefineFrom is refined: the next round's candidate.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 12
#include "common.glsl"
layout(local_size_x = kReceiverGroup) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, r32ui) readonly uniform uimageBuffer representatives;
layout(binding = 2, r32ui) readonly uniform uimageBuffer candidatesIn;
layout(std430, binding = 3) writeonly buffer CandidatesOut { uint candidatesOut[]; };
layout(std430, binding = 4) buffer ReceiverCounts { uint receiverCounts[]; };
layout(binding = 5, r32ui) readonly uniform uimageBuffer skip;
layout(binding = 6, rgba32f) readonly uniform imageBuffer gathered;  // per surfel, at receivers
layout(binding = 7, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(std430, binding = 8) readonly buffer Proximity { float proximity[]; };  // per surfel
layout(std430, binding = 9) buffer Needs { float needs[]; };                   // per node
layout(std430, binding = 10) readonly buffer LevelStarts { uint levelStarts[]; };
layout(binding = 11, r32f) readonly uniform imageBuffer presences;  // 0 where not sampled
layout(push_constant) uniform Push { ReceiverPush push; };

#include "receivers.glsl"

// Whether a node's cone (axis, half-angle) may hold a normal within the interpolation's angle of n
// (receiverWeight's normal test, with a margin for rounding).
bool mayFace(vec4 cone, vec3 n) {
  return acos(clamp(dot(cone.xyz, n), -1.0, 1.0)) - min(cone.w, kPi) < acos(kReceiverNormalCos) + 1e-3;
}

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The level holding node n: its first node and the first of the level after.
uvec2 levelOf(uint n) {
  uint l = 0u;
  while (levelStarts[l + 1u] <= n) ++l;
  return uvec2(levelStarts[l], levelStarts[l + 1u]);
}

// How far sample s (of child c of a candidate) misses its prediction from the other samples around
// it of its level or coarser (weighed by their place: a coarser one by its role, one of its level by
// its presence), over the tolerance. They are found by walking the sampled part of the trees
// (depth first, without a stack: `skip`), entering only the nodes whose samples may reach s.
float lightNeed(uint c, uint s, float floorValue) {
  const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
  const vec3 x = nodePositionArea(leaf).xyz, n = nodeNormalCone(leaf).xyz;
  vec3 t1, t2;
  tangentFrame(n, t1, t2);
  tapCount = 0u;
  const uvec2 level = levelOf(c);  // the first node of c's level, and of the next
  for (uint node = 0u; node < level.y;) {
    const uvec4 t = imageLoad(tree, int(node));  // parent, firstChild, childCount, surfel
    const float radius = nodeRadius(node);
    // Below a node of no presence (or not sampled) no sample has any.
    const float presence = imageLoad(presences, int(node)).x;
    const bool root = t.x == 0xFFFFFFFFu;
    // Its samples and those below lie within its radius and reach kReceiverReach times as far; their
    // normals lie within its cone.
    if ((presence <= 0.0 && !root) || distance(nodePositionArea(node).xyz, x) > (1.0 + kReceiverReach) * radius ||
        !mayFace(nodeNormalCone(node), n)) {
      node = imageLoad(skip, int(node)).x;
      continue;
    }
    const uint r = imageLoad(representatives, int(node)).x;
    if (presence > 0.0 && r != s) {
      const float place = node >= level.x || t.z == 0u ? presence : presence * (1.0 - refinementShare(needs[node]));
      const uint at = imageLoad(leafOfSurfel, int(r)).x;
      const vec3 p = nodePositionArea(at).xyz;
      const float w = receiverWeight(x, n, p, nodeNormalCone(at).xyz, kReceiverReach * radius) * place;
      if (w > 0.0) keepTap(r, w, vec2(dot(p - x, t1), dot(p - x, t2)));
    }
    node = node < level.x && t.z != 0u ? t.y : imageLoad(skip, int(node)).x;
  }
  if (tapCount == 0u) return 1e30;
  fitCoefficients();
  float prediction = 0.0;
  for (uint t = 0u; t < tapCount; ++t)
    prediction += tapWeight[t] * luminance(imageLoad(gathered, int(tapReceiver[t])).rgb);
  const float value = luminance(imageLoad(gathered, int(s)).rgb);
  return abs(max(prediction, 0.0) - value) / max(push.tolerance * max(value, floorValue), 1e-30);
}

void main() {
  const uint k = itemIndex();
  if (k >= receiverCounts[push.source]) return;
  const uint node = imageLoad(candidatesIn, int(k)).x;
  const uvec4 t = imageLoad(tree, int(node));
  const float floorValue = push.floorShare * uintBitsToFloat(receiverCounts[kReceiverScale]);
  for (uint c = t.y; c < t.y + t.z; ++c) {
    if (imageLoad(tree, int(c)).z == 0u) continue;  // a leaf: nothing to refine
    const uint s = imageLoad(representatives, int(c)).x;
    const float radius = nodeRadius(c);
    // Past 1 the need makes no difference (refinementShare), so the light's test, a walk of the
    // trees, runs only where the other two leave it below.
    const float sure = max(kReceiverReach * radius * proximity[s] / push.proximity, radius / push.largest);
    const float need = sure >= 1.0 ? sure : max(sure, lightNeed(c, s, floorValue));
    needs[c] = need;
    if (need <= kRefineFrom) continue;
    candidatesOut[atomicAdd(receiverCounts[push.target], 1u)] = c;
  }
}

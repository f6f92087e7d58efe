#version 460
// Receivers' refinement, last step of a round (docs/design.md §2.4). Each child of a candidate node
// has been sampled (its representative is a receiver, its direct irradiance estimated) and gets a
// need, the largest of three tests' statistic over its threshold:
// - its support against how near what its receiver sees is: kReceiverReach·radius over `proximity`
//   times the harmonic mean distance of the surfaces around it (light changes near corners, contacts
//   and occluders; after Ward's irradiance cache), times its sharpness where the eye sees a narrow
//   lobe's reflection (seen_nodes);
// - its radius against the largest a cell may have (a shadow's edge between samples spaced wider
//   might go unseen);
// - its sample against the prediction from the other samples nearby of its level or coarser (each
//   turned to its normal by its rotation gradient), over --receiver-tol of its own irradiance
//   (against a share of the largest where it is darker).
// A node none of whose surfels the image reads (seen_nodes) is judged at --unseen-tol: its light
// reaches the image only after another bounce.
// A child whose need passes kRefineFrom is refined: the next round's candidate. A child whose
// receiver lies inside another object (a floor under a block) is refined where any of its surfels
// lies outside, for its receiver's light is none of theirs, and never where none does. The last
// workgroup starts the next round.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 12
#include "common/common.glsl"
layout(local_size_x = kReceiverGroup) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, r32ui) readonly uniform uimageBuffer representatives;
layout(binding = 2, r32ui) readonly uniform uimageBuffer candidatesIn;
layout(std430, binding = 3) writeonly buffer CandidatesOut { uint candidatesOut[]; };
layout(std430, binding = 4) coherent buffer ReceiverCounts { uint receiverCounts[]; };
layout(binding = 5, r32ui) readonly uniform uimageBuffer skip;
layout(binding = 6, rgba32f) readonly uniform imageBuffer gathered;  // per surfel, at receivers
layout(binding = 7, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(std430, binding = 8) readonly buffer Proximity { float proximity[]; };  // per surfel
layout(std430, binding = 9) buffer Needs { float needs[]; };                   // per node
layout(std430, binding = 10) readonly buffer LevelStarts { uint levelStarts[]; };
layout(binding = 11, r32f) readonly uniform imageBuffer presences;  // 0 where not sampled
layout(std430, binding = 13) writeonly buffer ReceiverArgs { uvec4 receiverArgs[]; };
layout(binding = 14, rgba32f) readonly uniform imageBuffer rotationGradients;  // 3 a surfel: r, g, b
// Per node, the surfels below it inside another object (buried_surfels), and all the surfels below.
layout(binding = 15, r32ui) readonly uniform uimageBuffer nodeBuried;
layout(binding = 16, r32ui) readonly uniform uimageBuffer nodeLeaves;
layout(binding = 17, r32ui) readonly uniform uimageBuffer surfelBuried;
layout(binding = 18, r32ui) readonly uniform uimageBuffer seenNodes;
layout(push_constant) uniform Push { ReceiverPush push; };
#include "receiver_args.glsl"

#include "receivers.glsl"
#include "turned_irradiance.glsl"

// The level holding node n: its first node and the first of the level after.
uvec2 levelOf(uint n) {
  uint l = 0u;
  while (levelStarts[l + 1u] <= n) ++l;
  return uvec2(levelStarts[l], levelStarts[l + 1u]);
}

// The sample being predicted: its surfel, position, normal and tangents, and whether it lies inside
// another object (only samples inside too then predict it; outside, only those outside).
struct Query {
  uint s;
  vec3 x, n, t1, t2;
  bool buried;
};

// Node q's sample weighed into the prediction for the query (none for the query's own), by its place:
// a node of the query's level (or a leaf) by its presence, a coarser one by its role.
void considerSample(uint q, uvec4 t, float presence, uvec2 level, Query query) {
  const uint r = imageLoad(representatives, int(q)).x;
  if (r == query.s || (imageLoad(surfelBuried, int(r)).x != 0u) != query.buried) return;
  const float place = q >= level.x || t.z == 0u ? presence : presence * (1.0 - refinementShare(needs[q]));
  const uint at = imageLoad(leafOfSurfel, int(r)).x;
  const vec3 p = nodePositionArea(at).xyz;
  const float w = receiverWeight(query.x, query.n, p, nodeNormalCone(at).xyz, kReceiverReach * nodeRadius(q)) * place;
  if (w > 0.0) keepTap(r, w, vec2(dot(p - query.x, query.t1), dot(p - query.x, query.t2)));
}

// The samples that may weigh for a query within `radius` of `centre` with a normal in `cone`: the
// sampled nodes of the level given or coarser, found by a walk of the sampled part of the trees (depth
// first, without a stack: `skip`) that enters only the nodes whose samples may reach so far: their
// samples lie within their radius and reach kReceiverReach times as far, their normals within their
// cone (receiverWeight's normal test, with a margin for rounding). The children of a candidate list
// them once for all (`collect`: false where more than kNearby); a child whose list overflowed walks
// with its own point and weighs them as it goes.
const uint kNearby = 128u;
uint nearby[kNearby];
uint nearbyCount = 0u;
bool walkSamples(uvec2 level, vec3 centre, float radius, vec4 cone, bool collect, Query query) {
  nearbyCount = 0u;
  for (uint node = 0u; node < level.y;) {
    const uvec4 t = imageLoad(tree, int(node));  // parent, firstChild, childCount, surfel
    // Below a node of no presence (or not sampled) no sample has any.
    const float presence = imageLoad(presences, int(node)).x;
    const vec4 normalCone = nodeNormalCone(node);
    if ((presence <= 0.0 && t.x != 0xFFFFFFFFu) ||
        distance(nodePositionArea(node).xyz, centre) > (1.0 + kReceiverReach) * nodeRadius(node) + radius ||
        !normalsMayWeigh(angleOutside(cone, normalCone.xyz) - normalCone.w)) {
      node = imageLoad(skip, int(node)).x;
      continue;
    }
    if (presence > 0.0) {
      if (!collect)
        considerSample(node, t, presence, level, query);
      else if (nearbyCount == kNearby)
        return false;
      else
        nearby[nearbyCount++] = node;
    }
    node = node < level.x && t.z != 0u ? t.y : imageLoad(skip, int(node)).x;
  }
  return true;
}

// How far child c's sample s misses its prediction from the samples around it of its level or
// coarser, over the tolerance; `listed`: the candidate's list holds them.
float lightNeed(uint c, uint s, float floorValue, uvec2 level, bool listed) {
  const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
  Query query = Query(s, nodePositionArea(leaf).xyz, nodeNormalCone(leaf).xyz, vec3(0.0), vec3(0.0),
                      imageLoad(surfelBuried, int(s)).x != 0u);
  tangentFrame(query.n, query.t1, query.t2);
  tapCount = 0u;
  if (listed)
    for (uint i = 0u; i < nearbyCount; ++i) {
      const uint q = nearby[i];
      considerSample(q, imageLoad(tree, int(q)), imageLoad(presences, int(q)).x, level, query);
    }
  else
    walkSamples(level, query.x, 0.0, vec4(query.n, 0.0), false, query);
  if (tapCount == 0u) return 1e30;
  fitCoefficients(false);  // linear: the sample left out, a quadratic through the rest swings
  float prediction = 0.0;
  FOR_TAPS(t)
  prediction += tapWeight[t] * luminance(turnedIrradiance(tapReceiver[t], query.n));
  const float value = luminance(imageLoad(gathered, int(s)).rgb);
  return abs(max(prediction, 0.0) - value) / max(push.tolerance * max(value, floorValue), 1e-30);
}

void refineCandidate() {
  const uint k = itemIndex();
  if (k >= receiverCounts[push.source]) return;
  const uint node = imageLoad(candidatesIn, int(k)).x;
  const uvec4 t = imageLoad(tree, int(node));
  const float floorValue = push.floorShare * uintBitsToFloat(receiverCounts[kReceiverScale]);
  uvec2 level = uvec2(0u);  // the children's level: its first node, and the next level's
  bool walked = false, listed = false;
  for (uint c = t.y; c < t.y + t.z; ++c) {
    if (imageLoad(tree, int(c)).z == 0u) continue;  // a leaf: nothing to refine
    const uint s = imageLoad(representatives, int(c)).x;
    const uint buried = imageLoad(nodeBuried, int(c)).x;
    if (buried != 0u) {
      const bool whole = buried == imageLoad(nodeLeaves, int(c)).x;
      if (whole || imageLoad(surfelBuried, int(s)).x != 0u) {
        needs[c] = whole ? 0.0 : 1e30;
        if (!whole) candidatesOut[atomicAdd(receiverCounts[push.target], 1u)] = c;
        continue;
      }
    }
    const float radius = nodeRadius(c);
    // Past 1 the need makes no difference (refinementShare), so the light's test, a walk of the
    // trees, runs only where the other two leave it below.
    const float seen = push.unseenShare < 1.0 ? uintBitsToFloat(imageLoad(seenNodes, int(c)).x) : 1.0;
    const float unseen = seen > 0.0 ? 1.0 : push.unseenShare, sharpness = max(seen, 1.0);
    const float sure =
        max(sqrt(unseen) * kReceiverReach * radius * proximity[s] * sharpness / push.proximity, radius / push.largest);
    if (sure < 1.0 && !walked) {
      level = levelOf(c);
      const Query none = Query(0u, vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), false);
      listed = walkSamples(level, nodePositionArea(node).xyz, nodeRadius(node), nodeNormalCone(node), true, none);
      walked = true;
    }
    const float need = sure >= 1.0 ? sure : max(sure, unseen * lightNeed(c, s, floorValue, level, listed));
    needs[c] = need;
    if (need <= kRefineFrom) continue;
    candidatesOut[atomicAdd(receiverCounts[push.target], 1u)] = c;
  }
}

// The last workgroup starts the next round (the candidates listed here; this round's list emptied
// for the round after) and sizes its dispatches over no new receivers yet: where the next round
// has no candidates, its steps run no workgroup, and those sizes stand.
void main() {
  refineCandidate();
  ONLY_IN_THE_LAST_WORKGROUP(receiverCounts[kReceiverGroupsDone]);
  startRound(push.target, push.source);
  receiversListed(push.batch, push.leavesPerGroup, push.maxGroups, push.batches);
}

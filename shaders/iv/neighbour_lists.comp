#version 460
// Interpolation weights, step 1 (docs/design.md §2.4): per group of neighbouring surfels (a node two
// levels above their leaves), the sampled nodes whose receiver may weigh for one of them: with a
// role, their support within reach of the group's sphere, and their receiver's normal within the
// kernel's angle of the group's cone (nested parts of many orientations meet within one support).
// One walk of the trees (depth first, without a stack: `skip`) where `reach` says one below may.
// The group's surfels weigh only those.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 3
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, rg32f) readonly uniform imageBuffer reach;     // reach, least cosine
layout(binding = 2, r32ui) readonly uniform uimageBuffer skip;
layout(binding = 4, r32ui) readonly uniform uimageBuffer groups;                           // their nodes
layout(std430, binding = 5) writeonly buffer NeighbourCounts { uint neighbourCounts[]; };  // per group
layout(binding = 6, r32ui) writeonly uniform uimageBuffer neighbours;  // kGroupNeighbours nodes a group
layout(binding = 7, r32f) readonly uniform imageBuffer roles;
layout(binding = 8, r32ui) readonly uniform uimageBuffer representatives;
layout(binding = 9, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(push_constant) uniform Push { ReceiverPush push; };

#include "receivers.glsl"

// Whether a node (reach r, normal cone) may hold a surfel within `radius` of `centre` with a normal in
// `cone` (its half-angle's cosine and sine in `coneCosSin`): the cosine of the least angle between
// the node's axis and the cone, cos(θ − w) = cos θ cos w + sin θ sin w past the cone, with a margin
// for rounding (a node it lets in is still listed only where mayWeigh says its receiver may weigh).
bool mayHold(vec2 r, vec4 normalCone, vec3 at, vec3 centre, float radius, vec4 cone, vec2 coneCosSin) {
  const float c = clamp(dot(cone.xyz, normalCone.xyz), -1.0, 1.0);
  const float least = c >= coneCosSin.x ? 1.0 : c * coneCosSin.x + sqrt(1.0 - c * c) * coneCosSin.y;
  return r.x >= 0.0 && distance(at, centre) <= r.x + radius && (r.y <= -1.0 || least + 1e-4 >= r.y);
}

// Whether node q's receiver may weigh for a surfel within `radius` of `centre` whose normal lies in
// `cone`: receiverWeight's support (centred on the receiver) and its normal test.
bool mayWeigh(uint q, vec3 centre, float radius, vec4 cone) {
  const uint at = imageLoad(leafOfSurfel, int(imageLoad(representatives, int(q)).x)).x;
  return distance(nodePositionArea(at).xyz, centre) <= kReceiverReach * nodeRadius(q) + radius &&
         normalsMayWeigh(angleOutside(cone, nodeNormalCone(at).xyz));
}

void main() {
  const uint k = itemIndex();
  if (k >= push.groupCount) return;
  const uint group = imageLoad(groups, int(k)).x;
  const vec3 centre = nodePositionArea(group).xyz;
  const float radius = nodeRadius(group);
  const vec4 cone = nodeNormalCone(group);
  const float w = min(cone.w, kPi);
  const vec2 coneCosSin = vec2(cos(w), sin(w));
  uint count = 0u;
  for (uint node = 0u; node < push.nodeCount;) {
    const vec4 positionArea = nodePositionArea(node), normalCone = nodeNormalCone(node);
    if (!mayHold(imageLoad(reach, int(node)).xy, normalCone, positionArea.xyz, centre, radius, cone, coneCosSin)) {
      node = imageLoad(skip, int(node)).x;
      continue;
    }
    if (imageLoad(roles, int(node)).x > 0.0 && mayWeigh(node, centre, radius, cone)) {
      if (count < kGroupNeighbours) imageStore(neighbours, int(k * kGroupNeighbours + count), uvec4(node));
      ++count;
    }
    const uvec4 t = imageLoad(tree, int(node));  // parent, firstChild, childCount, surfel
    node = t.z != 0u ? t.y : imageLoad(skip, int(node)).x;
  }
  neighbourCounts[k] = count;
}

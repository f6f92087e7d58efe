#version 460
// Receivers' reach, bottom-up in one dispatch (climb.glsl): per node, how far from its position the
// support of a sampled node at or below it that has a role reaches (negative where none does; a
// support is centred on the node's receiver, which stands off the node's centre), and
// the least cosine between a surfel's normal and the node's cone axis that such a receiver may still
// weigh for, so that the interpolation's walk enters only the nodes that may hold its surfels.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 3
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, r32f) readonly uniform imageBuffer roles;
layout(std430, binding = 2) coherent buffer Reach { vec2 reach[]; };  // reach, least cosine
layout(binding = 4, r32ui) readonly uniform uimageBuffer representatives;
layout(binding = 5, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(push_constant) uniform Push { CountPush push; };  // count: nodes

uvec4 treeNodeAt(uint i) { return imageLoad(tree, int(i)); }

void combine(uint i) {
  const uvec4 t = treeNodeAt(i);
  const float cone = nodeNormalCone(i).w, angle = cone + acos(kReceiverNormalCos);
  const vec3 p = nodePositionArea(i).xyz;
  float r = -1.0;
  if (imageLoad(roles, int(i)).x > 0.0) {
    const uint receiverLeaf = imageLoad(leafOfSurfel, int(imageLoad(representatives, int(i)).x)).x;
    r = distance(p, nodePositionArea(receiverLeaf).xyz) + kReceiverReach * nodeRadius(i);
  }
  for (uint c = t.y; c < t.y + t.z; ++c)
    if (reach[c].x >= 0.0) r = max(r, distance(p, nodePositionArea(c).xyz) + reach[c].x);
  reach[i] = vec2(r, angle >= kPi ? -2.0 : cos(angle));
}

#define CLIMB_ARRIVALS 6
#include "common/climb.glsl"

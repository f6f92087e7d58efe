#version 460
// ar: the clusters' tables, one level a dispatch, deepest first. A flat node (its normals within
// kArFlatCone) sends what its surfaces send with one normal, so it sums its children's exitance and
// their antiradiance per bin, and the reader applies the cosines exactly. A curved node's table
// holds what it sends toward each bin's centre, its children's cosines applied there.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common.glsl"
layout(local_size_x = 64) in;

layout(binding = 1, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 2, rgba32f) uniform imageBuffer intensity;        // per node and bin
layout(binding = 3, rgba32f) uniform imageBuffer exitance;         // per node, area · L (flat nodes)
layout(push_constant) uniform Push { ArPush push; };               // count: the level's nodes × bins

void main() {
  uint item = itemIndex();
  if (item >= push.count) return;
  uint bins = 6u * push.bins * push.bins, node = push.first + item / bins, c = item % bins;
  uvec4 t = imageLoad(tree, int(node));  // parent, firstChild, childCount, surfel
  if (t.z == 0u) return;                 // a leaf: the local pass wrote it
  bool flatNode = nodeNormalCone(node).w <= kArFlatCone;
  vec3 omega = normalize(binDirection(c, push.bins)), sum = vec3(0.0), exitanceSum = vec3(0.0);
  for (uint k = 0u; k < t.z; ++k) {
    uint child = t.y + k;
    vec3 entry = imageLoad(intensity, int(child * bins + c)).rgb;
    vec4 cone = nodeNormalCone(child);
    if (!flatNode && cone.w <= kArFlatCone) {  // a flat child into a curved table: its cosines at the bin's centre
      float cosine = dot(cone.xyz, omega);
      entry = imageLoad(exitance, int(child)).rgb * max(cosine, 0.0) - entry * abs(cosine);
    }
    sum += entry;
    exitanceSum += imageLoad(exitance, int(child)).rgb;
  }
  imageStore(intensity, int(node * bins + c), vec4(sum, 0.0));
  if (c == 0u) imageStore(exitance, int(node), vec4(flatNode ? exitanceSum : vec3(0.0), 0.0));
}

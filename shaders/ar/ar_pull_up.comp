#version 460
// ar: the clusters' tables, one level a dispatch, deepest first, over the level's inner nodes (the
// local pass wrote the leaves'). A flat node (its normals within
// kArFlatCone) sends what its surfaces send with one normal, so it sums its children's exitance and
// their antiradiance per bin, and the reader applies the cosines exactly. A curved node's table
// holds what it sends toward each bin's centre, its children's cosines applied there.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint kDirs = 4;  // --dirs: a constant, so that dividing by the bins is cheap

layout(binding = 1, rgba32ui) readonly uniform uimageBuffer tree;     // TreeNode
layout(binding = 2, rgba32f) uniform imageBuffer intensity;           // per node and bin
layout(binding = 3, rgba32f) uniform imageBuffer exitance;            // per node, area · L (flat nodes)
layout(binding = 4, r32ui) readonly uniform uimageBuffer innerNodes;  // level by level
layout(push_constant) uniform Push { ArLevelPush push; };             // an invocation per inner node and bin

void main() {
  uint item = itemIndex();
  const uint bins = 6u * kDirs * kDirs;
  if (item >= push.innerCount * bins) return;
  uint node = imageLoad(innerNodes, int(push.firstInner + item / bins)).x, c = item % bins;
  uvec4 t = imageLoad(tree, int(node));  // parent, firstChild, childCount, surfel
  bool flatNode = nodeNormalCone(node).w <= kArFlatCone;
  vec3 omega = flatNode ? vec3(0.0) : normalize(binDirection(c, kDirs)), sum = vec3(0.0), exitanceSum = vec3(0.0);
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

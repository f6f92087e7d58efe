#version 460
// ar: the inner nodes' gathered tables summed down the trees, one level a dispatch, the top first:
// each inner node's bins then hold what it and all its ancestors gathered, so that a surfel reads
// what reaches it through its tree from its leaf and the leaf's parent (ar_incident), not from
// every node of its path. The leaves, whose tables only their own surfels read, are left as they are.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint kDirs = 4;  // --dirs: a constant, so that dividing by the bins is cheap

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;     // TreeNode
layout(binding = 1, rgba32f) uniform imageBuffer gathered;            // per node and bin
layout(binding = 2, r32ui) readonly uniform uimageBuffer innerNodes;  // level by level
layout(push_constant) uniform Push { ArLevelPush push; };             // an invocation per inner node

void main() {
  uint item = itemIndex();
  if (item >= push.innerCount) return;
  const uint bins = 6u * kDirs * kDirs;
  uint node = imageLoad(innerNodes, int(push.firstInner + item)).x;
  int parent = int(imageLoad(tree, int(node)).x);
  if (parent < 0) return;
  for (uint c = 0u; c < bins; ++c) {
    int texel = int(node * bins + c);
    imageStore(gathered, texel, imageLoad(gathered, texel) + imageLoad(gathered, int(uint(parent) * bins + c)));
  }
}

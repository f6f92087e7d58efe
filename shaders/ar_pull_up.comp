#version 460
// ar: a node's intensity toward each bin is the sum of its children's (clusters send what their
// surfaces send), one level a dispatch, deepest first.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, rgba32f) uniform imageBuffer intensity;        // per node and bin
layout(push_constant) uniform Push { ArPush push; };               // count: the level's nodes × bins

void main() {
  uint item = itemIndex();
  if (item >= push.count) return;
  uint bins = 6u * push.bins * push.bins, node = push.first + item / bins, c = item % bins;
  uvec4 t = imageLoad(tree, int(node));  // parent, firstChild, childCount, surfel
  if (t.z == 0u) return;                 // a leaf: the local pass wrote it
  vec3 sum = vec3(0.0);
  for (uint k = 0u; k < t.z; ++k) sum += imageLoad(intensity, int((t.y + k) * bins + c)).rgb;
  imageStore(intensity, int(node * bins + c), vec4(sum, 0.0));
}

#version 460
// Receivers' roles, per node once the refinement is done (docs/design.md §2.4): a sampled node's
// place in the interpolation, its presence less what its children took over (a leaf keeps it all).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, r32f) readonly uniform imageBuffer needs;
layout(binding = 2, r32f) readonly uniform imageBuffer presences;  // 0 where not sampled
layout(std430, binding = 3) writeonly buffer Roles { float roles[]; };
layout(push_constant) uniform Push { ReceiverPush push; };

void main() {
  const uint n = itemIndex();
  if (n >= push.nodeCount) return;
  const float presence = imageLoad(presences, int(n)).x;
  const bool leaf = imageLoad(tree, int(n)).z == 0u;
  roles[n] = leaf ? presence : presence * (1.0 - refinementShare(imageLoad(needs, int(n)).x));
}

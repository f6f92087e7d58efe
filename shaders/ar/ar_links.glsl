// ar: the key a receiver's list of senders is sorted by (interface.h's walkKey) for the sender's
// link to the receiver at `receiverPosition`. Define NODE_TEXELS and TREE_TEXELS (the bindings of
// the nodes' texels and of the trees) before including it.
#include "common/common.glsl"

layout(binding = TREE_TEXELS, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode

uint walkKeyOf(uint sender, vec3 receiverPosition, uint n) {
  uint node = sender & ~kEmitterBit;
  vec4 ps = nodePositionArea(node);
  vec3 d = ps.xyz - receiverPosition;
  return walkKey(sender, linkKind(imageLoad(tree, int(node)).z != 0u, ps.w, dot(d, d), n));
}

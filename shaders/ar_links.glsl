// ar: the key a receiver's list of senders is sorted by (interface.h's walkKey) for the sender
// node's link to the receiver at `receiverPosition`, `cluster` its tree's child count. Define
// NODE_TEXELS (the binding of the nodes' texels) before including it.
#include "common.glsl"

uint walkKeyOf(uint sender, uint cluster, vec3 receiverPosition, uint n) {
  vec4 ps = nodePositionArea(sender & ~kEmitterBit);
  vec3 d = ps.xyz - receiverPosition;
  return walkKey(sender, linkKind(cluster != 0u, ps.w, dot(d, d), n));
}

#version 460
// ar: the senders of each node that ar_sort_senders queued (a list longer than kArShortList) in
// the order the global pass walks them (walkKey), a workgroup a node: the list's keys in place of its
// senders, sorted, then the senders again. A bitonic network of all-ascending compare-exchanges (each
// merge first compares mirrored pairs) over the list padded to a power of two, in place; pairs
// reaching into the padding need no exchange. A small workgroup: every subgroup of a workgroup runs
// every stage; 64 lanes sort a list of kArSortedMost senders in 30,720 loop rounds (and 1,024 to
// make and undo the keys), within lavapipe's budget (common.glsl).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 3
#define TREE_TEXELS 4
#include "ar_links.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Starts { uint starts[]; };
layout(binding = 1, r32ui) coherent uniform uimageBuffer senders;
layout(std430, binding = 2) readonly buffer LongSorts { uint longSorts[]; };  // count, then the queued nodes
layout(constant_id = 0) const uint kDirs = 4;                                 // --dirs

void main() {
  uint queued = groupIndex();
  if (queued >= longSorts[0]) return;
  uint node = longSorts[1u + queued];
  uint first = starts[node], count = starts[node + 1u] - first;
  uint padded = 1u << uint(findMSB(count - 1u) + 1);
  vec3 receiver = nodePositionArea(node).xyz;
  for (uint i = gl_LocalInvocationID.x; i < count; i += gl_WorkGroupSize.x) {
    uint sender = imageLoad(senders, int(first + i)).x;
    imageStore(senders, int(first + i), uvec4(walkKeyOf(sender, receiver, kDirs)));
  }
  memoryBarrierImage();
  barrier();
  for (uint size = 2u; size <= padded; size <<= 1u)
    for (uint stride = size >> 1u; stride > 0u; stride >>= 1u) {
      uint shift = uint(findLSB(stride));
      for (uint t = gl_LocalInvocationID.x; t < padded >> 1u; t += gl_WorkGroupSize.x) {
        uint i = ((t >> shift) << (shift + 1u)) + (t & (stride - 1u));
        uint j = stride == size >> 1u ? i ^ (size - 1u) : i + stride;
        if (j >= count) continue;
        uint a = imageLoad(senders, int(first + i)).x, b = imageLoad(senders, int(first + j)).x;
        if (walkedBefore(b, a)) {
          imageStore(senders, int(first + i), uvec4(b));
          imageStore(senders, int(first + j), uvec4(a));
        }
      }
      memoryBarrierImage();
      barrier();
    }
  for (uint i = gl_LocalInvocationID.x; i < count; i += gl_WorkGroupSize.x)
    imageStore(senders, int(first + i), uvec4(senderOfKey(imageLoad(senders, int(first + i)).x)));
}

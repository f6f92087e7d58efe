#version 460
// ar: each receiver node's senders in the order the global pass walks them (walkKey). Link creation
// lists them in whatever order its atomics ran; the global pass sums in list order, so a canonical
// order makes its sums, and the image, the same run to run. An invocation a node: most lists are
// short, and one invocation sorts a short list by insertion faster than a workgroup starts. A
// longer list is queued for ar_sort_long_senders (a workgroup each); one longer than kArSortedMost
// is flagged, and the solve stops with a message.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 5
#define TREE_TEXELS 4
#include "ar_links.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Starts { uint starts[]; };
layout(binding = 1, r32ui) uniform uimageBuffer senders;
layout(std430, binding = 2) buffer GatherFlags { uint gatherFlags[]; };
layout(std430, binding = 3) buffer LongSorts { uint longSorts[]; };  // count, then the queued nodes
layout(constant_id = 0) const uint kDirs = 4;                        // --dirs
layout(push_constant) uniform Push { CountPush push; };              // count: nodes

void main() {
  uint node = itemIndex();
  if (node >= push.count) return;
  uint first = starts[node], count = starts[node + 1u] - first;
  if (count < 2u) return;
  if (count > kArSortedMost) {
    atomicOr(gatherFlags[0], kArFlagUnsorted);
  } else if (count > kArShortList) {
    longSorts[1u + atomicAdd(longSorts[0], 1u)] = node;
  } else {
    uint list[kArShortList];
    vec3 receiver = nodePositionArea(node).xyz;
    for (uint i = 0u; i < count; ++i) {
      uint sender = imageLoad(senders, int(first + i)).x;
      list[i] = walkKeyOf(sender, receiver, kDirs);
    }
    for (uint i = 1u; i < count; ++i) {
      uint value = list[i], j = i;
      for (; j > 0u && walkedBefore(value, list[j - 1u]); --j) list[j] = list[j - 1u];
      list[j] = value;
    }
    for (uint i = 0u; i < count; ++i) imageStore(senders, int(first + i), uvec4(senderOfKey(list[i])));
  }
}

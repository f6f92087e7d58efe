#version 460
// Reads one buffer through imageBuffers of three formats and through the NodeState helpers of
// shaders/common/common.glsl, and writes what it read (tests/vk_test.cpp).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 3
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) readonly uniform imageBuffer asVec4;
layout(binding = 1, rg32ui) readonly uniform uimageBuffer asUvec2;
layout(binding = 2, r32ui) readonly uniform uimageBuffer asUint;
layout(std430, binding = 4) writeonly buffer Results { vec4 results[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = itemIndex();
  if (i >= count) return;
  // Element i of each view: a vec4, a pair of words, a word; node i / 3 as a NodeState.
  NodeState node = nodeState(i / 3u);
  vec4 fromNode = (i % 3u == 0u) ? node.positionArea : (i % 3u == 1u ? node.normalCone : node.shape);
  results[4u * i] = imageLoad(asVec4, int(i));
  results[4u * i + 1u] = vec4(uintBitsToFloat(imageLoad(asUvec2, int(i)).xy), 0.0, 0.0);
  results[4u * i + 2u] = vec4(uintBitsToFloat(imageLoad(asUint, int(i)).x), 0.0, 0.0, 0.0);
  results[4u * i + 3u] = fromNode;
}

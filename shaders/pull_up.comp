#version 460
// Pass 6d, pull-up: inner nodes carry the area-weighted mean radiosity of the leaves below, so that
// coarse senders send the new value. One dispatch takes up to kPullUpLevels levels, deepest first: a
// node sums its descendants down to the first that are leaves or lie below the dispatch's levels
// (done before), so that no node reads one the same dispatch writes.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(std430, binding = 1) readonly buffer Nodes { NodeState nodes[]; };
layout(std430, binding = 2) buffer Radiosity { vec4 radiosity[]; };
layout(push_constant) uniform Push { LevelPush push; };  // the dispatch's levels: nodes [first, first + count)

vec3 weighted = vec3(0.0), mean = vec3(0.0);
float area = 0.0, count = 0.0;

void add(uint c) {
  const float a = nodes[c].positionArea.w;
  const vec3 b = radiosity[c].rgb;
  weighted += a * b, mean += b, area += a, count += 1.0;
}

// Children of node i and of its descendants within the dispatch's levels.
uvec2 childrenOf(uint i) { return imageLoad(tree, int(i)).yz; }
bool pending(uint c) { return c < push.first + push.count && imageLoad(tree, int(c)).z != 0u; }

void main() {
  const uint k = itemIndex();
  if (k >= push.count) return;
  const uint i = push.first + k;
  const uvec2 children = childrenOf(i);
  if (children.y == 0u) return;
  for (uint c = children.x; c < children.x + children.y; ++c) {
    if (!pending(c)) {
      add(c);
      continue;
    }
    const uvec2 grand = childrenOf(c);
    for (uint g = grand.x; g < grand.x + grand.y; ++g) {
      if (!pending(g)) {
        add(g);
        continue;
      }
      const uvec2 great = childrenOf(g);
      for (uint q = great.x; q < great.x + great.y; ++q) add(q);
    }
  }
  radiosity[i] = vec4(area > 0.0 ? weighted / area : mean / count, 0.0);
}

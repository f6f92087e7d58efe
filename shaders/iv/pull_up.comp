#version 460
// iv's pull-up: inner nodes carry the area-weighted mean radiosity of their children (so of the
// leaves below), so that coarse senders send the new value. The whole trees in one dispatch
// (climb.glsl).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(std430, binding = 1) readonly buffer Nodes { NodeState nodes[]; };
layout(std430, binding = 2) coherent buffer Radiosity { vec4 radiosity[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: nodes

uvec4 treeNodeAt(uint i) { return imageLoad(tree, int(i)); }

void combine(uint i) {
  const uvec4 t = treeNodeAt(i);
  if (t.z == 0u) return;  // a leaf's radiosity is the interpolation's
  vec3 weighted = vec3(0.0), mean = vec3(0.0);
  float area = 0.0;
  for (uint c = t.y; c < t.y + t.z; ++c) {
    const float a = nodes[c].positionArea.w;
    const vec3 b = radiosity[c].rgb;
    weighted += a * b, mean += b, area += a;
  }
  radiosity[i] = vec4(area > 0.0 ? weighted / area : mean / float(t.z), 0.0);
}

#define CLIMB_ARRIVALS 3
#include "common/climb.glsl"

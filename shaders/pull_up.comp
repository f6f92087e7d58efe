#version 460
// Pass 6c, pull-up: inner nodes carry the area-weighted mean radiosity of their children, one level
// per dispatch, deepest first, so that coarse senders send the new value.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Tree { TreeNode tree[]; };
layout(std430, binding = 1) readonly buffer Nodes { NodeState nodes[]; };
layout(std430, binding = 2) buffer Radiosity { vec4 radiosity[]; };
layout(push_constant) uniform Push { LevelPush push; };

void main() {
  uint k = itemIndex();
  if (k >= push.count) return;
  uint i = push.first + k;
  TreeNode t = tree[i];
  if (t.childCount == 0u) return;
  vec3 weighted = vec3(0.0), mean = vec3(0.0);
  float area = 0.0;
  for (uint c = 0; c < t.childCount; ++c) {
    float a = nodes[t.firstChild + c].positionArea.w;
    vec3 b = radiosity[t.firstChild + c].rgb;
    weighted += a * b;
    mean += b;
    area += a;
  }
  radiosity[i] = vec4(area > 0.0 ? weighted / area : mean / float(t.childCount), 0.0);
}

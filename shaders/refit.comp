#version 460
// Pass 3, refit: node attributes bottom-up, one dispatch per level (deepest first). Leaves copy
// their surfel; inner nodes combine their children, already refit.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Tree { TreeNode tree[]; };
layout(std430, binding = 1) readonly buffer Surfels { Surfel surfels[]; };
layout(std430, binding = 2) buffer Nodes { NodeState nodes[]; };
layout(push_constant) uniform Push { uint first; uint count; };

void main() {
  uint k = itemIndex();
  if (k >= count) return;
  uint i = first + k;
  TreeNode t = tree[i];
  if (t.surfel >= 0) {
    Surfel s = surfels[t.surfel];
    nodes[i].positionArea = s.positionArea;
    nodes[i].normalCone = vec4(s.normal.xyz, 0.0);
    nodes[i].radius = vec4(sqrt(s.positionArea.w / kPi), 0.0, 0.0, 0.0);
    return;
  }
  float area = 0.0;
  vec3 weighted = vec3(0.0), mean = vec3(0.0), normal = vec3(0.0);
  for (uint c = 0; c < t.childCount; ++c) {
    NodeState child = nodes[t.firstChild + c];
    area += child.positionArea.w;
    weighted += child.positionArea.w * child.positionArea.xyz;
    mean += child.positionArea.xyz;
    normal += child.positionArea.w * child.normalCone.xyz;
  }
  vec3 p = area > 0.0 ? weighted / area : mean / float(t.childCount);
  float len = length(normal);
  vec3 n = len > 0.0 ? normal / len : vec3(0.0);
  float cone = len > 0.0 ? 0.0 : kPi, radius = 0.0;
  for (uint c = 0; c < t.childCount; ++c) {
    NodeState child = nodes[t.firstChild + c];
    if (len > 0.0 && child.positionArea.w > 0.0)
      cone = max(cone, acos(clamp(dot(n, child.normalCone.xyz), -1.0, 1.0)) + child.normalCone.w);
    radius = max(radius, length(child.positionArea.xyz - p) + child.radius.x);
  }
  nodes[i].positionArea = vec4(p, area);
  nodes[i].normalCone = vec4(n, min(cone, kPi));
  nodes[i].radius = vec4(radius, 0.0, 0.0, 0.0);
}

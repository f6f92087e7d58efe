#version 460
// Runs loops of the given rounds, then loopBudgetSpent() of shaders/common/common.glsl, for the cases of
// tests/shared_definitions_test.cpp: one case a workgroup (a subgroup's loops share the budget).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 8) in;

layout(std430, binding = 0) readonly buffer Cases { uvec2 cases[]; };       // rounds of a first and a second loop
layout(std430, binding = 1) writeonly buffer Results { uvec4 results[]; };  // rounds each loop ran, spent
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = groupIndex();
  if (i >= count) return;
  uint first = 0u, second = 0u;
  for (uint k = 0u; k < cases[i].x; ++k) ++first;
  for (uint k = 0u; k < cases[i].y; ++k) ++second;
  bool spent = loopBudgetSpent();
  if (gl_LocalInvocationID.x == 0u) results[i] = uvec4(first, second, spent ? 1u : 0u, 0u);
}

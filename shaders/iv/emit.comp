#version 460
// iv's bounces, first: emitted radiosity B = π·Le at the leaves, the start of the bounces.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer LeafOfSurfel { uint leafOfSurfel[]; };
layout(std430, binding = 1) readonly buffer Emission { vec4 emission[]; };
layout(std430, binding = 2) writeonly buffer Radiosity { vec4 radiosity[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: surfels

void main() {
  uint s = itemIndex();
  if (s >= push.count) return;
  radiosity[leafOfSurfel[s]] = vec4(kPi * emission[s].rgb, 0.0);
}

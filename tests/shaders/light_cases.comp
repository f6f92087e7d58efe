#version 460
// Runs lightFalloff() of shaders/interface.h for every (light, point) pair of the host side of the
// test (tests/shared_definitions_test.cpp).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Lights { PunctualLight lights[]; };
layout(std430, binding = 1) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 2) writeonly buffer Results { vec4 results[]; };  // toLight, falloff
layout(std430, binding = 3) writeonly buffer Distances { float distances[]; };
layout(push_constant) uniform Push {
  uint lightCount;
  uint pointCount;
};

void main() {
  uint i = itemIndex();
  if (i >= lightCount * pointCount) return;
  vec3 toLight;
  float dist2;
  float falloff = lightFalloff(lights[i / pointCount], points[i % pointCount].xyz, toLight, dist2);
  results[i] = vec4(toLight, falloff);
  distances[i] = dist2;
}

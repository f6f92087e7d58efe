#version 460
// Direct light at the surfels: each surfel's irradiance from the emitter samples, seen or hidden by
// their depth maps (direct_light.glsl), the source of the first bounce.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Surfels { Surfel surfels[]; };
layout(std430, binding = 1) readonly buffer LightPoints { LightPoint lightPoints[]; };
layout(std430, binding = 2) readonly buffer LightViews { Camera lightViews[]; };
layout(std430, binding = 3) readonly buffer LightDepth { uint lightDepth[]; };
layout(std430, binding = 4) writeonly buffer SurfelDirect { vec4 surfelDirect[]; };
layout(push_constant) uniform Push { DirectLightPush push; };
#include "direct_light.glsl"

void main() {
  const uint i = itemIndex();
  if (i >= push.count) return;
  const Surfel s = surfels[i];
  surfelDirect[i] =
      vec4(directIrradiance(s.positionArea.xyz, s.normal.xyz, push.sampleCount, push.resolution, 0u, 1u), 0.0);
}

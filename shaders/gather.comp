#version 460
// Pass 6b, gather at the leaves: irradiance G = external + Σ F·B_sender over the surviving links,
// radiosity B = π·Le + ρ·G. Reads last bounce's radiosity, writes the next (no race).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer LeafOfSurfel { uint leafOfSurfel[]; };
layout(std430, binding = 1) readonly buffer Ranges { LeafRange ranges[]; };
layout(std430, binding = 2) readonly buffer Links { LeafLink leafLinks[]; };
layout(std430, binding = 3) readonly buffer External { vec4 externalLight[]; };
layout(std430, binding = 4) readonly buffer Albedo { vec4 albedo[]; };
layout(std430, binding = 5) readonly buffer Emission { vec4 emission[]; };
layout(std430, binding = 6) readonly buffer RadiosityIn { vec4 radiosityIn[]; };
layout(std430, binding = 7) writeonly buffer RadiosityOut { vec4 radiosityOut[]; };
layout(std430, binding = 8) writeonly buffer Irradiance { vec4 irradiance[]; };
layout(push_constant) uniform Push { uint surfelCount; };

void main() {
  uint s = itemIndex();
  if (s >= surfelCount) return;
  LeafRange range = ranges[s];
  vec3 g = externalLight[s].rgb;
  for (uint k = range.first; k < range.first + range.count; ++k) {
    LeafLink link = leafLinks[k];
    g += link.formFactor * radiosityIn[link.sender].rgb;
  }
  radiosityOut[leafOfSurfel[s]] = vec4(kPi * emission[s].rgb + albedo[s].rgb * g, 0.0);
  irradiance[s] = vec4(g, 0.0);
}

#version 460
// iv's bounces, first: at the leaves, emitted radiosity π·Le (`nodeEmission`, what the prune and
// link creation know emitters by) and the bounces' start π·Le + ρ·E_direct (`radiosity`), E_direct
// the depth maps' direct light (zero where the bins carry it).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer LeafOfSurfel { uint leafOfSurfel[]; };
layout(std430, binding = 1) readonly buffer Emission { vec4 emission[]; };
layout(std430, binding = 2) readonly buffer Albedo { vec4 albedo[]; };
layout(std430, binding = 3) readonly buffer SurfelDirect { vec4 surfelDirect[]; };
layout(std430, binding = 4) writeonly buffer NodeEmission { vec4 nodeEmission[]; };
layout(std430, binding = 5) writeonly buffer Radiosity { vec4 radiosity[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: surfels

void main() {
  uint s = itemIndex();
  if (s >= push.count) return;
  const vec3 emitted = kPi * emission[s].rgb;
  nodeEmission[leafOfSurfel[s]] = vec4(emitted, 0.0);
  radiosity[leafOfSurfel[s]] = vec4(emitted + albedo[s].rgb * surfelDirect[s].rgb, 0.0);
}

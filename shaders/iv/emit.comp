#version 460
// iv's bounces, first: at the leaves, emitted radiosity π·Le (`nodeEmission`, what the prune and
// link creation know emitters by) and the bounces' start π·Le + ρ·E_direct (`radiosity`), E_direct
// the depth maps' direct light (zero where the bins carry it). With kSenderLobes, what a glossy
// leaf's lobe reflects of that light and its direction, which it sends along the lobe
// (common/send_lobe.glsl).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer LeafOfSurfel { uint leafOfSurfel[]; };
layout(std430, binding = 1) readonly buffer Emission { vec4 emission[]; };
layout(std430, binding = 2) readonly buffer Albedo { vec4 albedo[]; };
layout(std430, binding = 3) readonly buffer SurfelDirect { vec4 surfelDirect[]; };
layout(std430, binding = 4) writeonly buffer NodeEmission { vec4 nodeEmission[]; };
layout(std430, binding = 5) writeonly buffer Radiosity { vec4 radiosity[]; };
layout(std430, binding = 6) readonly buffer SurfelArrival { vec4 surfelArrival[]; };
layout(std430, binding = 7) readonly buffer SurfelBrdf { SurfaceBrdf surfelBrdf[]; };
layout(binding = 8, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(std430, binding = 9) readonly buffer Nodes { NodeState nodes[]; };
layout(std430, binding = 10) writeonly buffer SenderLobes { vec4 senderLobes[]; };
layout(push_constant) uniform Push { CountPush push; };    // count: surfels
layout(constant_id = 28) const bool kSenderLobes = false;  // some lobe sends by direction
#include "common/send_lobe.glsl"
#include "common/specular_albedo.glsl"

void main() {
  uint s = itemIndex();
  if (s >= push.count) return;
  const vec3 emitted = kPi * emission[s].rgb;
  nodeEmission[leafOfSurfel[s]] = vec4(emitted, 0.0);
  radiosity[leafOfSurfel[s]] = vec4(emitted + albedo[s].rgb * surfelDirect[s].rgb, 0.0);
  vec4 lobe, light;
  if (kSenderLobes) sendLobe(s, leafOfSurfel[s], nodes[leafOfSurfel[s]].normalCone.xyz, lobe, light);
}

#version 460
// iv's bounces, once they are done (bounce_check.comp sizes it): the bounces not run, added at
// every surfel as the geometric tail of its irradiance's last change, E += ΔE · q/(1 − q).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer BounceStates { BounceState state; };
layout(binding = 1, rgba32f) readonly uniform imageBuffer irradianceChange;
layout(std430, binding = 2) buffer Irradiance { vec4 irradiance[]; };
layout(push_constant) uniform Push { InterpolatePush push; };

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount) return;
  const vec3 e = irradiance[s].rgb + state.gain * imageLoad(irradianceChange, int(s)).rgb;
  irradiance[s] = vec4(max(e, vec3(0.0)), 0.0);
}

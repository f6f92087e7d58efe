// What a glossy leaf sends along its lobe (common/sender_lobes.glsl reads it), written where the
// solver takes the direct light in (iv's emit, ar's ar_local). Expects `surfelBrdf`, `surfelArrival`
// (DirectLight::surfelArrival), `surfelDirect` and `specularAlbedo` declared as storage buffers,
// and `senderLobes` (two vec4 a node) writable.
#include "common/specular_albedo.glsl"

// Surfel s's lobe as its leaf (of normal n) sends it: what it reflects of the direct light from its mean
// direction l, its α widened by the spread of the light's directions about l (1 − |mean|, per
// axis), l, and the square root of the solid angle the leaf spans from the lights; returned too.
void sendLobe(uint s, uint leaf, vec3 n, out vec4 lobe, out vec4 light) {
  const SurfaceBrdf brdf = surfelBrdf[s];
  const vec4 arrival = surfelArrival[s];
  const float r = length(arrival.xyz), mu = r > 0.0 ? dot(n, arrival.xyz) / r : 0.0;
  vec3 sent = vec3(0.0);
  if (!isLambertian(brdf) && mu > 0.0) sent = lobeReflectanceOf(brdf, specularAlbedoAt(brdf, mu)) * surfelDirect[s].rgb;
  const bool sends = any(greaterThan(sent, vec3(0.0)));
  const float alpha = widenedLobe(brdf, 1.0 - min(r, 1.0)).alpha;
  lobe = vec4(sent, sends ? alpha : 0.0);
  light = sends ? vec4(arrival.xyz / r, sqrt(max(arrival.w, 0.0))) : vec4(0.0);
  senderLobes[2u * leaf] = lobe;
  senderLobes[2u * leaf + 1u] = light;
}

// Glossy senders send by direction what their lobes reflect of the direct light (kSenderLobes:
// some lobe is far from even, scene::kEvenLobeDeviation). A glossy leaf's radiosity B holds S,
// what its specular lobe reflects of the depth maps' direct light (common/send_lobe.glsl); sent
// evenly, S would leave as radiance S/π in every direction. It leaves instead along the lobe:
// toward ω, S·π·f(l, ω)/a(l)/π, l the direct light's mean direction and a(l) = ∫ f(l, ω) cos θ_ω dω
// the lobe's albedo toward l, which over the hemisphere gives back S. Inner nodes send their
// pulled-up radiosity evenly. Expects the specular albedo table declared as `specularAlbedo`; with
// SENDER_LOBES defined (the binding of `senderLobes`), also NODE_TEXELS.
#include "common/specular_albedo.glsl"

// What a leaf of normal n whose lobe (S, α) the light reaches from l sends along unit w beyond S
// sent evenly, as radiosity (π times the radiance): S·(π·f(l, w)/a(l) − 1). The lobe is taken at
// the leaf's centre for all of its disk. Across the disk the mirror direction turns by the disk's
// angular radius seen from the light plus `extent`, the solid angle of what the reader takes as one
// direction (the disk seen from the reader, or a table's bin): a lobe narrower than that turn would
// be sampled between the leaves rather than summed over them, so it is widened to span it (a
// spread of the radii's sum squared, over π; brdf.h's widenedLobe), at least to `leastSpread`.
// `lightRadius`: √ of the solid angle the leaf spans from the lights.
vec3 excessAlong(vec4 lobe, vec3 l, float lightRadius, vec3 n, vec3 w, float extent, float leastSpread) {
  const float nl = dot(n, l), nw = dot(n, w);
  const float turn = lightRadius + sqrt(max(extent, 0.0));
  const float spread = max(turn * turn / kPi, leastSpread);
  const float alpha = min(sqrt(lobe.w * lobe.w + spread), 1.0), a2 = alpha * alpha;
  const float f = ggxD(dot(n, normalize(l + w)), a2) * smithVisibility(nl, nw, a2);
  const vec2 table = specularAlbedoOf(alpha, nl);
  return lobe.rgb * (kPi * f / max(table.x + table.y, 1e-4) - 1.0);
}

#ifdef SENDER_LOBES
// Per node two texels: (S, α widened by the light's spread) with α = 0 where the node sends evenly;
// (l, √ of the solid angle the leaf spans from the lights). Zero for inner nodes.
layout(binding = SENDER_LOBES, rgba32f) readonly uniform imageBuffer senderLobes;
layout(constant_id = 28) const bool kSenderLobes = false;  // some lobe sends by direction

// Where sender q lies from point x: its normal, the unit direction w from it to x, and the squared
// sum of the radii (as √ of solid angles) that widen its lobe toward x: its disk's seen from x and
// `receiverExtent`, a receiver's larger than a point seen from q. False where x lies on q's centre.
bool senderToward(uint q, vec3 x, float receiverExtent, out vec3 n, out vec3 w, out float widening) {
  const vec4 positionArea = nodePositionArea(q);
  n = nodeNormalCone(q).xyz;
  const vec3 d = x - positionArea.xyz;
  const float d2 = dot(d, d);
  w = d * inversesqrt(max(d2, 1e-30));
  const float extent = positionArea.w * max(dot(n, w), 0.0) / (d2 + positionArea.w / kPi);
  const float radii = sqrt(extent) + sqrt(max(receiverExtent, 0.0));
  widening = radii * radii;
  return d2 > 0.0;
}

// What sender q sends toward point x beyond its radiosity sent evenly, as radiosity. A receiver
// larger than a point spans `receiverExtent` (solid angle) from q, which widens the lobe as q's own
// extent does.
vec3 excessToward(uint q, vec3 x, float receiverExtent, float leastSpread) {
  if (!kSenderLobes) return vec3(0.0);
  const vec4 lobe = imageLoad(senderLobes, int(2u * q));
  if (!(lobe.w > 0.0)) return vec3(0.0);
  vec3 n, w;
  float widening;
  if (!senderToward(q, x, receiverExtent, n, w, widening)) return vec3(0.0);
  const vec4 light = imageLoad(senderLobes, int(2u * q + 1u));
  return excessAlong(lobe, light.xyz, light.w, n, w, widening, leastSpread);
}

#ifdef ARRIVAL_LOBES
// Per node 2·kArrivalLobes texels, as senderLobes' two for each of the classes of the first
// bounce's arriving light its lobe reflects most (send_arrival.comp), the strongest first: what
// its lobe reflects of the class (S, α; α = 0: no more) and the class's mean direction (l, 0).
layout(binding = ARRIVAL_LOBES, rgba32f) readonly uniform imageBuffer arrivalLobes;

// What sender q, of normal n, sends along unit w beyond its radiosity sent evenly of the first
// bounce's light; `first`: its first texel, `widening` as senderToward gives it.
vec3 arrivalAlong(uint q, vec4 first, vec3 n, vec3 w, float widening, float leastSpread) {
  vec3 excess = vec3(0.0);
  const uint at = 2u * kArrivalLobes * q;
  for (uint c = 0u; c < kArrivalLobes; ++c) {
    const vec4 lobe = c == 0u ? first : imageLoad(arrivalLobes, int(at + 2u * c));
    if (lobe.w > 0.0)
      excess += excessAlong(lobe, imageLoad(arrivalLobes, int(at + 2u * c + 1u)).xyz, 0.0, n, w, widening, leastSpread);
  }
  return excess;
}
#endif
#endif

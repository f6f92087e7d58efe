// The specular albedo table's (A, B) toward cos θ = mu for material m (or α), bilinear. Expects the
// table declared as `specularAlbedo`, an rgba32f imageBuffer (texels, not a storage buffer: it is
// read in the loops over links, common.glsl) whose texel holds a node and the next in its row
// (scene::SpecularAlbedo::texels): two fetches a lookup, not four.
#ifndef SPECULAR_ALBEDO_GLSL
#define SPECULAR_ALBEDO_GLSL
vec2 specularAlbedoOf(float alpha, float mu) {
  const vec4 cell = albedoTableCell(mu, sqrt(alpha));
  const int t = int(uint(cell.y) * kAlbedoTableSize + uint(cell.x)), row = int(kAlbedoTableSize);
  const vec4 lower = imageLoad(specularAlbedo, t), upper = imageLoad(specularAlbedo, t + row);
  return mix(mix(lower.xy, lower.zw, cell.z), mix(upper.xy, upper.zw, cell.z), cell.w);
}
vec2 specularAlbedoAt(SurfaceBrdf m, float mu) { return specularAlbedoOf(m.alpha, mu); }
// Their cosine-weighted means over the hemisphere at α (the table's last row, by roughness:
// scene::SpecularAlbedo::meanAt).
vec2 specularAlbedoMeanOf(float alpha) {
  const vec4 cell = albedoTableCell(1.0, sqrt(alpha));
  const vec4 pair = imageLoad(specularAlbedo, int(kAlbedoTableSize * kAlbedoTableSize + uint(cell.y)));
  return mix(pair.xy, pair.zw, cell.w);
}
// Whether some dielectric's base sends its light far from evenly (scene::Geometry::directionalBases):
// else every base sends evenly.
layout(constant_id = 26) const bool kBasesByAngle = false;
// What m's base sends toward exit cosine mu beyond what it would send evenly, per unit of all m
// reflects of even light: under a glossy dielectric's layer the base leaves as (1 − E(μ))/(1 − Ē)
// of even (brdf.h's baseWeight), as the resolve shows it toward the camera. Zero for other materials.
// What of m does not change with the direction, for a pass that takes many: the base's share of all
// m reflects (base/all at the hemisphere's mean albedo) and 1/(1 − Ē); w = 0 where m's base is even.
vec4 baseShareOf(SurfaceBrdf m) {
  if (!kBasesByAngle || !baseLeavesByAngle(m)) return vec4(0.0);
  const vec2 mean = specularAlbedoMeanOf(m.alpha);
  const vec3 base = baseReflectanceOf(m, mean), all = base + lobeReflectanceOf(m, mean);
  return vec4(base / max(all, vec3(1e-6)), 1.0 / max(1.0 - layerAlbedo(m, mean), 1e-6));
}
vec3 baseBeyondEven(SurfaceBrdf m, vec4 share, float mu) {
  if (!(share.w > 0.0)) return vec3(0.0);
  return share.rgb * ((1.0 - layerAlbedo(m, specularAlbedoAt(m, max(mu, 0.0)))) * share.w - 1.0);
}
vec3 baseBeyondEven(SurfaceBrdf m, float mu) { return baseBeyondEven(m, baseShareOf(m), mu); }
#endif

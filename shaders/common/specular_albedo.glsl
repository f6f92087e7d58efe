// The specular albedo table's (A, B) (brdf.h's layout, engine/scene/reflectance.h) toward cos θ = mu
// for material m (or α), bilinear. Expects the table declared as `specularAlbedo` (vec2 per node).
#ifndef SPECULAR_ALBEDO_GLSL
#define SPECULAR_ALBEDO_GLSL
vec2 specularAlbedoOf(float alpha, float mu) {
  const vec4 cell = albedoTableCell(mu, sqrt(alpha));
  const uint at = uint(cell.y) * kAlbedoTableSize + uint(cell.x);
  return mix(mix(specularAlbedo[at], specularAlbedo[at + 1u], cell.z),
             mix(specularAlbedo[at + kAlbedoTableSize], specularAlbedo[at + kAlbedoTableSize + 1u], cell.z), cell.w);
}
vec2 specularAlbedoAt(SurfaceBrdf m, float mu) { return specularAlbedoOf(m.alpha, mu); }
#endif

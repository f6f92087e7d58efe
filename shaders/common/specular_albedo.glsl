// The specular albedo table's (A, B) (brdf.h's layout, engine/scene/reflectance.h) toward cos θ = mu
// for material m (or α), bilinear. Expects the table declared as `specularAlbedo`, an rg32f
// imageBuffer (texels, not a storage buffer: it is read in the loops over links, common.glsl).
#ifndef SPECULAR_ALBEDO_GLSL
#define SPECULAR_ALBEDO_GLSL
vec2 specularAlbedoOf(float alpha, float mu) {
  const vec4 cell = albedoTableCell(mu, sqrt(alpha));
  const uint at = uint(cell.y) * kAlbedoTableSize + uint(cell.x);
  const int t = int(at), row = int(kAlbedoTableSize);
  return mix(mix(imageLoad(specularAlbedo, t).xy, imageLoad(specularAlbedo, t + 1).xy, cell.z),
             mix(imageLoad(specularAlbedo, t + row).xy, imageLoad(specularAlbedo, t + row + 1).xy, cell.z), cell.w);
}
vec2 specularAlbedoAt(SurfaceBrdf m, float mu) { return specularAlbedoOf(m.alpha, mu); }
// Their cosine-weighted means over the hemisphere at α (the table's last row, by roughness:
// scene::SpecularAlbedo::meanAt).
vec2 specularAlbedoMeanOf(float alpha) {
  const vec4 cell = albedoTableCell(1.0, sqrt(alpha));
  const int at = int(kAlbedoTableSize * kAlbedoTableSize + uint(cell.y));
  return mix(imageLoad(specularAlbedo, at).xy, imageLoad(specularAlbedo, at + 1).xy, cell.w);
}
#endif

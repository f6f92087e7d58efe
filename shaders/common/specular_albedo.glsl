// The specular albedo table's (A, B) (brdf.h's layout, engine/scene/reflectance.h) toward cos θ = mu
// for material m, bilinear. Expects the table declared as `specularAlbedo` (vec2 per node).
vec2 specularAlbedoAt(SurfaceBrdf m, float mu) {
  const vec4 cell = albedoTableCell(mu, sqrt(m.alpha));
  const uint at = uint(cell.y) * kAlbedoTableSize + uint(cell.x);
  return mix(mix(specularAlbedo[at], specularAlbedo[at + 1u], cell.z),
             mix(specularAlbedo[at + kAlbedoTableSize], specularAlbedo[at + kAlbedoTableSize + 1u], cell.z), cell.w);
}

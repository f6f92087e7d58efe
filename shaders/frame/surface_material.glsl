// The material at a point the camera's raster hit (resolve, direct_pixels): base colour (factor ×
// texture × vertex colour), emission, and glTF's metallic-roughness (brdf.h). Expects `materials`,
// `uvs`, `colors`, `textures` and `texels` declared before it (textures.glsl), the constants kTextured (some
// material has a texture), kColored (some primitive has COLOR_0), kNormalMapped (some material has
// a normal texture) and kGlossy (some material is not Lambertian), and surface_hit.glsl included.

#include "textures.glsl"

struct SurfaceMaterial {
  SurfaceBrdf brdf;  // base colour, the dielectric's reflectance, metallic, α
  vec3 emission;
  float roughness;  // as the file gives it (brdf.alpha is its square, clamped)
};

// The material of triangle t (v0, v1, v2, material | kFlatShaded) at barycentric weights w.
SurfaceMaterial materialAt(uvec4 t, vec3 w) {
  const uint mi = t.w & ~kTriangleFlags;
  SurfaceMaterial m;
  vec3 base = uintBitsToFloat(imageLoad(materials, int(kMaterialTexels * mi)).rgb);
  m.emission = uintBitsToFloat(imageLoad(materials, int(kMaterialTexels * mi + 1u)).rgb);
  const vec4 specular = uintBitsToFloat(imageLoad(materials, int(kMaterialTexels * mi + 2u)));
  vec2 metalRough = uintBitsToFloat(imageLoad(materials, int(kMaterialTexels * mi + 4u)).xy);
  if (kColored) base *= w.x * colorOf(t.x) + w.y * colorOf(t.y) + w.z * colorOf(t.z);
  if (kTextured) {
    const vec4 uv = w.x * uvOf(t.x) + w.y * uvOf(t.y) + w.z * uvOf(t.z);
    // base colour, emissive, metallic-roughness; -1: none
    const ivec3 maps = ivec3(imageLoad(materials, int(kMaterialTexels * mi + 3u)).xyz);
    base *= sampleTexture(maps.x, uv).rgb;
    m.emission *= sampleTexture(maps.y, uv).rgb;
    metalRough *= sampleTexture(maps.z, uv).bg;
  }
  m.roughness = metalRough.y;
  m.brdf = SurfaceBrdf(vec4(base, 0.0), specular, metalRough.x, alphaOf(metalRough.y), 0.0, 0.0);
  return m;
}

// The shading normal at barycentric weights w of triangle t (v0, v1, v2, material) whose unit normal
// there is n: n turned by its material's normal texture, as the host's scene::mappedNormalAt.
vec3 mappedNormalAt(uvec4 t, vec3 w, vec3 n) {
  if (!kNormalMapped) return n;
  const uint mi = t.w & ~kTriangleFlags;
  const int index = int(imageLoad(materials, int(kMaterialTexels * mi + 3u)).w);
  if (index < 0) return n;
  const float scale = uintBitsToFloat(imageLoad(materials, int(kMaterialTexels * mi + 4u)).z);
  const Texture map = textures[index];
  const vec4 a = uvOf(t.x), b = uvOf(t.y), c = uvOf(t.z);
  return mappedNormal(n, positionOf(t.x), positionOf(t.y), positionOf(t.z), transformedUv(map, a),
                      transformedUv(map, b), transformedUv(map, c),
                      sampleTexture(index, w.x * a + w.y * b + w.z * c).rgb, scale);
}

// h's face normal (unit) on the side of its unit normal n; zero on a degenerate triangle.
vec3 faceNormalOf(SurfaceHit h, vec3 n) {
  const float faceLength = length(h.face);
  return faceLength > 0.0 ? h.face / faceLength * (dot(h.face, n) < 0.0 ? -1.0 : 1.0) : vec3(0.0);
}

// The normal hit h shades with, as pt's paths take it (path_tracer.cpp), where its unit normal is n,
// its face normal `face` (faceNormalOf) and the eye lies along unit toEye: n turned by the normal
// texture, then lifted so that the view's mirror image stays above the triangle's plane (scene.h's
// liftedShadingNormal). Only a normal texture or a lobe reads the difference; elsewhere n as it is.
vec3 shadingNormalAt(SurfaceHit h, vec3 n, vec3 face, vec3 toEye) {
  const vec3 mapped = mappedNormalAt(h.triangle, h.weights, n);
  if (!(kNormalMapped || kGlossy)) return mapped;
  return dot(face, toEye) > 0.0 ? liftedShadingNormal(face, toEye, mapped) : mapped;
}

// The share of a lobe of roughness α about `shading` that a face of unit normal `face` leaves above
// its plane, seen from unit toEye (brdf.h's lobeShareAbove); 1 where the face does not face the eye.
float lobeShareAt(vec3 face, vec3 shading, vec3 toEye, float alpha) {
  const float nv = dot(shading, toEye);
  if (!(dot(face, toEye) > 0.0) || !(nv > 0.0)) return 1.0;
  // The lobe's frame turned so that the face's normal leans along its first axis: the quadrature
  // then depends on the geometry alone.
  const vec3 lean = face - shading * dot(face, shading);
  const float leanLength = length(lean);
  if (!(leanLength > 1e-6)) return 1.0;  // the face's plane is the lobe's own horizon
  const vec3 t1 = lean / leanLength, t2 = cross(shading, t1);
  return lobeShareAbove(alpha, vec3(dot(toEye, t1), dot(toEye, t2), nv), vec3(leanLength, 0.0, dot(face, shading)));
}

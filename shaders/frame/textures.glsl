// The scene's texture lookups at a point of a triangle: its coordinate sets, vertex colour, a
// material's textures, and whether the material cuts the surface away there. Expects `uvs`,
// `colors`, `materials`, `textures` and `texels` declared before it.

vec4 uvOf(uint vertex) { return imageLoad(uvs, int(vertex)); }  // TEXCOORD_0 (xy), TEXCOORD_1 (zw)
vec3 colorOf(uint vertex) { return imageLoad(colors, int(vertex)).rgb; }

// (`texels` are read as texels, not a storage buffer: a bilinear sample reads four, common.glsl.)
vec4 texel(Texture t, int x, int y) {
  const uvec2 words = imageLoad(texels, int(t.offset + uint(y) * t.width + uint(x))).xy;
  return vec4(unpackHalf2x16(words.x), unpackHalf2x16(words.y));
}

vec4 sampleTexture(int index, vec4 uvs) {
  if (index < 0) return vec4(1.0);
  Texture t = textures[index];
  if (t.width == 0u || t.height == 0u) return vec4(1.0);
  const vec2 uv = transformedUv(t, uvs);
  float ax, ay;
  ivec2 xs = texelPair(uv.x, int(t.width), t.wrap & 0xffffu, ax), ys = texelPair(uv.y, int(t.height), t.wrap >> 16, ay);
  ax = texelWeight(t, ax), ay = texelWeight(t, ay);
  return mix(mix(texel(t, xs.x, ys.x), texel(t, xs.y, ys.x), ax), mix(texel(t, xs.x, ys.y), texel(t, xs.y, ys.y), ax),
             ay);
}

// Whether triangle t's (v0, v1, v2, material | flags) material takes any of its surface away
// (alphaMode MASK or BLEND).
float alphaCutoffOf(uvec4 t) {
  return uintBitsToFloat(imageLoad(materials, int(kMaterialTexels * (t.w & ~kTriangleFlags) + 4u)).w);
}
bool materialCuts(uvec4 t) { return alphaMatters(alphaCutoffOf(t)); }

// How much of triangle t (v0, v1, v2, material | flags) is there at barycentric weights w
// (presenceOf over the base colour's alpha, factor × texture × COLOR_0; scene::presenceAt).
float presenceAt(uvec4 t, vec3 w) {
  const float cutoff = alphaCutoffOf(t);
  if (!alphaMatters(cutoff)) return 1.0;
  const uint texelsAt = kMaterialTexels * (t.w & ~kTriangleFlags);
  const vec4 uv = w.x * uvOf(t.x) + w.y * uvOf(t.y) + w.z * uvOf(t.z);
  const float color =
      w.x * imageLoad(colors, int(t.x)).a + w.y * imageLoad(colors, int(t.y)).a + w.z * imageLoad(colors, int(t.z)).a;
  const float alpha = uintBitsToFloat(imageLoad(materials, int(texelsAt)).a) * color *
                      sampleTexture(int(imageLoad(materials, int(texelsAt + 3u)).x), uv).a;
  return presenceOf(alpha, cutoff);
}

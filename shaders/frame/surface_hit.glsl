// The surface a sample of the camera's raster hit (resolve, direct_pixels): its triangle, where on it
// and its shading normal. Expects `world`, `triangles` and `visibility` declared before it.

vec3 positionOf(uint vertex) { return imageLoad(world, int(2u * vertex)).xyz; }
vec3 normalOf(uint vertex) { return imageLoad(world, int(2u * vertex + 1u)).xyz; }

struct SurfaceHit {
  bool hit;        // false: the sample sees nothing
  uvec4 triangle;  // v0, v1, v2, material
  vec3 weights;    // the corners' barycentric weights
  vec3 position;
  vec3 normal;  // the shading normal (flat shaded: the winding's), not normalized; zero on a degenerate triangle
  vec3 face;    // the winding's normal, not normalized
  float depth;  // the raster's depth
};

// Sample `s` of the `fine` grid of samples the camera's raster cast.
SurfaceHit surfaceHit(Camera camera, uvec2 s, uvec2 fine) {
  SurfaceHit h;
  const uint64_t key = packUint2x32(imageLoad(visibility, int(s.y * fine.x + s.x)).xy);
  h.hit = key != kEmptyVisibility;
  if (!h.hit) return h;
  const uvec4 t = imageLoad(triangles, int(keyId(key)));
  const vec3 a = positionOf(t.x), b = positionOf(t.y), c = positionOf(t.z);
  float tHit;
  vec2 bc;
  const vec3 ray = cameraRay(camera, vec2(s) + 0.5, fine), from = cameraRayOrigin(camera, vec2(s) + 0.5, fine);
  intersectTriangle(from, ray, a, b, c, tHit, bc);
  h.triangle = t;
  h.weights = vec3(1.0 - bc.x - bc.y, bc.x, bc.y);
  h.position = from + tHit * ray;
  h.face = h.normal = cross(b - a, c - a);
  if ((t.w & kFlatShaded) == 0u)
    h.normal = h.weights.x * normalOf(t.x) + h.weights.y * normalOf(t.y) + h.weights.z * normalOf(t.z);
  h.depth = keyDepth(key);
  return h;
}

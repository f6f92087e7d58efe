// A triangle's bounds in a view and how the rasteriser walks them (raster.comp, raster_slices.comp).
// Expects `world`, `triangles`, `views` and `push` (RasterPush) declared before it.

// Bounds holding at most this many samples are walked by the triangle's own invocation.
const int kSmallBounds = 256;
// Samples of slack around a triangle's projected bounds: float rounding there is far below it.
const float kBoundsSlack = 1.0 / 16.0;

// Sample-space x/y of a world point at distance z (> 0) along the view's forward axis (an
// orthographic view's do not depend on z).
vec2 projectAt(Camera camera, vec3 p, float z) {
  const vec3 d = p - camera.origin.xyz;
  const vec2 ndc = vec2(dot(d, camera.right.xyz) / dot(camera.right.xyz, camera.right.xyz),
                        dot(d, camera.up.xyz) / dot(camera.up.xyz, camera.up.xyz)) /
                   (camera.up.w == kOrthographic ? 1.0 : z);
  return vec2((ndc.x + 1.0) * 0.5 * float(push.size.x), (1.0 - ndc.y) * 0.5 * float(push.size.y));
}

// A triangle's corners, from the world vertices.
struct Corners {
  vec3 a, b, c;
};
Corners cornersOf(uint tri) {
  const uvec4 v = imageLoad(triangles, int(tri));
  return Corners(imageLoad(world, int(2u * v.x)).xyz, imageLoad(world, int(2u * v.y)).xyz,
                 imageLoad(world, int(2u * v.z)).xyz);
}

// The samples whose centres (x + 0.5) lie within sample-space bounds [mn, mx], widened by
// kBoundsSlack for the rounding between the projection and the ray test that decides: a triangle
// smaller than a sample mostly walks none. Empty (hi < lo) where nothing of them is on screen.
void boundsOf(vec2 mn, vec2 mx, out ivec2 lo, out ivec2 hi) {
  const vec2 far = vec2(push.size) + 2.0;  // past it, bounds convert to int safely and stay off screen
  lo = max(ivec2(0), ivec2(ceil(clamp(mn - 0.5 - kBoundsSlack, vec2(-2.0), far))));
  hi = min(ivec2(push.size) - 1, ivec2(floor(clamp(mx - 0.5 + kBoundsSlack, vec2(-2.0), far))));
  if (mx.x < -1.0 || mx.y < -1.0 || mn.x > float(push.size.x) + 1.0 || mn.y > float(push.size.y) + 1.0)
    hi = ivec2(-1);  // off screen, or wholly behind the near plane (mn > mx)
}

// A triangle's corners and its screen bounds (empty: nothing of it on screen).
struct Projected {
  vec3 a, b, c;
  ivec2 lo, hi;
};
// The bounds are those of the part of the triangle beyond the near plane (the triangle clipped by
// it), so that a triangle reaching behind the camera walks only what it can cover, and one wholly
// behind walks nothing.
Projected projected(Camera camera, Corners k) {
  Projected t;
  t.a = k.a, t.b = k.b, t.c = k.c;
  const vec3 corner[3] = vec3[3](t.a, t.b, t.c);
  const float near = camera.origin.w;
  float z[3];
  for (int i = 0; i < 3; ++i) z[i] = dot(corner[i] - camera.origin.xyz, camera.forward.xyz);
  vec2 mn = vec2(3.4e38), mx = vec2(-3.4e38);
  for (int i = 0; i < 3; ++i) {
    const int j = i == 2 ? 0 : i + 1;
    if (z[i] > near) {
      const vec2 s = projectAt(camera, corner[i], z[i]);
      mn = min(mn, s), mx = max(mx, s);
    }
    if ((z[i] > near) != (z[j] > near)) {  // the edge crosses the near plane: where it does
      const vec2 s = projectAt(camera, mix(corner[i], corner[j], (near - z[i]) / (z[j] - z[i])), near);
      mn = min(mn, s), mx = max(mx, s);
    }
  }
  boundsOf(mn, mx, t.lo, t.hi);
  return t;
}

// Larger bounds are walked in 8×8 tiles, at most `tilesPerSlice` of them by one workgroup: a block
// of tile columns as wide as the bounds or `tilesPerSlice`, and as many tile rows as fit. The
// bounds are cut into columnBlocks × rowBlocks such slices.
struct Slicing {
  int columns, rows, columnBlocks, rowBlocks;
};
Slicing slicing(Projected t, int tilesPerSlice) {
  Slicing s;
  const int tileColumns = (t.hi.x - t.lo.x) / 8 + 1, tileRows = (t.hi.y - t.lo.y) / 8 + 1;
  s.columns = min(tileColumns, tilesPerSlice);
  s.columnBlocks = (tileColumns + s.columns - 1) / s.columns;
  s.rows = max(1, tilesPerSlice / s.columns);
  s.rowBlocks = (tileRows + s.rows - 1) / s.rows;
  return s;
}

// Whether triangle t's bounds are on screen and walked by its workgroup in tiles.
bool isLarge(Projected t) {
  const ivec2 extent = t.hi - t.lo + 1;
  return all(greaterThan(extent, ivec2(0))) && extent.x * extent.y > kSmallBounds;
}

// A triangle's screen bounds and how the rasteriser walks them (raster.comp, raster_slices.comp).
// Expects `world`, `triangles` and `push` (RasterPush) declared before it.

// Bounds holding at most this many samples are walked by the triangle's own invocation.
const int kSmallBounds = 256;

// Sample-space x/y of a world point, or false when it lies at or behind the near plane.
bool project(vec3 p, out vec2 s) {
  vec3 d = p - push.camera.origin.xyz;
  float z = dot(d, push.camera.forward.xyz);
  s = vec2(0.0);
  if (z <= push.camera.origin.w) return false;
  vec2 ndc = vec2(dot(d, push.camera.right.xyz) / dot(push.camera.right.xyz, push.camera.right.xyz),
                  dot(d, push.camera.up.xyz) / dot(push.camera.up.xyz, push.camera.up.xyz)) /
             z;
  s = vec2((ndc.x + 1.0) * 0.5 * float(push.size.x), (1.0 - ndc.y) * 0.5 * float(push.size.y));
  return true;
}

// Triangle `tri`'s corners and its screen bounds (empty: nothing of it on screen).
struct Projected {
  vec3 a, b, c;
  ivec2 lo, hi;
};
Projected projected(uint tri) {
  Projected t;
  uvec4 v = imageLoad(triangles, int(tri));
  t.a = imageLoad(world, int(2u * v.x)).xyz, t.b = imageLoad(world, int(2u * v.y)).xyz,
  t.c = imageLoad(world, int(2u * v.z)).xyz;
  vec2 pa, pb, pc;
  t.lo = ivec2(0), t.hi = ivec2(push.size) - 1;
  if (project(t.a, pa) && project(t.b, pb) && project(t.c, pc)) {
    vec2 mn = min(pa, min(pb, pc)), mx = max(pa, max(pb, pc));
    if (mx.x < -1.0 || mx.y < -1.0 || mn.x > float(push.size.x) + 1.0 || mn.y > float(push.size.y) + 1.0)
      t.hi = ivec2(-1);
    t.lo = max(t.lo, ivec2(floor(mn)) - 1);
    t.hi = min(t.hi, ivec2(ceil(mx)));
  }  // else: a vertex behind the near plane, so the whole image is a conservative bound
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

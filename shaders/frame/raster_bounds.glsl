// A triangle's bounds in a view and how the rasteriser walks them (raster.comp, raster_slices.comp,
// drawn_bounds.comp). Expects `world`, `triangles` and `push` (RasterPush) declared before it.
#include "view_bounds.glsl"

// Bounds holding at most this many samples are walked by the triangle's own invocation.
const int kSmallBounds = 256;
// A triangle's corners, from the world vertices.
struct Corners {
  vec3 a, b, c;
};
Corners cornersOf(uint tri) {
  const uvec4 v = imageLoad(triangles, int(tri));
  return Corners(imageLoad(world, int(2u * v.x)).xyz, imageLoad(world, int(2u * v.y)).xyz,
                 imageLoad(world, int(2u * v.z)).xyz);
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

// The box around the workgroup's triangles (min x, y, z, max x, y, z as orderedBits). Every
// invocation calls it (it holds barriers); `has`: whether k is a triangle.
shared uint groupBox[6];
void gatherGroupBox(bool has, Corners k, out vec3 lo, out vec3 hi) {
  const uint lid = gl_LocalInvocationID.x;
  if (lid < 6u) groupBox[lid] = lid < 3u ? 0xFFFFFFFFu : 0u;
  barrier();
  if (has)
    for (int axis = 0; axis < 3; ++axis) {
      atomicMin(groupBox[axis], orderedBits(min(k.a[axis], min(k.b[axis], k.c[axis]))));
      atomicMax(groupBox[3 + axis], orderedBits(max(k.a[axis], max(k.b[axis], k.c[axis]))));
    }
  barrier();
  fromOrderedBox(groupBox, lo, hi);
  if (groupBox[0] > groupBox[3]) lo = vec3(3.4e38), hi = vec3(-3.4e38);  // no triangle
}

#version 460
// The raster pass, last: each invocation takes a triangle and projects it into a few views (a camera,
// or faces of lights' cubes of depth maps), one after another: workgroups z are the views drawn_views
// listed, kViewsPerGroup to a workgroup, so that a workgroup starts and reads a triangle's corners
// once for them all (most of what a small triangle costs a view), each batch in as many slices as
// the largest bounds need (raster_slices). Where its bounds in a view hold at most kSmallBounds
// samples the invocation walks them itself, sample by sample; the workgroup walks each larger
// triangle in each view together after, in 8×8 tiles (no integer division in the loops: lavapipe
// divides one lane at a time). At every sample the camera ray through its centre is cast and the
// nearest hit kept by 64-bit atomicMin. lavapipe starts a workgroup at a cost of its own, so the
// many small triangles of a tessellated scene go 64 to a workgroup. A workgroup walks at most
// kTilesPerSlice tiles of each large triangle in each view, so that its subgroups stay within
// lavapipe's loop budget (common.glsl; past it a triangle would silently lose some of its samples);
// bounds holding more are cut into slices of tiles, a workgroup a slice (raster_slices counts as
// many as the largest bounds need).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;
// Of each large triangle of the workgroup's 64 in each of its views: kViewsPerGroup × 64 × tiles
// stays under the budget (engine/gi/raster.cpp).
layout(constant_id = 0) const int kTilesPerSlice = 896;
// True for depth maps: the nearest depth alone (`depths`, 32 bits: non-negative floats order as their
// bits), no triangle key (`visibility`).
layout(constant_id = 1) const bool kDepthOnly = false;
// Where some material's alpha takes its surface away (alphaMode MASK or BLEND), the triangles are drawn in two
// dispatches: those that do not cut (kDrawUncut), then those that do (kDrawCutting), whose samples
// are tested. lavapipe runs both sides of a branch, so the test's lookups would cost every sample
// of a dispatch that held them. kDrawAll: no material cuts.
const uint kDrawAll = 0u, kDrawUncut = 1u, kDrawCutting = 2u;
layout(constant_id = 2) const uint kDraw = kDrawAll;
layout(constant_id = 3) const uint kViewsPerGroup = 1;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;           // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;     // Triangle
layout(std430, binding = 2) buffer Visibility { uint64_t visibility[]; };  // view after view
layout(binding = 3, rgba32f) readonly uniform imageBuffer views;           // Camera
layout(std430, binding = 4) buffer Depths { uint depths[]; };              // kDepthOnly: the depth's float bits
// The views drawn (drawn_views): their count, then each one's index in `views`.
layout(std430, binding = 5) readonly buffer DrawnViews { uint drawnViews[]; };
// What a material whose alpha takes surface away (alphaMode MASK, BLEND) reads to know where (textures.glsl).
layout(binding = 6, rgba32f) readonly uniform imageBuffer uvs;
layout(binding = 7, rgba32f) readonly uniform imageBuffer colors;
layout(binding = 8, rgba32ui) readonly uniform uimageBuffer materials;
layout(std430, binding = 9) readonly buffer Textures { Texture textures[]; };
layout(binding = 10, rg32ui) readonly uniform uimageBuffer texels;
layout(push_constant) uniform Push { RasterPush push; };
#include "raster_bounds.glsl"
#include "textures.glsl"

shared uint largeCount;
shared uvec2 large[64 * kViewsPerGroup];  // (triangle, view)

Camera camera;   // the view being drawn
uint viewStart;  // its first sample in `visibility`

// A twinned face (kTwinned) and its twin lie in one place, facing apart, and the camera sees the one
// that faces it: this one's front, the side its vertex normals face (flat shaded: its corners'
// counter-clockwise side), as its surfels'. Zero for any other face, seen from either side, and in
// a depth map, where either twin stands for both.
vec3 twinFront(uint tri, Projected t) {
  if (kDepthOnly) return vec3(0.0);
  const uvec4 v = imageLoad(triangles, int(tri));
  if ((v.w & kTwinned) == 0u) return vec3(0.0);
  const vec3 normals = imageLoad(world, int(2u * v.x + 1u)).xyz + imageLoad(world, int(2u * v.y + 1u)).xyz +
                       imageLoad(world, int(2u * v.z + 1u)).xyz;
  return faceFront(t.a, t.b, t.c, normals, (v.w & kFlatShaded) != 0u);
}

// Whether this dispatch draws triangle tri (kDraw).
bool drawnHere(uint tri) {
  return kDraw == kDrawAll || materialCuts(imageLoad(triangles, int(tri))) == (kDraw == kDrawCutting);
}

void castSample(uint tri, Projected t, vec3 front, ivec2 px) {
  vec3 dir = cameraRay(camera, vec2(px) + 0.5, push.size);
  if (dot(front, dir) > 0.0) return;  // a twin seen from behind
  float depth;
  vec2 uv;
  if (!intersectTriangle(cameraRayOrigin(camera, vec2(px) + 0.5, push.size), dir, t.a, t.b, t.c, depth, uv)) return;
  if (depth <= camera.origin.w || (camera.forward.w > 0.0 && depth > camera.forward.w)) return;
  const uint at = viewStart + uint(px.y) * push.size.x + uint(px.x);
  // A blended surface is there for its alpha's share of the samples, each its own (at, tri).
  if (kDraw == kDrawCutting &&
      cutAway(presenceAt(imageLoad(triangles, int(tri)), vec3(1.0 - uv.x - uv.y, uv)), unitHash(at, tri)))
    return;
  if (kDepthOnly)
    atomicMin(depths[at], floatBitsToUint(depth));
  else
    atomicMin(visibility[at], packDepthKey(depth, tri));
}

// Draws triangle `tri` (its corners `k`) into view `view` where its bounds are small; lists it for
// the workgroup to draw together where they are large.
void drawView(uint view, uint tri, Corners k, uint slice) {
  camera = CAMERA_TEXELS(views, view);
  viewStart = view * push.size.x * push.size.y;
  const Projected t = projected(camera, k);
  if (isLarge(t)) {
    large[atomicAdd(largeCount, 1u)] = uvec2(tri, view);
  } else if (slice == 0u) {  // empty bounds walk nothing
    const vec3 front = twinFront(tri, t);
    for (int y = t.lo.y; y <= t.hi.y; ++y)
      for (int x = t.lo.x; x <= t.hi.x; ++x) castSample(tri, t, front, ivec2(x, y));
  }
}

void main() {
  const uint listed = drawnViews[0], batches = (listed + kViewsPerGroup - 1u) / kViewsPerGroup,
             slices = gl_NumWorkGroups.z / batches, batch = gl_WorkGroupID.z / slices,
             slice = gl_WorkGroupID.z - batch * slices;
  const uint lid = gl_LocalInvocationID.x;
  if (lid == 0u) largeCount = 0u;
  barrier();
  const uint tri = itemIndex();
  if (tri < push.triangleCount && drawnHere(tri)) {
    const Corners k = cornersOf(tri);
    for (uint d = batch * kViewsPerGroup; d < min(listed, (batch + 1u) * kViewsPerGroup); ++d)
      drawView(drawnViews[1u + d], tri, k, slice);
  }
  barrier();
  // The large ones together: this workgroup's slice of each, at most kTilesPerSlice tiles of it (a
  // block of tile columns, as wide as the bounds or kTilesPerSlice, and as many tile rows as fit).
  const ivec2 lane = ivec2(lid & 7u, lid >> 3u);
  for (uint n = 0u; n < largeCount; ++n) {
    const uint tri = large[n].x, view = large[n].y;
    camera = CAMERA_TEXELS(views, view);
    viewStart = view * push.size.x * push.size.y;
    const Projected t = projected(camera, cornersOf(tri));
    const vec3 front = twinFront(tri, t);
    const Slicing s = slicing(t, kTilesPerSlice);
    const int z = int(slice), rowBlock = z / s.columnBlocks, columnBlock = z - rowBlock * s.columnBlocks;
    const ivec2 first = t.lo + 8 * ivec2(s.columns * columnBlock, s.rows * rowBlock),
                last = min(t.hi, first + 8 * ivec2(s.columns, s.rows) - 1);
    // One loop round a tile (the budget counts rounds), the tile stepped along its rows.
    const int columns = (last.x - first.x) / 8 + 1, tiles = columns * ((last.y - first.y) / 8 + 1);
    ivec2 tile = first;
    for (int i = 0, column = 0; i < tiles; ++i) {
      const ivec2 px = tile + lane;
      if (all(lessThanEqual(px, last))) castSample(tri, t, front, px);
      if (++column == columns)
        column = 0, tile = ivec2(first.x, tile.y + 8);
      else
        tile.x += 8;
    }
  }
}

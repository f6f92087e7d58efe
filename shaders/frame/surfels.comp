#version 460
// The surfel pass: area = a third of the adjacent triangles (less what the material cuts away); position = the centroid
// of that area (the vertex's corner quad of each triangle: vertex, edge midpoints, centroid), so that a surfel on a
// hard edge lies inside its own face; normal from the welded vertex normals or, where the mesh has none, area-weighted
// face normals.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer SurfelSources { SurfelSource sources[]; };
// Read in the loops over a surfel's triangles: texels (common.glsl).
layout(binding = 1, r32ui) readonly uniform uimageBuffer surfelVertices;
layout(binding = 2, r32ui) readonly uniform uimageBuffer surfelTriangles;
layout(binding = 3, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(binding = 4, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(std430, binding = 5) writeonly buffer Surfels { Surfel surfels[]; };
// The surfels of the objects that move: the others keep what a frame before gave them.
layout(binding = 6, r32ui) readonly uniform uimageBuffer movingSurfels;
// The share of each surfel's area its material's alpha leaves (alphaMode MASK, BLEND; 1 elsewhere).
layout(binding = 7, r32f) readonly uniform imageBuffer surfelCoverage;
layout(push_constant) uniform Push { ListedPush push; };  // the surfels, or those listed

vec3 positionOf(uint v) { return imageLoad(world, int(2u * v)).xyz; }
// The k-th of the surfel's triangles: its vertices' positions.
void triangleOf(SurfelSource src, uint k, out vec3 a, out vec3 b, out vec3 c) {
  const uvec4 t = imageLoad(triangles, int(imageLoad(surfelTriangles, int(src.firstTriangle + k)).x));
  a = positionOf(t.x), b = positionOf(t.y), c = positionOf(t.z);
}

void main() {
  uint s = itemIndex();
  if (s >= push.count) return;
  if (push.listed != 0u) s = imageLoad(movingSurfels, int(s)).x;
  SurfelSource src = sources[s];
  float area = 0.0;
  vec3 faceSum = vec3(0.0), vertexSum = vec3(0.0), moment = vec3(0.0);
  vec3 self = positionOf(imageLoad(surfelVertices, int(src.firstVertex)).x);
  for (uint k = 0; k < src.triangleCount; ++k) {
    vec3 a, b, c;
    triangleOf(src, k, a, b, c);
    vec3 n = cross(b - a, c - a);
    float third = length(n) / 6.0;
    area += third;
    faceSum += n;
    moment += third * (22.0 * self + 7.0 * (a + b + c - self)) / 36.0;  // the other two vertices: a + b + c - self
  }
  for (uint k = 0; k < src.vertexCount; ++k)
    vertexSum += imageLoad(world, int(2u * imageLoad(surfelVertices, int(src.firstVertex + k)).x + 1u)).xyz;
  vec3 n = length(vertexSum) > 1e-6 ? vertexSum : faceSum;
  float len = length(n);
  vec3 centre = area > 0.0 ? moment / area : self, normal = len > 0.0 ? n / len : vec3(0.0);
  // The surfel's rectangle, centred on its centroid and scaled to its area: on a regular grid an inner
  // surfel is the square of its cell and one on a border the half-cell strip it covers, so that
  // neighbours tile the view as their surfaces do (a gap between them, seen from near, spans bins).
  // A fan whose edges span nothing along an axis (degenerate) is the square of its area.
  vec3 t1, t2;
  tangentFrame(len > 0.0 ? normal : vec3(0.0, 0.0, 1.0), t1, t2);
  // Its axes follow the mesh's edges (their directions modulo a right angle, weighted by length), so
  // that on a grid the rectangles of neighbours share their sides whatever the grid's turn.
  vec2 quarter = vec2(0.0);
  for (uint k = 0; k < src.triangleCount; ++k) {
    vec3 a, b, c;
    triangleOf(src, k, a, b, c);
    quarter += edgeQuarterTurns(a, b, c, t1, t2);
  }
  float angle = quarterAngle(quarter);
  vec3 u1, u2;
  rectangleAxes(len > 0.0 ? normal : vec3(0.0, 0.0, 1.0), angle, u1, u2);
  // Along each axis, half way to the farthest neighbour either side (a border surfel reaches from its
  // vertex half way in), so that on a grid neighbours' rectangles meet.
  vec4 reach = vec4(0.0);  // +u1, -u1, +u2, -u2
  for (uint k = 0; k < src.triangleCount; ++k) {
    vec3 a, b, c;
    triangleOf(src, k, a, b, c);
    vec2 e1 = vec2(dot(a - self, u1), dot(a - self, u2)), e2 = vec2(dot(b - self, u1), dot(b - self, u2)),
         e3 = vec2(dot(c - self, u1), dot(c - self, u2));
    reach = max(reach, max(vec4(e1, -e1).xzyw, max(vec4(e2, -e2).xzyw, vec4(e3, -e3).xzyw)));
  }
  // What the material cuts away is not there: the surfel keeps the rest of its area, on the same
  // rectangle's shape (a leaf's holes let through what they would on average).
  area *= imageLoad(surfelCoverage, int(s)).x;
  vec2 extent = 0.25 * (reach.xz + reach.yw);
  extent = extent.x * extent.y > 0.0 ? extent * sqrt(area / (4.0 * extent.x * extent.y)) : vec2(0.5 * sqrt(area));
  surfels[s].positionArea = vec4(centre, len > 0.0 ? area : 0.0);
  surfels[s].normal = vec4(normal, 0.0);
  surfels[s].shape = vec4(sqrt(area / kPi), angle, extent);
}

#version 460
// The refit: node attributes bottom-up, the trees in one dispatch (climb.glsl). Leaves copy their
// surfel; inner nodes combine their children, already refit. Once every tree is refit, a frame refits
// only the trees of the objects that move.
//
// Each node also gets the rectangle that has its area's second moments in its tangent plane
// (half-extents √3·σ along its principal axes, or its children's where those are not clear):
// prune files a near sender as pieces of that rectangle, so that neighbouring nodes tile the view
// as their surfaces do (disks of the same areas would overlap at their sides and leave gaps at
// their corners, a tenth of the coverage). A leaf takes its surfel's rectangle (surfels.comp).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Tree { TreeNode tree[]; };
layout(std430, binding = 1) readonly buffer Surfels { Surfel surfels[]; };
layout(std430, binding = 2) coherent buffer Nodes { NodeState nodes[]; };
// Per node, Σ a·n over its surfels (xyz; w unused): its vector area, which the winding number of a
// far node takes (buried_surfels).
layout(std430, binding = 4) coherent buffer NodeVectorArea { vec4 nodeVectorArea[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: the leaves listed

uvec4 treeNodeAt(uint i) {
  const TreeNode t = tree[i];
  return uvec4(uint(t.parent), t.firstChild, t.childCount, uint(t.surfel));
}

// Second moments of a node's area about `centre`, in the tangent axes (a, b), per unit area:
// its rectangle's own (uniform over ±e: e²/3 along each axis) plus its offset.
vec3 secondMoments(NodeState node, vec3 centre, vec3 a, vec3 b) {
  vec3 u1, u2, d = node.positionArea.xyz - centre;
  rectangleAxes(node.normalCone.xyz, node.shape.y, u1, u2);
  vec2 e2 = node.shape.zw * node.shape.zw / 3.0;
  vec2 pa = vec2(dot(u1, a), dot(u2, a)), pb = vec2(dot(u1, b), dot(u2, b));
  float da = dot(d, a), db = dot(d, b);
  return vec3(dot(e2, pa * pa) + da * da, dot(e2, pb * pb) + db * db, dot(e2, pa * pb) + da * db);
}

void combine(uint i) {
  TreeNode t = tree[i];
  if (t.surfel >= 0) {
    Surfel s = surfels[t.surfel];
    nodes[i].positionArea = s.positionArea;
    nodes[i].normalCone = vec4(s.normal.xyz, 0.0);
    nodes[i].shape = s.shape;
    nodeVectorArea[i] = vec4(s.positionArea.w * s.normal.xyz, 0.0);
    return;
  }
  float area = 0.0;
  vec3 weighted = vec3(0.0), mean = vec3(0.0), normal = vec3(0.0), vectorArea = vec3(0.0);
  for (uint c = 0; c < t.childCount; ++c) {
    NodeState child = nodes[t.firstChild + c];
    area += child.positionArea.w;
    weighted += child.positionArea.w * child.positionArea.xyz;
    mean += child.positionArea.xyz;
    normal += child.positionArea.w * child.normalCone.xyz;
    vectorArea += nodeVectorArea[t.firstChild + c].xyz;
  }
  nodeVectorArea[i] = vec4(vectorArea, 0.0);
  vec3 p = area > 0.0 ? weighted / area : mean / float(t.childCount);
  float len = length(normal);
  vec3 n = len > 0.0 ? normal / len : vec3(0.0, 0.0, 1.0);
  vec3 a, b;
  tangentFrame(n, a, b);
  float cone = len > 0.0 ? 0.0 : kPi, radius = 0.0;
  vec3 moments = vec3(0.0);  // about p along a, along b, and mixed
  vec2 quarter = vec2(0.0);  // the children's axes, their angle in (a, b) times four, by area
  for (uint c = 0; c < t.childCount; ++c) {
    NodeState child = nodes[t.firstChild + c];
    if (len > 0.0 && child.positionArea.w > 0.0)
      cone = max(cone, acos(clamp(dot(n, child.normalCone.xyz), -1.0, 1.0)) + child.normalCone.w);
    radius = max(radius, length(child.positionArea.xyz - p) + child.shape.x);
    if (child.positionArea.w > 0.0) moments += child.positionArea.w * secondMoments(child, p, a, b);
    vec3 u1, u2;
    rectangleAxes(child.normalCone.xyz, child.shape.y, u1, u2);
    vec2 axis = quarterTurns(u1, a, b);
    if (length(axis) > 0.0) quarter += child.positionArea.w * normalize(axis);
  }
  moments /= max(area, 1e-30);
  // The rectangle's axes: the principal axes of the 2×2 moment matrix [[x, z], [z, y]] where they
  // are clear, the children's where the moments are nearly round (a square of cells, whose principal
  // axes follow the triangulation's diagonals and would tip the rectangle past the node's corners);
  // its half-extents √3·σ along them.
  float mid = 0.5 * (moments.x + moments.y), spread = length(vec2(0.5 * (moments.x - moments.y), moments.z));
  float angle = spread > 0.2 * mid ? 0.5 * atan(2.0 * moments.z, moments.x - moments.y) : quarterAngle(quarter);
  float ca = cos(angle), sa = sin(angle);
  vec2 along = vec2(ca * ca * moments.x + 2.0 * ca * sa * moments.z + sa * sa * moments.y,
                    sa * sa * moments.x - 2.0 * ca * sa * moments.z + ca * ca * moments.y);
  vec2 halfExtents = sqrt(3.0 * max(along, vec2(0.0)));
  nodes[i].positionArea = vec4(p, area);
  nodes[i].normalCone = vec4(len > 0.0 ? n : vec3(0.0), min(cone, kPi));
  nodes[i].shape = vec4(radius, angle, halfExtents);
}

#define CLIMB_ARRIVALS 3
#define CLIMB_LEAVES 5  // every leaf, or those of the objects that move (the others' nodes stand)
#include "common/climb.glsl"

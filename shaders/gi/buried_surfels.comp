#version 460
// Per surfel, whether it lies inside another object, or another part of its own: a floor's surfels
// under a block standing on it. Such a surfel's own light stands for no surface anyone sees, yet the
// triangles that reach out from under the block share its vertex, and the resolve would draw their
// light down toward it along the contact (vertex_irradiance carries them the light of their
// neighbours outside instead).
// Inside is where the object's generalised winding number (the signed solid angle of its surface,
// over 4π, its normals pointing out) reaches kBurialWinding (¼): 1 inside a closed object, ½ on a
// face it rests on, 0 outside. An object whose normals point in (a room seen from inside) counts as outside.
// A surfel also lies inside where another part of its own object encloses it (kSelfBurialWinding: an
// eyeball sunk into a head, whose hidden back would darken the visible eye around its rim).
// Summed over the object's tree, depth first without a stack (`skip`), as fast winding numbers are
// (Barill et al. 2018): a node far from the point as a dipole of its vector area, a near surfel as
// its rectangle's exact solid angle. A surfel of an object that stays still, inside another that
// does too, is also counted apart: it stays inside for as long as links made once stand, and the
// frames after the first test again only what moves (BurialPush::stillKnown).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 3
#include "common/common.glsl"
#include "common/solid_angle.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, r32ui) readonly uniform uimageBuffer skip;
layout(binding = 2, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(binding = 4, rgba32f) readonly uniform imageBuffer surfels;         // Surfel: positionArea, normal, shape
layout(binding = 7, r32ui) readonly uniform uimageBuffer rootFlags;        // kRootEncloses, kRootStill, kRootRigid
layout(std430, binding = 5) buffer SurfelBuried { uint surfelBuried[]; };  // kBuried, kBuriedInItself
// Per node, the buried surfels below it, and those of them still and inside still objects (both
// zeroed before the pass).
layout(std430, binding = 6) buffer NodeBuried { uint nodeBuried[]; };
layout(std430, binding = 9) buffer NodeStillBuried { uint nodeStillBuried[]; };
layout(binding = 10, r32ui) readonly uniform uimageBuffer surfelRoot;  // its tree's root
layout(binding = 11, r32ui) readonly uniform uimageBuffer movingLeaves;
layout(binding = 8, rgba32f) readonly uniform imageBuffer nodeVectorArea;  // Σ a·n (refit)
layout(push_constant) uniform Push { BurialPush push; };

// Node i's share of the winding number at p (times 4π): far, as a dipole; else i is a surfel, its
// rectangle (two triangles) scaled to its area.
float solidAngleOf(uint i, vec3 p) {
  const vec4 positionArea = nodePositionArea(i), normalCone = nodeNormalCone(i), shape = nodeShape(i);
  const vec3 d = positionArea.xyz - p;
  const float dist = length(d);
  if (dist > kBurialFar * shape.x) return dot(imageLoad(nodeVectorArea, int(i)).xyz, d) / (dist * dist * dist);
  vec3 u1, u2;
  rectangleAxes(normalCone.xyz, shape.y, u1, u2);
  u1 *= shape.z, u2 *= shape.w;
  const float rectangle = 4.0 * shape.z * shape.w;
  // A point on the rectangle's plane (a floor under a box's bottom lying on it) sees it edge-on: its
  // solid angle is 0, where the formula's ±2π inside it would hang on the sign of a rounding.
  if (rectangle <= 0.0 || abs(dot(normalCone.xyz, d)) <= 1e-4 * max(shape.z, shape.w)) return 0.0;
  const float turn = dot(cross(u1, u2), normalCone.xyz) >= 0.0 ? 1.0 : -1.0;
  return turn * rectangleSolidAngle(d, u1, u2) * positionArea.w / rectangle;
}

// Whether the object of `root` winds around the point p at least `least` times: its winding number,
// summed over the tree. A walk cut short by kBurialVisits says nothing: the point counts as outside.
bool windsAround(uint root, vec3 p, float least) {
  if (distance(nodePositionArea(root).xyz, p) > nodeRadius(root)) return false;  // outside its sphere
  const uint end = imageLoad(skip, int(root)).x;
  float winding = 0.0;
  uint visits = 0u;
  for (uint node = root; node != end; ++visits) {
    if (visits == kBurialVisits) return false;
    const uvec4 t = imageLoad(tree, int(node));  // parent, firstChild, childCount, surfel
    if (t.z == 0u || distance(nodePositionArea(node).xyz, p) > kBurialFar * nodeRadius(node)) {
      winding += solidAngleOf(node, p);
      node = imageLoad(skip, int(node)).x;
    } else {
      node = t.y;
    }
  }
  return winding >= least * 4.0 * kPi;
}

void main() {
  const uint item = itemIndex();
  if (item >= push.surfelCount) return;
  const uint leaf = push.listed != 0u ? imageLoad(movingLeaves, int(item)).x : imageLoad(leafOfSurfel, int(item)).x;
  const uint s = push.listed != 0u ? uint(imageLoad(tree, int(leaf)).w) : item;
  // Still, inside a still object, as a pass before found: counted in nodeBuried already.
  if (push.stillKnown != 0u && nodeStillBuried[leaf] != 0u) {
    surfelBuried[s] = kBuried;
    return;
  }
  const vec3 p = imageLoad(surfels, int(3u * s)).xyz;
  const uint own = imageLoad(surfelRoot, int(s)).x, ownFlags = imageLoad(rootFlags, int(own)).x;
  const bool ownStill = (ownFlags & kRootStill) != 0u, ownRigid = (ownFlags & kRootRigid) != 0u;
  // Inside another part of its own object: its own surfel sees the point edge-on (solidAngleOf), so
  // the rest of its closed surface winds ½. A still surfel not found so at first never is; one of an
  // object that moves rigidly is as the pass at rest found it, whatever frame the render starts at.
  if (push.atRest != 0u && !ownRigid) return;  // the pass at rest is the rigid objects'
  const bool selfTested = (ownFlags & kRootEncloses) != 0u && !(push.stillKnown != 0u && ownStill),
             kept = push.atRest == 0u && push.shapesKnown != 0u && ownRigid;
  const bool inItself =
      selfTested && (kept ? (surfelBuried[s] & kBuriedInItself) != 0u : windsAround(own, p, kSelfBurialWinding));
  if (push.atRest != 0u) {
    surfelBuried[s] = inItself ? kBuriedInItself : 0u;
    return;
  }
  bool buried = inItself, stillBuried = inItself && ownStill;
  for (uint root = 0u; root < push.rootCount && !stillBuried && !(buried && !ownStill); ++root) {
    const uint flags = imageLoad(rootFlags, int(root)).x;
    const bool still = (flags & kRootStill) != 0u;
    if (root == own || (flags & kRootEncloses) == 0u || (buried && !still)) continue;
    // A still surfel known to lie outside every still object stays outside them.
    if (push.stillKnown != 0u && still && ownStill) continue;
    const bool inside = windsAround(root, p, kBurialWinding);
    buried = buried || inside;
    stillBuried = inside && still && ownStill;
  }
  surfelBuried[s] = (buried ? kBuried : 0u) | (inItself ? kBuriedInItself : 0u);
  if (buried)
    for (int node = int(leaf); node >= 0; node = int(imageLoad(tree, node).x)) {
      atomicAdd(nodeBuried[node], 1u);
      if (stillBuried) atomicAdd(nodeStillBuried[node], 1u);
    }
}

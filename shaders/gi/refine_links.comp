#version 460
// Link creation, one refinement level: each candidate pair (receiver, sender) is stored as
// a link or split into the pairs of the larger node's children (docs/design.md §2.1). The last
// workgroup to finish sizes the next level's dispatch and the sort's, so that a level is one
// dispatch (a level of no pairs runs no workgroup, and leaves the sizes it found: zero for the next
// level, the links for the sort).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 1
#include "common/common.glsl"
layout(local_size_x = kLinkGroup) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 2, rg32ui) readonly uniform uimageBuffer pairs;
// Texels, as every array that grows with the link counts: their views reach past one storage binding.
layout(binding = 3, rg32ui) writeonly uniform uimageBuffer nextWorklist;
layout(binding = 4, rg32ui) writeonly uniform uimageBuffer links;
layout(std430, binding = 5) coherent buffer Counters { uint counters[]; };
layout(binding = 6, rgba32f) readonly uniform imageBuffer emitters;  // nonzero: the node emits
layout(std430, binding = 7) writeonly buffer Args { uvec4 args[]; };
// Per node, the surfels below it inside another object for as long as this set's links stand
// (buried_surfels), and all the surfels below.
layout(binding = 8, r32ui) readonly uniform uimageBuffer nodeBuried;
layout(binding = 9, r32ui) readonly uniform uimageBuffer nodeLeaves;
layout(binding = 10, r32ui) readonly uniform uimageBuffer nodeFlags;  // iv's kNodeClosed (unread with bothSides)
layout(push_constant) uniform Push { RefinePush push; };

// Room in the next worklist for `count` pairs, taken at once (the counter is shared by every
// thread): the first slot. Past the capacity the frame is redone (sizeNextLevel() records how long
// the list grew).
uint reservePairs(uint count) {
  uint first = atomicAdd(counters[push.target], count);
  if (first + count > push.capacity) atomicOr(counters[kCounterOverflow], kOverflowWorklist);
  return first;
}
void storePair(uint slot, uint r, uint s) {
  if (slot < push.capacity) imageStore(nextWorklist, int(slot), uvec4(r, s, 0u, 0u));
}
// The pairs of receiver r's children with s, or of r with s's children.
void emitChildPairs(uint r, uint s, uvec4 tr, uvec4 ts, bool receiverSide) {
  uint count = receiverSide ? tr.z : ts.z, first = reservePairs(count);
  for (uint c = 0u; c < count; ++c) storePair(first + c, receiverSide ? tr.y + c : r, receiverSide ? s : ts.y + c);
}

// Stores the link (r, s); past the capacity the frame is redone with the room counted.
void storeLink(uint r, uint s) {
  uint slot = atomicAdd(counters[kCounterLinks], 1u);
  if (slot < push.linkCapacity)
    imageStore(links, int(slot), uvec4(r, s, 0u, 0u));
  else
    atomicOr(counters[kCounterOverflow], kOverflowLinks);
}

// Cosine of the smallest angle between a cone of normals (axis n, half-angle cone) and directions
// toward a sphere seen at angular radius `spread` along dir.
float cosUpper(vec3 n, float cone, vec3 dir, float spread) {
  if (cone >= kPi) return 1.0;
  float angle = acos(clamp(dot(n, dir), -1.0, 1.0)) - cone - spread;
  return angle <= 0.0 ? 1.0 : (angle >= 0.5 * kPi ? 0.0 : cos(angle));
}

// Once every workgroup has listed its pairs: the dispatch sizes of the next level and of the sort,
// the longest list so far (counted past the capacity too: the room the next frame's lists need),
// and this level's counter zeroed, to count the level after next.
void sizeNextLevel() {
  const uint items = counters[push.target];
  counters[kCounterWorklistPeak] = max(counters[kCounterWorklistPeak], items);
  args[kLinkArgsLevel] = linkGroupsFor(items);
  args[kLinkArgsSort] = linkGroupsFor(counters[kCounterLinks]);
  counters[push.source] = 0u;
}

// Whether every surfel below node n lies inside another object: its faces then hide n from every
// surface outside it, and what the surfaces inside with n receive is never shown (§2.4).
bool whollyBuried(uint n) {
  const uint buried = imageLoad(nodeBuried, int(n)).x;
  return buried != 0u && buried == imageLoad(nodeLeaves, int(n)).x;
}

void refinePairs() {
  uint total = counters[push.source];
  uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint k = gl_GlobalInvocationID.x; k < total && k < push.capacity; k += stride) {
    uvec2 pair = imageLoad(pairs, int(k)).xy;
    uint r = pair.x, s = pair.y;
    if (push.skipBuriedSenders != 0u && whollyBuried(s))
      continue;  // hidden: linked, it could only win bins through their gaps
    uvec4 tr = imageLoad(tree, int(r)), ts = imageLoad(tree, int(s));  // parent, firstChild, childCount, surfel
    if (r == s) {  // a node with itself (concave objects): all ordered pairs of its children
      uint first = reservePairs(tr.z * tr.z);
      for (uint a = 0; a < tr.z; ++a)
        for (uint b = 0; b < tr.z; ++b) storePair(first + a * tr.z + b, tr.y + a, tr.y + b);
      continue;
    }
    NodeState nr = nodeState(r), ns = nodeState(s);
    vec3 d = ns.positionArea.xyz - nr.positionArea.xyz;
    float dist2 = dot(d, d), dist = sqrt(dist2);
    bool leafR = tr.z == 0u, leafS = ts.z == 0u;
    float scale = max(nr.positionArea.w, ns.positionArea.w);
    if (dist2 <= 1e-6 * scale) {  // coincident (hard edges): the pruning bins it by points on its disk
      if (leafR && leafS) {
        // Twins (a face and its back, scene/back_faces.h) face apart: neither sees the other.
        if (dot(nr.normalCone.xyz, ns.normalCone.xyz) > -0.999) storeLink(r, s);
        continue;
      }
    } else {
      vec3 dir = d / dist;
      float spreadS = asin(min(ns.shape.x / dist, 1.0)), spreadR = asin(min(nr.shape.x / dist, 1.0));
      float cosS = cosUpper(ns.normalCone.xyz, ns.normalCone.w, -dir, spreadR);
      float cosR = cosUpper(nr.normalCone.xyz, nr.normalCone.w, dir, spreadS);
      if (push.bothSides != 0u) {  // |cos|: the back of either side carries antiradiance
        cosS = max(cosS, cosUpper(-ns.normalCone.xyz, ns.normalCone.w, -dir, spreadR));
        cosR = max(cosR, cosUpper(-nr.normalCone.xyz, nr.normalCone.w, dir, spreadS));
      }
      // Senders wholly below the receiver's horizon matter neither for light nor for visibility.
      if (nr.positionArea.w > 0.0 && cosR <= 0.0) continue;
      // A closed object's faces turned away from the whole receiver lie behind its faces turned
      // toward it; they matter only where the back of a surface carries antiradiance.
      if (push.bothSides == 0u && cosS <= 0.0 && (imageLoad(nodeFlags, int(s)).x & kNodeClosed) != 0u) continue;
      // iv re-bins a sender at each leaf under the receiver: one it cannot split stays linked whole.
      if (leafS && push.receiverStaysWhole != 0u) {
        storeLink(r, s);
        continue;
      }
      bool overlapping = dist <= nr.shape.x + ns.shape.x;
      bool large = ns.positionArea.w > push.largeSender * dist2;
      float estimate = formFactor(ns.positionArea.w, cosS, cosR, dist2);
      // A sender wider than a bin must be split itself (iv's leaves re-bin from their own position,
      // so a coarse receiver is fine there; ar splits a wide receiver too); overlap or a large form
      // factor splits the larger node.
      bool refineSender = large && !leafS;
      // An emitter's light is what changes fastest across a receiver: it may get its own limit.
      bool emits = any(greaterThan(imageLoad(emitters, int(s)).rgb, vec3(0.0)));
      float receiverLimit = emits ? push.emitterReceiver : push.largeReceiver;
      bool refineReceiver = !refineSender && !leafR && nr.positionArea.w > receiverLimit * dist2;
      bool refine = refineSender || refineReceiver || (!(leafR && leafS) && (overlapping || estimate > push.epsilon));
      if (!refine) {
        storeLink(r, s);
        continue;
      }
      if (refineSender || refineReceiver) {
        emitChildPairs(r, s, tr, ts, refineReceiver);
        continue;
      }
    }
    if (leafR && leafS) continue;
    // Split the larger node (by area), or the one that is not a leaf.
    emitChildPairs(r, s, tr, ts, leafS || (!leafR && nr.positionArea.w >= ns.positionArea.w));
  }
}

void main() {
  refinePairs();
  ONLY_IN_THE_LAST_WORKGROUP(counters[kCounterGroupsDone]);
  sizeNextLevel();
}

#version 460
// The prune, bin pruning and push-down: each leaf takes the links of itself and of all its ancestors,
// re-bins them from its own position into 6×N×N direction bins and keeps the nearest sender per bin
// (64-bit atomicMin on distance², sender; senders centred in the bin rank ahead of those whose
// footprint only brushes it); everything farther in a bin is occluded. The links along
// a leaf's root path partition every other surface once, so the solid angles they subtend also say
// how much of each bin is covered; the survivor stands for that covered part:
// F = cos θr · min(Ω_bin, Ω_covered) / π (a hemisphere never sums above 1). Survivors are written
// in bin order. Punctual lights, the environment and emitters' direct light (each emitter's own
// form factor, not the whole bins it would win) are tested against the same bins. Bins live in
// shared memory where they fit, else in a global slot per workgroup; each workgroup walks many
// leaves and resets only the bins it touched.
//
// Objects that cannot move are linked and pruned once (the static pass, over the links between
// them); every frame (the frame pass) a moving leaf is pruned in full from the links of the pairs
// with a moving side, and a static leaf files only those and merges the bins they touch with its
// static bins: nearest key and summed coverage as a full prune would find them. Its touched bins
// are re-emitted and flagged in an override mask that the gather reads to skip the static entries.
// A static leaf also keeps the emitters of its static links, whose direct light each frame tests
// against the merged bins (a moving block may hide them).
//
// An object that moves rigidly keeps its shape: the distances, footprints and occlusion among its
// own surfels are the same every frame, only their directions turn with it. So its pairs with
// itself are static pairs, and its leaves are pruned like static ones, each seeing the scene as from
// its object's rest pose (NODE_POSE: every node it reads is moved by the object's motion back to
// rest), bins fixed to the object. What depends on the world's directions (the environment and the
// punctual lights) such a leaf sums in full every frame.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 1
#define NODE_POSE
#include "common/common.glsl"
#include "common/parted_texels.glsl"
// As few subgroups a workgroup as lavapipe's loop budget allows (engine/gi/iv/prune.cpp): lavapipe
// runs a workgroup's subgroups one after another on one thread, switching at every barrier.
layout(local_size_x_id = 8) in;
const uint kGroupSize = gl_WorkGroupSize.x;  // a multiple of 8

layout(constant_id = 0) const uint kN = 16;  // bins per face side
layout(constant_id = 1) const bool kSharedBins = true;
layout(constant_id = 2) const uint kSharedSlots = 1536;  // 6·N² on the shared path, else 1
layout(constant_id = 3) const uint kMaskWords = 48;      // ⌈6·N² / 32⌉
layout(constant_id = 4) const bool kStaticPass = false;  // prune static leaves against static links, once

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 2, r32ui) readonly uniform uimageBuffer starts;
layout(binding = 3, r32ui) readonly uniform uimageBuffer senders;  // kEmitterBit marks emitters
layout(binding = 4, r32ui) readonly uniform uimageBuffer leafOfSurfel;
// ∫ω dω over the bin (its cosine-weighted solid angle is n·∫ω dω, exact wherever the bin lies wholly
// above the horizon, so that a hemisphere's bins never sum above π), solid angle
layout(binding = 5, rgba32f) readonly uniform imageBuffer binTable;
layout(std430, binding = 6) buffer GlobalBins { uint64_t globalBins[]; };
layout(std430, binding = 7) writeonly buffer Ranges { LeafRange ranges[]; };
// The leaf links are texel buffers bound in parts (parted_texels.glsl): they reach past one view's
// maxTexelBufferElements (2^27 on lavapipe, 1 GiB of links) and one storage binding's range.
layout(binding = 8, rg32ui) writeonly uniform uimageBuffer leafLinks[kTexelParts];  // LeafLink
layout(std430, binding = 9) buffer Counters { uint counters[]; };
// irradiance from lights and environment
layout(std430, binding = 10) writeonly buffer ExternalLight { vec4 externalLight[]; };
layout(std430, binding = 11) readonly buffer Lights { PunctualLight lights[]; };
layout(binding = 12, rgba32f) readonly uniform imageBuffer environment;  // radiance per bin
layout(std430, binding = 13) buffer GlobalCoverage { uint globalCoverage[]; };
// per node: kNodeMoves, kNodeClosed, kNodeRigid, root; then per object its pose (kPoseWords)
layout(binding = 14, r32ui) readonly uniform uimageBuffer nodeFlags;
// The static pass writes these; the frame pass reads them.
layout(std430, binding = 15) buffer StaticRanges { LeafRange staticRanges[]; };
layout(binding = 16, rg32ui) uniform uimageBuffer staticLinks[kTexelParts];  // LeafLink
layout(binding = 17, r32ui) uniform uimageBuffer staticBins[kTexelParts];    // StaticBin: bin and coverage, packed
// the key's upper half (fringe bit, d²), beside the link
layout(binding = 18, r32ui) uniform uimageBuffer staticDepths[kTexelParts];
// per leaf and mask word: bins held, entries before
layout(std430, binding = 19) buffer StaticMasks { uvec2 staticMasks[]; };
layout(std430, binding = 20) buffer StaticLeaves { StaticLeaf staticLeaves[]; };
// per static leaf and mask word: bins re-emitted
layout(std430, binding = 21) writeonly buffer Overrides { uint overrides[]; };
layout(binding = 22, rgba32f) readonly uniform imageBuffer nodeEmission;  // π·Le per node, pulled up
// per static leaf: the emitters of its static links
layout(std430, binding = 23) buffer StaticEmitters { uint staticEmitters[]; };
// the static set's (the frame pass merges its bins)
layout(std430, binding = 24) readonly buffer StaticCounters { uint staticCounters[]; };
// Listed: the round's new receivers (receivers from the round's start in the receivers' counters).
layout(binding = 25, r32ui) readonly uniform uimageBuffer receivers;
layout(std430, binding = 26) readonly buffer ReceiverCounts { uint receiverCounts[]; };
// Per leaf: how near what it sees is, Σ cos θ·ω / (π·d) over its survivors, the inverse of the
// harmonic mean distance (the receivers' refinement reads it).
layout(std430, binding = 27) writeonly buffer Proximity { float proximity[]; };
layout(push_constant) uniform Push { PrunePush push; };

shared uint64_t sharedBins[kSharedSlots];
shared uint sharedCoverage[kSharedSlots];  // covered solid angle in 1/kCoverageUnit of the bin's
shared uint mask[kMaskWords], grown[kMaskWords];
shared uint halfCovered[kMaskWords], staticHalfCovered[kMaskWords];  // markFiledBins
shared uvec2 staticWords[kMaskWords];  // a merging leaf's static mask words (staticMasks'), read once
shared uint wordStart[kMaskWords];
shared vec3 partial[kGroupSize];
shared uint leafBase;
shared uint pathChunk[kPathChunk], wideQueue[kPathChunk];
shared uint wideCount;
shared uint emitterQueue[kEmitterQueue], sortedEmitters[kEmitterQueue];
shared uint emitterCount;

const uint kBinCount = 6u * kN * kN;

#include "object_pose.glsl"
#include "prune_bins.glsl"
#include "prune_footprints.glsl"
#include "prune_lights.glsl"

// Sum of the workgroup's partial vectors in a fixed order (deterministic); valid in invocation 0.
vec3 sumPartials(uint lid, vec3 mine) {
  partial[lid] = mine;
  barrier();
  vec3 sum = vec3(0.0);
  if (lid == 0u)
    for (uint t = 0u; t < kGroupSize; ++t) sum += partial[t];
  return sum;
}

// ---- A leaf's prune, phase by phase (main() below runs them in order) ----

// This invocation's lane, and where its workgroup's bins start in the global slots (0: shared).
uint lid = 0u, slot = 0u;

// Sets what the leaf (its surfel, node and the node's `flags`) sees every node through: its own bin
// frame (common.glsl's binFrame: its normal, and its object's axes tilted onto it), after, where
// its object moves rigidly, the object's motion back to its rest pose (`posed`). The static pass
// keeps the frame for the frames, which merge their senders into the bins it filed, and for the
// gather, which turns them back into the world.
void poseNodes(uint surfel, uint node, uint flags) {
  posed = !kStaticPass && (flags & kNodeRigid) != 0u;  // the static pass reads them at rest
  const mat3 turn = posed ? restTurn(flags >> kNodeRootShift) : mat3(1.0);
  const vec3 shift = posed ? restShift(flags >> kNodeRootShift) : vec3(0.0);
  uvec2 frame;
  if (merging) {
    frame = uvec2(staticLeaves[surfel].frameNormal, staticLeaves[surfel].frameTangent);
  } else {
    nodeTurn = mat3(1.0), nodeShift = vec3(0.0);
    const mat3 axes = objectAxes(flags >> kNodeRootShift, kStaticPass);  // the static pass reads the nodes at rest
    const vec3 n = nodeNormalCone(node).xyz;
    frame = packBinFrame(n, transpose(axes) * tiltedTangent(axes * n));
    if (kStaticPass && lid == 0u)
      staticLeaves[surfel].frameNormal = frame.x, staticLeaves[surfel].frameTangent = frame.y;
  }
  const mat3 binTurn = binFrameOf(frame);
  nodeTurn = binTurn * turn;
  nodeShift = binTurn * shift;
}

// The leaf being pruned: its surfel, its node, and the receiver's position, normal and area.
struct Leaf {
  uint surfel;
  uint node;
  vec3 p;
  vec3 n;
  float area;
};

// Adds n to the 64-bit count whose low word is counters[at].
void countWalked(uint at, uint n) {
  if (atomicAdd(counters[at], n) > 0xFFFFFFFFu - n) atomicAdd(counters[at + 1u], 1u);
}

// Gathers the leaf's root path (the senders linked to it and to each of its ancestors), a chunk at a
// time, into shared memory, and files each chunk in one pass: a CPU device runs the filing code,
// lanes masked, on every round of a subgroup however few of its lanes have a sender, and ancestor
// by ancestor the ranges are short (a static leaf's frame senders: a few per ancestor). The senders
// the filing queued as wide are then filed in pieces, 8 lanes a sender.
void fileRootPath(Leaf leaf) {
  int a = leaf.area > 0.0 ? int(leaf.node) : -1;
  uint next = a >= 0 ? imageLoad(starts, a).x : 0u;
  while (a >= 0) {
    uint listed = 0u;
    while (a >= 0 && listed < kPathChunk) {
      uint end = imageLoad(starts, a + 1).x, take = min(end - next, kPathChunk - listed);
      for (uint j = lid; j < take; j += kGroupSize) pathChunk[listed + j] = imageLoad(senders, int(next + j)).x;
      listed += take;
      next += take;
      if (next == end) {
        a = int(imageLoad(tree, a).x);
        next = a >= 0 ? imageLoad(starts, a).x : 0u;
      }
    }
    barrier();
    if (lid == 0u) {
      countWalked(kCounterSendersWalked, listed);
      if (merging) countWalked(kCounterMergedWalked, listed);
      if (posed) countWalked(kCounterRigidWalked, listed);
    }
    for (uint j = lid; j < listed; j += kGroupSize)
      fileSender(slot, leaf.node, leaf.p, leaf.n, leaf.area, pathChunk[j]);
    barrier();
    // Each group of 8 lanes (a subgroup on lavapipe) takes a queued sender and files its pieces, one per lane.
    for (uint e = lid / 8u; e < wideCount; e += kGroupSize / 8u) {
      uint s = wideQueue[e];
      vec4 normalCone = nodeNormalCone(s);
      View v = viewOf(leaf.p, nodePositionArea(s), normalCone);
      for (uint piece = lid % 8u; piece < v.k * v.k; piece += 8u) filePiece(slot, leaf.n, s, normalCone, v, piece);
    }
    barrier();
    if (lid == 0u) wideCount = 0u;  // before the next chunk's filing, past its gathering barrier
  }
  barrier();
}

// Marks the bins the walk filed senders in (`mask`), read once from the bins rather than marked by
// every filing; and in the same sweep those whose gaps a neighbour may close (closedCoverage): at
// least half covered, or below the horizon of the leaf (normal n). A merging leaf's static mask
// words are kept (staticWords) for what reads its static entries after.
void markFiledBins(vec3 n) {
  for (uint w = lid; w < kMaskWords; w += kGroupSize) {
    uint bits = 0u, halfBits = 0u, staticHalfBits = 0u;
    const uvec2 word = merging ? staticMasks[maskBase + w] : uvec2(0u);
    for (uint i = 0u; i < 32u && w * 32u + i < kBinCount; ++i) {
      const uint b = w * 32u + i, staticCovered = staticCoverageAt(staticEntryIn(word, i));
      const bool below = dot(n, imageLoad(binTable, int(b)).xyz) <= 0.0;
      bits |= loadBin(slot, b) != kEmptyVisibility ? 1u << i : 0u;
      halfBits |= below || loadCoverage(slot, b) + staticCovered >= kCoverageUnit / 2u ? 1u << i : 0u;
      staticHalfBits |= below || staticCovered >= kCoverageUnit / 2u ? 1u << i : 0u;
    }
    mask[w] = bits;
    staticWords[w] = word;
    halfCovered[w] = halfBits;
    staticHalfCovered[w] = staticHalfBits;
  }
  barrier();
}

// Grows a merging leaf's mask over the static bins beside those its frame senders touched, which it
// re-emits too: whether a bin's gaps are closed depends on its neighbours' coverage.
void growIntoStaticBins() {
  for (uint w = lid; w < kMaskWords; w += kGroupSize) grown[w] = 0u;
  barrier();
  for (uint w = lid; w < kMaskWords; w += kGroupSize)
    for (uint bits = mask[w]; bits != 0u; bits &= bits - 1u) {
      uint b = w * 32u + uint(findLSB(bits));
      growInto(neighbourBin(b, ivec2(1, 0)));
      growInto(neighbourBin(b, ivec2(-1, 0)));
      growInto(neighbourBin(b, ivec2(0, 1)));
      growInto(neighbourBin(b, ivec2(0, -1)));
    }
  barrier();
  for (uint w = lid; w < kMaskWords; w += kGroupSize) mask[w] |= grown[w];
  barrier();
}

// Emitters' light: from the depth maps where they give it (PrunePush::emittersByMaps); else direct
// where they are few enough to list (the static pass keeps the list for
// the frames, whose moving senders may hide them), the bins then carrying only their reflected
// light; through the bins like any sender where they are many (a wholly emissive room). Lists them
// in `sortedEmitters` in a fixed order whatever order the atomics queued them in: the static list
// (sorted by the static pass), then the queued ones sorted by node (another object's, so never in
// the static list). A static leaf whose emitters stand still queues none and sorts nothing.
// Whether the leaf takes their light directly; `listed`: how many.
bool sortEmitters(uint surfel, uint staticEmitterCount, out uint listed) {
  listed = 0u;
  if (push.emittersByMaps != 0u) return true;  // none listed, the bins' credit taken back
  uint staticListed = staticEmitterCount == kManyEmitters ? 0u : staticEmitterCount,
       emitters = staticListed + emitterCount;
  bool direct = staticEmitterCount != kManyEmitters && emitters <= (kStaticPass ? kStaticEmitters : kEmitterQueue);
  if (direct)
    for (uint e = lid; e < emitters; e += kGroupSize) {
      uint s = emitterAt(surfel, staticListed, e), rank = min(e, staticListed);
      for (uint j = 0u; j < (e < staticListed ? 0u : emitterCount); ++j) rank += emitterQueue[j] < s ? 1u : 0u;
      sortedEmitters[rank] = s;
    }
  listed = emitters;
  return direct;
}

// The emitters' direct light at the leaf (each lane its share); the static pass instead keeps the
// list for the frames.
vec3 emittersLight(Leaf leaf, bool direct, uint emitters) {
  vec3 light = vec3(0.0);
  if (kStaticPass) {
    if (direct)
      for (uint e = lid; e < emitters; e += kGroupSize)
        staticEmitters[leaf.surfel * kStaticEmitters + e] = sortedEmitters[e];
    if (lid == 0u) staticLeaves[leaf.surfel].emitterCount = direct ? emitters : kManyEmitters;
  } else if (direct) {
    for (uint e = lid; e < emitters; e += kGroupSize) light += directLight(slot, leaf.p, leaf.n, sortedEmitters[e]);
  }
  return light;
}

// Room for the leaf's survivors, in bin order (deterministic): `wordStart` turned from counts per
// mask word into where each word's survivors start, after `leafBase`, and the leaf's range.
void reserveSurvivors(uint surfel) {
  if (lid != 0u) return;
  uint total = 0u;
  for (uint w = 0u; w < kMaskWords; ++w) {
    uint c = wordStart[w];
    wordStart[w] = total;
    total += c;
  }
  leafBase = atomicAdd(counters[kCounterLeafLinks], total);
  // A leaf past the room is counted (the frame is redone with room for all), its range left
  // empty: nothing reads past the links.
  bool fits = leafBase + total <= push.linkCapacity;
  if (!fits) atomicOr(counters[kCounterOverflow], kOverflowLeafLinks);
  if (kStaticPass)  // a listed rigid leaf past the room stays unpruned, for the frame's redo
    staticRanges[surfel] =
        fits || push.listed == 0u ? LeafRange(leafBase, fits ? total : 0u) : LeafRange(kRigidUnpruned, 0u);
  else
    ranges[surfel] = LeafRange(leafBase, fits ? total : 0u);
}

// Merges and writes the survivors: per marked bin, the nearest of the filed senders and the leaf's
// static entry, its form factor for the covered part (gaps closed), its proximity (`near`: for a
// merging leaf, the change from its static share). Where the emitters' light is direct, the light
// the bins credit emissive survivors is taken back (`emitterLight`). A merging leaf's environment
// changes only in the bins it touched: this frame's minus its static share (`environmentChange`,
// and of its rotation gradient `turnChange`).
void writeSurvivors(Leaf leaf, bool direct, inout vec3 emitterLight, out vec3 environmentChange, out mat3 turnChange,
                    out float near) {
  environmentChange = vec3(0.0);
  turnChange = mat3(0.0);
  near = 0.0;
  const vec3 n = leaf.n;
  const float radius = sqrt(leaf.area / kPi);
  for (uint w = lid; w < kMaskWords; w += kGroupSize) {
    uint bits = mask[w], outIndex = leafBase + wordStart[w];
    if (kStaticPass) staticMasks[maskBase + w] = uvec2(bits, wordStart[w]);
    if (merging) overrides[maskBase + w] = bits;
    while (bits != 0u) {
      uint b = w * 32u + uint(findLSB(bits));
      bits &= bits - 1u;
      Bin bin = binAt(slot, b);
      uint s = keyId(bin.key), covered = closedCoverage(b, bin.covered, false),
           staticCovered = bin.staticEntry >= 0 ? closedCoverage(b, bin.staticCovered, true) : 0u;
      float f = survivorFormFactor(n, s, b, covered);
      near += proximityOf(n, b, covered, linkKeyDepth(bin.key), radius);
      if (bin.staticEntry >= 0) near -= proximityOf(n, b, staticCovered, bin.staticDistance2, radius);
      if (outIndex < push.linkCapacity) {
        if (kStaticPass) {
          storeParted(staticLinks, outIndex, uvec4(s, floatBitsToUint(f), 0u, 0u));
          storeParted(staticBins, outIndex, uvec4(packStaticBin(b, bin.covered)));
          storeParted(staticDepths, outIndex, uvec4(uint(bin.key >> 32)));
        } else {
          storeParted(leafLinks, outIndex, uvec4(s, floatBitsToUint(f), 0u, 0u));
        }
      }
      ++outIndex;
      if (direct) {
        emitterLight -= f * emitted(s);
        if (bin.staticEntry >= 0) {
          const uint entry = uint(bin.staticEntry);
          uvec2 link = loadParted(staticLinks, entry).xy;
          emitterLight += uintBitsToFloat(link.y) * emitted(link.x);
        }
      }
      if (merging && !posed && push.environmentOn != 0u) {
        addEnvironmentThrough(n, b, coveredFraction(staticCovered) - coveredFraction(covered), environmentChange,
                              turnChange);
      }
    }
  }
}

// Sums the leaf's light from outside the links (the environment through its empty bins above the
// horizon, with its rotation gradient; the emitters' direct light, the punctual lights) and its
// proximity over the workgroup in a fixed order, and stores them: the static pass for the frames,
// the frame pass per surfel.
void sumExternalLight(Leaf leaf, bool direct, vec3 emitterLight, vec3 environmentChange, mat3 turnChange, float near) {
  const uint surfel = leaf.surfel;
  vec3 env = environmentChange;
  mat3 turn = turnChange;
  if (push.environmentOn != 0u && leaf.area > 0.0 && (!merging || posed))
    for (uint b = lid; b < kBinCount; b += kGroupSize)
      addEnvironmentThrough(leaf.n, b, 1.0 - coveredFraction(closedCoverage(b, coverageAt(slot, b, false), false)), env,
                            turn);
  if (push.environmentOn != 0u)
    for (uint c = 0u; c < 3u; ++c) {
      turn[c] = sumPartials(lid, turn[c]);
      barrier();
    }
  if (kStaticPass) {
    vec3 correction = sumPartials(lid, emitterLight);
    barrier();
    if (lid == 0u) staticLeaves[surfel].correction = vec4(correction, 0.0);
  }
  near = sumPartials(lid, vec3(near, 0.0, 0.0)).x;
  barrier();
  vec3 sum = sumPartials(lid, kStaticPass ? env : env + emitterLight);
  if (lid == 0u) {
    if (kStaticPass) {
      staticLeaves[surfel].environment = vec4(sum, 0.0);
      for (uint c = 0u; c < 3u; ++c) staticLeaves[surfel].environmentTurn[c] = vec4(turn[c], 0.0);
      staticLeaves[surfel].proximity = near;
    } else {
      // (A posed leaf's environment was summed in full above.)
      if (merging)
        sum += (posed ? vec3(0.0) : staticLeaves[surfel].environment.rgb) +
               (direct ? staticLeaves[surfel].correction.rgb : vec3(0.0));
      if (leaf.area > 0.0) sum += punctualLight(slot, leaf.p, leaf.n);
      externalLight[kExternalTexels * surfel] = vec4(sum, 0.0);
      // The turn's axes back in the world from the leaf's frame (nodeTurn is a rotation: its inverse is
      // its transpose).
      for (uint c = 0u; c < 3u; ++c)
        externalLight[kExternalTexels * surfel + 1u + c] =
            vec4(transpose(nodeTurn) *
                     (turn[c] + (merging && !posed ? staticLeaves[surfel].environmentTurn[c].xyz : vec3(0.0))),
                 0.0);
      proximity[surfel] = merging ? staticLeaves[surfel].proximity + near : near;
    }
  }
  barrier();  // the lights read the bins
}

// Empties the bins the leaf touched and its mask for the next leaf.
void resetFiledBins() {
  for (uint w = lid; w < kMaskWords; w += kGroupSize) {
    uint bits = mask[w];
    while (bits != 0u) {
      resetBin(slot, w * 32u + uint(findLSB(bits)));
      bits &= bits - 1u;
    }
    mask[w] = 0u;
  }
  if (lid == 0u) emitterCount = 0u;  // (each chunk already emptied the wide queue)
  barrier();
}

void main() {
  // Links cut short by an overflow (this set's, or the static links a frame pass merges): the frame
  // is redone, and pruning them would be wasted.
  if (((counters[kCounterOverflow] | staticCounters[kCounterOverflow]) & (kOverflowWorklist | kOverflowLinks)) != 0u)
    return;
  lid = gl_LocalInvocationID.x;
  slot = kSharedBins ? 0u : groupIndex() * kBinCount;
  if (kSharedBins)
    for (uint b = lid; b < kBinCount; b += kGroupSize) sharedBins[b] = kEmptyVisibility, sharedCoverage[b] = 0u;
  for (uint w = lid; w < kMaskWords; w += kGroupSize) mask[w] = 0u;
  if (lid == 0u) wideCount = 0u, emitterCount = 0u;
  barrier();

  uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y, end = push.endSurfel, listStart = 0u;
  if (push.listed != 0u) {
    listStart = receiverCounts[kReceiverRound];
    end = min(end, receiverCounts[kReceiverCount] - listStart);
  }
  for (uint item = push.firstSurfel + groupIndex(); item < end; item += groups) {
    const uint surfel = push.listed != 0u ? imageLoad(receivers, int(listStart + item)).x : item;
    uint node = imageLoad(leafOfSurfel, int(surfel)).x;
    const uint flags = imageLoad(nodeFlags, int(node)).x;
    const bool moves = (flags & kNodeMoves) != 0u, rigid = (flags & kNodeRigid) != 0u;
    if (kStaticPass && moves && !rigid) {  // pruned every frame instead
      if (lid == 0u) staticRanges[surfel] = LeafRange(0u, 0u);
      continue;
    }
    // Where rigid leaves are pruned when listed, the static pass over every leaf marks them
    // unpruned, and a listed one prunes only a rigid leaf still unpruned.
    if (kStaticPass && push.rigidWhenListed != 0u) {
      if (push.listed == 0u && rigid) {
        if (lid == 0u) staticRanges[surfel] = LeafRange(kRigidUnpruned, 0u);
        continue;
      }
      if (push.listed != 0u && !(rigid && staticRanges[surfel].first == kRigidUnpruned)) continue;
    }
    merging = !kStaticPass && (!moves || rigid);
    poseNodes(surfel, node, flags);
    if (lid == 0u && posed) atomicAdd(counters[kCounterRigidLeaves], 1u);
    staticFirst = merging ? staticRanges[surfel].first : 0u;
    maskBase = surfel * kMaskWords;
    vec4 receiver = nodePositionArea(node);
    const Leaf leaf = Leaf(surfel, node, receiver.xyz, nodeNormalCone(node).xyz, receiver.w);
    // The emitters whose direct light this leaf takes: a merging leaf's static ones (listed by the
    // static pass) and those the walk queues. Past the queue, the bins credit them as any sender.
    uint staticEmitterCount = merging ? staticLeaves[surfel].emitterCount : 0u;

    fileRootPath(leaf);
    markFiledBins(leaf.n);
    if (merging) growIntoStaticBins();
    uint emitters;
    bool direct = sortEmitters(surfel, staticEmitterCount, emitters);
    for (uint w = lid; w < kMaskWords; w += kGroupSize) wordStart[w] = bitCount(mask[w]);
    barrier();
    vec3 emitterLight = emittersLight(leaf, direct, emitters), environmentChange;
    mat3 turnChange;
    reserveSurvivors(surfel);
    barrier();
    float near;
    writeSurvivors(leaf, direct, emitterLight, environmentChange, turnChange, near);
    sumExternalLight(leaf, direct, emitterLight, environmentChange, turnChange, near);
    resetFiledBins();
  }
  // Cut short by lavapipe's loop budget (common/common.glsl), every leaf after the one it ran out
  // in came out short: the frame is redone with more subgroups a workgroup.
  if (loopBudgetSpent()) atomicOr(counters[kCounterOverflow], kOverflowLoopBudget);
}

// ar (engine/gi/ar/): directional tables of 6·N² world bins per node or surfel; how the global
// pass cuts and orders its links; the push constants of ar's passes. N (--dirs) is a
// specialization constant of ar's programs (kDirs), not a push constant.
// Part of shaders/interface.h, which includes it inside its namespace and language macros.
// Pieces per side a near or wide surfel sender is cut into at most (the gather's loops stay far
// below lavapipe's budget: common.glsl).
IVGI_CONST uint kArPieces = 2u;

// Solid angle per unit area of a sender of area `area` at squared distance `dist2`: that of a disk
// of its area seen on its axis, 2π(1 − 1/√(1 + a/(π d²)))/a, finite as d → 0 and 1/d² far away.
IVGI_FN float solidAnglePerArea(float area, float dist2) {
  const float x = area / (kPi * dist2);
  if (x < 1e-4f) return 1.0f / dist2 * (1.0f - 0.75f * x);  // the series: no cancellation
  return 2.0f * kPi * (1.0f - inversesqrt(1.0f + x)) / area;
}

// The pieces per side the global pass cuts a surfel sender of area `area` at squared distance
// `dist2` into under bins of `n` per face's side: one wider than a bin, or near, goes as k×k pieces
// of its rectangle, each along its own direction (one direction would stand for a spread of them,
// and the disk for a nearby square).
IVGI_FN uint surfelPieces(float area, float dist2, uint n) {
  const float binWidth = 2.0f / float(n);  // of a bin at a face's centre, in the face's plane
  const float width = sqrt(solidAnglePerArea(area, dist2) * area) / binWidth;
  return dist2 <= 4.0f * (area / kPi) ? kArPieces : uint(clamp(ceil(width), 1.0f, float(kArPieces)));
}

// A receiver's senders in the order the global pass walks them, so that the lanes walking
// neighbouring receivers' lists side by side take links of the same kind at the same step (a
// lane's longer link holds up the rest): the clusters first, then the surfels by pieces, most
// first; within a kind by node. The key keeps the emitter bit where the sender has it, the kind in
// the bits below, the node in the rest: the ar solver takes at most 2^kArKindShift nodes.
IVGI_CONST uint kArKindShift = 29u;
IVGI_CONST uint kArNodeMask = (1u << kArKindShift) - 1u;
IVGI_FN uint linkKind(bool cluster, float senderArea, float dist2, uint n) {
  return cluster ? 0u : 1u + kArPieces - surfelPieces(senderArea, dist2, n);
}
IVGI_FN uint walkKey(uint sender, uint kind) {
  return (sender & kEmitterBit) | (kind << kArKindShift) | (sender & kArNodeMask);
}
// Keys compare without the emitter bit; the lists hold the senders (without their kind).
IVGI_FN bool walkedBefore(uint keyA, uint keyB) { return (keyA & ~kEmitterBit) < (keyB & ~kEmitterBit); }
IVGI_FN uint senderOfKey(uint key) { return key & (kEmitterBit | kArNodeMask); }
// The most links of a receiver's list one dispatch of the global pass walks, within lavapipe's loop
// budget (common.glsl): four loops (each list's clusters, then its surfels) each run as long as the
// longest lane's, a cluster one round, a surfel at most 1 + kArPieces², so a chunk's subgroup runs
// at most 2·(1 + 1 + kArPieces²) rounds a link. Longer lists take more dispatches, each going on
// where the one before stopped.
IVGI_CONST uint kArGatherChunk = 4096u;
// ar_sort_senders sorts a list of at most this many senders in one invocation; longer ones get a
// workgroup each (ar_sort_long_senders).
IVGI_CONST uint kArShortList = 64u;
// The longest list ar_sort_long_senders orders within lavapipe's loop budget, and the bits of the
// flags the global pass and the sort leave (ArBuffers::gatherFlags): a list longer than the chunks
// recorded walk (the frame is redone in more), a list too long to sort (the solve stops).
IVGI_CONST uint kArSortedMost = 32768u;
IVGI_CONST uint kArFlagChunks = 1u;
IVGI_CONST uint kArFlagUnsorted = 2u;
// The global pass's workgroup size, whose blocks of nodes ar_order_receivers orders.
IVGI_CONST uint kArGatherGroup = 64u;
// The global pass keeps a receiver's table in each invocation up to this many bins (--dirs 8).
IVGI_CONST uint kArGatherTableHere = 384u;
// A node whose normals spread less than this (radians) counts as flat: one plane, a front and a back.
IVGI_CONST float kArFlatCone = 0.05f;
// A flat node's texels in `gatheredVector`: its vector sum Σ s·ω (x, y, z, each RGB), then its
// irradiance's gradient over the receiver's position (x, y, z).
IVGI_CONST uint kArVectorTexels = 6u;
// The asymmetric scheme's antiradiance steps after each radiance step.
IVGI_CONST uint kAntiradianceSteps = 3u;
// Per workgroup of ar_incident, what the host judges an iteration by (area-weighted luminances).
struct IterationSum {
  float total;     // Σ area · Y(E), E ≥ 0 the irradiance shown
  float change;    // Σ area · |Y(E) − Y(E before)|
  float negative;  // Σ area · Y(max(−E, 0)): light cancelled past zero
  float pad;
};

// ---- Push constants of ar's passes ----

struct QueueArgsPush {  // queue_args
  uint slot;            // which dispatch arguments to write
};
struct ArLocalPush {  // ar_local
  uint surfelCount;
  // The surfels from here on are back faces (scene/back_faces.h): they let nothing through, since
  // their fronts' surfels, in the same places, let the light through both ways.
  uint firstBackSurfel;
  uint updateRadiance;  // 1: reflect the incident light (a radiance step); 0: keep the radiance
  // 1: the emitters' light comes from depth maps, inside the irradiance: the surfels send only what
  // they reflect (their Le is not transported).
  uint emittersByMaps;
};
struct ArLevelPush {  // ar_pull_up, ar_sum_down: one level of the trees' inner nodes
  uint firstInner;    // where the level starts in the inner nodes
  uint innerCount;    // its inner nodes (the pull-up runs an invocation per node and bin)
};
struct ArGatherPush {  // ar_gather, one chunk of each receiver's list
  uint nodeCount;
  uint chunk;           // which chunk of kArGatherChunk (chunkLinks) links this dispatch walks
  uint chunks;          // the chunks recorded (a list longer than they walk is flagged)
  uint chunkLinks;      // the links of a list a chunk walks (kArGatherChunk but in tests)
  uint emittersByMaps;  // 1: the surfels' radiance holds no emission (ArLocalPush's)
};
struct ArIncidentPush {  // ar_incident
  uint surfelCount;
  uint sumSlot;  // where the iteration leaves its IterationSums
  uint lightCount;
  uint environmentOn;
  // 1: each surfel's irradiance adds the emitters' and the punctual lights' direct light from depth
  // maps
  uint emittersByMaps;
  // The share ω of an iteration's step that is taken (1: all of it; less damps an iteration that
  // diverges): each surfel's incident table and irradiance go ω of the way to the new.
  float damping;
};

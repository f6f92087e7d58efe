// iv (engine/gi/iv/): leaf links, the prune's queues and what a static leaf keeps, the receivers,
// the bounces, and the push constants of its passes.
// Part of shaders/interface.h, which includes it inside its namespace and language macros.
// A leaf's surviving links: where they start and how many.
struct LeafRange {
  uint first;
  uint count;
};
// A surviving link of a leaf: sender node and the bits of its clamped form factor (one rg32ui texel).
struct LeafLink {
  uint sender;
  uint formFactorBits;
};
// Per node, for the prune: it moves (its object may move: pruned every frame), its object's
// surface is closed (scene::closedInstances) with its normals out (Hierarchy::rootEncloses), its object moves rigidly
// (its links to itself are pruned once, in its rest pose), and above kNodeRootShift its object's root node (which is
// the object's number: roots come first). For the reflections, a leaf whose base leaves by its exit angle
// (baseLeavesByAngle, in a scene where some base does: Geometry::directionalBases).
IVGI_CONST uint kNodeMoves = 1u;
IVGI_CONST uint kNodeClosed = 2u;
IVGI_CONST uint kNodeRigid = 4u;
IVGI_CONST uint kNodeBaseByAngle = 8u;
IVGI_CONST uint kNodeRootShift = 4u;
// After the nodes' flags, per object, kPoseWords float bits: the rigid motion from where a rigidly
// moving object is this frame back to its rest pose, 3 rows of a 3×4 matrix (identity for the
// others); then the axes its surfaces follow (gi::objectAxes' first and last rows), at rest
// (kRestAxesWord) and as it stands this frame (kAxesWord).
IVGI_CONST uint kRestAxesWord = 12u;
IVGI_CONST uint kAxesWord = 18u;
IVGI_CONST uint kPoseWords = 24u;
// Arrays that can outgrow one texel view (the leaf links grow with the bins squared) are bound as
// kTexelParts views of one buffer, each 2^texelPartBits texels (shaders/common/parted_texels.glsl, which
// names each view). Two: the prune binds four such arrays, and a push-descriptor layout holds at
// most 32 descriptors on lavapipe and NVIDIA alike.
IVGI_CONST uint kTexelParts = 2u;

// The prune's shared-memory queues: root-path senders gathered per round (also the most that can
// be wide), emitters a leaf lists, and emitters a static leaf keeps for the frames.
IVGI_CONST uint kPathChunk = 512u;
IVGI_CONST uint kEmitterQueue = 256u;
IVGI_CONST uint kStaticEmitters = 64u;
IVGI_CONST uint kManyEmitters = 0xFFFFFFFFu;  // a static leaf's emitters that did not fit its list
// What a static leaf keeps of its static survivors between frames (prune_bins.comp): the
// environment through its static bins and that light's rotation gradient (columns r, g, b), the
// emission those bins credited (taken back where its emitters' direct light stands for it), the
// proximity of what they show, how many emitters it lists (kManyEmitters: too many to list), and the
// frame its bins lie along (common.glsl's packBinFrame: its normal and first axis, packed).
struct StaticLeaf {
  vec4 environment;
  vec4 environmentTurn[3];
  vec4 correction;
  float proximity;
  uint emitterCount;
  uint frameNormal;
  uint frameTangent;
};
// Per surfel, the prune's light from outside the links (the environment through the empty bins, the
// lights the bins carry) and the rotation gradient of its environment's part: kExternalTexels
// texels, the light then the gradient's columns r, g, b.
IVGI_CONST uint kExternalTexels = 4u;

// Mask words of a leaf's 6·N² bins, one bit a bin.
IVGI_FN uint maskWordsFor(uint n) { return (6u * n * n + 31u) / 32u; }

// ---- iv: receivers (engine/gi/iv/receivers.h) ----

// Irradiance is solved at receivers, surfels chosen each frame where the lighting needs them, and
// interpolated to every other surfel. Slots of the receivers' counter buffer:
IVGI_CONST uint kReceiverCandidatesA = 0u;  // the two candidate lists of the refinement rounds
IVGI_CONST uint kReceiverCandidatesB = 1u;
IVGI_CONST uint kReceiverCount = 2u;       // receivers listed so far this frame
IVGI_CONST uint kReceiverRound = 3u;       // the first receiver listed in this round
IVGI_CONST uint kReceiverFills = 4u;       // surfels that no receiver's support reached, made receivers
IVGI_CONST uint kReceiverScale = 5u;       // the largest irradiance gathered (luminance bits)
IVGI_CONST uint kReceiverGroupsDone = 6u;  // workgroups of a round's step that finished
IVGI_CONST uint kReceiverSlots = 8u;
// A surfel's support radius as float bits: +inf while it is not a receiver (atomicMin lists it once).
IVGI_CONST uint kNotReceiver = 0x7F800000u;
// The most receivers a surfel's irradiance is interpolated from (those of largest weight), and the
// most nodes whose receivers may weigh for some surfel of a group of neighbours (listed per group; a
// group with more has its surfels search on their own).
IVGI_CONST uint kInterpolationTaps = 16u;
IVGI_CONST uint kGroupNeighbours = 256u;
// Invocations a workgroup of the dispatches over receivers and candidates: a round lists few, and
// lavapipe runs a workgroup on one thread, so small workgroups keep every thread busy.
IVGI_CONST uint kReceiverGroup = 8u;
// Dispatch arguments of the receivers (shaders/iv/receiver_args.glsl), in order: the round's
// candidates, the round's new receivers, every receiver, then one per prune batch over the new
// receivers.
IVGI_CONST uint kArgsCandidates = 0u;
IVGI_CONST uint kArgsNewReceivers = 1u;
IVGI_CONST uint kArgsReceivers = 2u;
IVGI_CONST uint kArgsPruneBatches = 3u;
// What receiver_args.comp does, as bits of its mode.
IVGI_CONST uint kArgsStartRound = 1u;  // the candidates' dispatch; the round's receivers start here
IVGI_CONST uint kArgsListed = 2u;      // the dispatches over the new and over every receiver

// A sampled node's receiver (its representative) stands for it in the interpolation: its support
// reaches kReceiverReach times the node's radius, and its weight at a surfel falls from a peak to 0
// over it (distances across the surfel's tangent plane count kReceiverPlaneStretch times) and with
// the angle between their normals, to 0 at kReceiverNormalCos.
IVGI_CONST float kReceiverReach = 2.5f;
IVGI_CONST float kReceiverNormalCos = 0.7f;
IVGI_CONST float kReceiverPlaneStretch = 4.0f;

// Refinement is continuous in what it judges by, so that a small change (a frame later, a scaled
// scene) changes the image a little: each sampled node has a need, the largest of its tests'
// statistics over their thresholds; its children are sampled once the need passes kRefineFrom, and
// they take over its place in the interpolation gradually, fully at 1. A node's presence is the
// product of refinementShare over its ancestors' needs (0: not sampled); its own share of that,
// its role, is what its children have not taken.
IVGI_CONST float kRefineFrom = 0.75f;
IVGI_FN float refinementShare(float need) { return clamp((need - kRefineFrom) / (1.0f - kRefineFrom), 0.0f, 1.0f); }

struct InterpolationTap {  // one rg32ui texel: the receiver, the bits of its coefficient
  uint receiver;
  uint weightBits;
};

// ---- Push constants of iv's passes ----

struct PrunePush {    // prune_bins
  uint firstSurfel;   // the leaves [firstSurfel, endSurfel) of this dispatch's batch; listed: of the
  uint endSurfel;     // round's new receivers
  uint listed;        // 1: the receivers the round listed; 0: the surfels themselves
  uint linkCapacity;  // of the leaf links (of the static pass: the static leaf links)
  uint lightCount;
  uint environmentOn;
  uint staticCapacity;  // the static leaf links the frame pass merges with
  // 1: the emitters' and the punctual lights' direct light comes from depth maps (surfelDirect): no
  // emitter is listed, the light the bins credit emissive survivors is taken back from every leaf,
  // and no light is looked for in the bins.
  uint emittersByMaps;
  uint poseBase;  // where the objects' poses start in the nodes' flags (the node count)
  // 1: the static pass prunes a rigid leaf only once it is a receiver (listed), the first time;
  // until then its static range is kRigidUnpruned.
  uint rigidWhenListed;
};
// A rigid leaf's static range until the static pass has pruned it (PrunePush::rigidWhenListed).
IVGI_CONST uint kRigidUnpruned = 0xFFFFFFFFu;
struct GatherPush {     // gather, lobe_excess and the passes of the metals' lobes (Bounces::recordArrival)
  uint maskWords;       // of a static leaf's override mask
  uint newOnly;         // 1: the round's new receivers; 0: every receiver listed
  uint emittersByMaps;  // 1: the depth maps give the emitters' light (left out of the gradient)
  float largestBin;     // solid angle of the largest direction bin, about (2/N)²
  float leastSpread;    // the least spread (brdf.h's widenedLobe) the bins resolve (sender_lobes.glsl)
  uint poseBase;        // PrunePush's
  uint arrival;         // gather: 1 adds what metals send along their lobes of the first bounce
  uint surfelCount;     // mark_arrival, send_arrival
  uint directKnown;     // lobe_excess: 1 where the estimates left each receiver's direct light's
                        // excess (Bounces::recordStart's `estimated`): the first bounce's alone
};
// The first bounce's light arriving where a metal surfel interpolates it from, split by where it
// comes from: the classes are the world's six half-axes, the one nearest its direction
// (arrival_lobes.comp). A metal leaf sends the lobes of the kArrivalLobes classes it reflects most
// along them, the rest evenly (send_arrival.comp).
IVGI_CONST uint kArrivalClasses = 6u;
IVGI_CONST uint kArrivalLobes = 3u;
struct ReceiverArgsPush {  // receiver_args
  uint mode;               // kArgsStartRound | kArgsListed
  uint source;             // the round's candidate list (counter slot)
  uint target;             // the next round's, emptied
  uint batch;              // receivers a prune batch takes
  uint leavesPerGroup;
  uint maxGroups;  // of a prune batch
  uint batches;    // prune batches recorded a round
  uint pad;
};
// select_receivers, refine_receivers, receiver_roles, neighbour_lists, interpolation_weights: the
// refinement's lists and criteria, and the counts the passes over nodes, groups and surfels run to.
struct ReceiverPush {
  uint source;      // candidate list (counter slot) read
  uint target;      // candidate list written
  float tolerance;  // --receiver-tol: how far a sample may miss its prediction from its neighbours
  float proximity;  // a node's support may reach this share of the mean distance to what its receiver sees
  uint nodeCount;
  uint surfelCount;
  float floorShare;  // a sample darker than this share of the largest is judged against that
  uint groupCount;   // of neighbour lists
  float largest;     // the largest radius a cell may have
  // At a node none of whose surfels the image shows (kShownFit), the light test's need is scaled by
  // this (1 / --unseen-tol) and the proximity test's by its square root, as --receiver-tol's own
  // scale them; 1 where the refinement does not follow the view.
  float unseenShare;
  // The prune's batching (Prune::Batching), for the dispatch sizes over the receivers listed.
  uint batch, leavesPerGroup, maxGroups, batches;
};
struct SeenPush {  // seen_nodes
  uint surfelCount;
  float leastSpread;  // senderBinSpread(): the bins' widening of a lobe (brdf.h's widenedLobe)
};
struct InterpolatePush {  // interpolate, bounce_tail
  uint surfelCount;
};
// The bounces stop where the light, with the geometric tail of the bounces not run added, settles
// within a tolerance (or after a count): the interpolation leaves per workgroup the area-weighted
// luminance of its leaves' radiosity and of its change, and bounce_check sums them in a fixed order,
// decides, and writes the next bounce's dispatch sizes (zero groups once it is done) and the tail's.
struct BounceSum {
  float total;   // Σ area · Y(B)
  float change;  // Σ area · |Y(B) − Y(B before)|
};
struct BounceState {
  uint gathers;     // run so far this frame (K bounces are K + 1 gathers)
  uint done;        // 1: converged or at the count
  float change;     // of the last gather
  float total;      // after the last gather
  float remaining;  // how far the light with its tail may still be off, over total (bounce_check.comp)
  float gain;       // the tail's factor q/(1 − q) (0: none), q the ratio of the last two changes
  float estimate;   // the light with its tail: total + change · gain
  float step;       // how much that estimate moved at the last gather, over total
  float least;      // the least change from the second gather on
  uint diverged;    // 1: stopped where a change grew past kDivergingGrowth times that least
};
// Each bounce adds less light than the one before wherever albedo is below 1 (a convergent
// transport); a change this many times the least before it, and past kDivergingFloor of the light,
// means the bounces diverge. Below that floor the changes are the float sums' own jitter (a count
// forced far past convergence), which may double.
IVGI_CONST float kDivergingGrowth = 2.0f;
IVGI_CONST float kDivergingFloor = 1e-4f;
struct BounceCheckPush {  // bounce_check
  uint groups;            // of the interpolation: BounceSums to add up
  uint dispatches;        // of a bounce: the gather, the interpolation, then one pull-up a level; the tail's after them
  uint maxGathers;        // done after this many
  float tolerance;  // done where remaining ≤ tolerance, and the tail added; negative: only at maxGathers, no tail
};

// Link creation (engine/gi/links.h), shared by iv and ar: a link set's counters, link creation's
// workgroups and dispatch sizes, what a frame ran out of room for, and its passes' push constants.
// Part of shaders/interface.h, which includes it inside its namespace and language macros.

IVGI_CONST uint kEmitterBit = 0x80000000u;  // on a sender in a receiver's list: it emits
// The slots of a link set's counter buffer. kCounterSendersWalked is the low word of a 64-bit
// count (the carries go to the next slot): the root-path senders a prune walked, its work;
// kCounterMergedWalked, likewise, the part of it the static leaves walked to merge a frame's
// senders into their static bins (the rest: the moving leaves' full walks), and
// kCounterRigidWalked the part of that the leaves of rigid objects walked (their objects' links to
// the rest); kCounterRigidLeaves counts those leaves.
IVGI_CONST uint kCounterWorklistA = 0u;
IVGI_CONST uint kCounterWorklistB = 1u;
IVGI_CONST uint kCounterLinks = 2u;
IVGI_CONST uint kCounterLeafLinks = 3u;
IVGI_CONST uint kCounterOverflow = 4u;
IVGI_CONST uint kCounterWorklistPeak = 5u;
IVGI_CONST uint kCounterSendersWalked = 6u;
IVGI_CONST uint kCounterGroupsDone = 8u;  // a refinement level's finished workgroups (refine_links)
IVGI_CONST uint kCounterMergedWalked = 9u;
IVGI_CONST uint kCounterRigidWalked = 11u;
IVGI_CONST uint kCounterRigidLeaves = 13u;
IVGI_CONST uint kCounterSlots = 14u;
// Link creation's workgroups (refine_links, count_links, scatter_links) and its indirect dispatch
// sizes (uvec4 each in its args buffer): the next refinement level's, and the sort's (the links).
IVGI_CONST uint kLinkGroup = 256u;
IVGI_CONST uint kLinkArgsLevel = 0u;
IVGI_CONST uint kLinkArgsSort = 1u;
// The dispatch size for a list of `items`: along x alone, as link creation's shaders loop over what
// their workgroups cannot cover at once.
IVGI_FN uvec4 linkGroupsFor(uint items) { return uvec4(groupsFor(items, kLinkGroup).x, 1u, 1u, 0u); }
// Bits of counters[kCounterOverflow]: what a frame ran out of room for (it is redone with more).
// kOverflowLoopBudget: a prune workgroup ran out of lavapipe's loop budget (common.glsl).
IVGI_CONST uint kOverflowWorklist = 1u;
IVGI_CONST uint kOverflowLinks = 2u;
IVGI_CONST uint kOverflowLeafLinks = 4u;
IVGI_CONST uint kOverflowLoopBudget = 8u;

struct RefinePush {  // refine_links
  uint source;       // counter slots of this level's list and of the next
  uint target;
  uint capacity;  // of each worklist
  uint linkCapacity;
  float epsilon;        // form-factor threshold
  float largeSender;    // κ·Ω of a bin: a sender subtending more is split
  float largeReceiver;  // and a receiver subtending more from its sender (3.4e38: never)
  uint bothSides;       // 1: senders behind the receiver's horizon are linked too (|cos| estimates)
  // A receiver subtending more than this from an emitting sender (`emitters` nonzero) is split
  // (0: down to its surfels).
  float emitterReceiver;
  uint receiverStaysWhole;  // 1: a pair whose sender is a leaf is stored, however large its receiver
  uint skipBuriedSenders;   // 1: a pair whose sender lies wholly inside another object is dropped
};
struct SortLinksPush {  // count_links, scatter_links
  uint linkCapacity;    // the links past it were not stored (the set overflowed)
};

#pragma once
// Link creation (docs/design.md §2.1, §5): from a list of root pairs, level-synchronous refinement on
// two worklists with indirect dispatch (a pair is stored as a link or split into the pairs of its
// larger node's children), then the links sorted by receiver: counted, scanned, scattered. iv and
// ar make their links with it, each by its own criteria.
#include <cstdint>
#include <vector>

#include "engine/gi/hierarchy.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

// The links made from a list of root pairs, sorted by receiver, with the counters of their making
// (gpu::kCounter… slots). iv has one set for the pairs of static objects (made once) and one for
// the pairs with a moving side (made whenever the geometry moved).
struct LinkSet {
  std::vector<uint32_t> rootPairs;  // receiver root, sender root
  // The refinement levels its pairs take at most: each level splits one side of a pair (or both of
  // a node with itself), so the deepest pair's two trees' heights, then a level that stores it.
  uint32_t levels = 0;
  vk::Buffer roots, counters, links, counts, starts, senders;
  uint32_t linkCapacity = 0, leafLinkCapacity = 0;

  bool empty() const { return rootPairs.empty(); }
  // Allocates the root pairs, counters and per-receiver lists of a hierarchy of `nodeCount` nodes
  // (links and senders are sized by the solver). The starts begin as zeros, so that an empty set's
  // lists are empty wherever a pass reads them.
  void allocateLists(const vk::Context& ctx, uint32_t nodeCount, vk::Allocations* allocations);
  std::vector<uint32_t> readCounters() const;
  // The counters after its refinement; throws where pairs were left unrefined (a bug).
  std::vector<uint32_t> refinedCounters() const;
  // Grows the link capacity, and `worklistCapacity`, to what the counters `c` say overflowed, with
  // a margin; whether either grew.
  bool growLinks(const std::vector<uint32_t>& c, uint32_t& worklistCapacity);
  // The surviving links the last prune of this set wrote (those that fit).
  uint32_t leafLinksHeld() const;
};

// Whether some objects move (per hierarchy root; empty: every one may) and some do not: then the
// pairs of two static objects are worth linking once.
bool mixesStaticAndMoving(const std::vector<bool>& objectMoves, size_t rootCount);
// Every pair of roots (receiver, sender), each object with every other and with itself: into
// `fixed` where both objects are static and `split`, or where both move rigidly together (the same
// `rigidGroup`, per root; -1: none; empty: no object does); else into `moving`.
void assignRootPairs(const Hierarchy& hierarchy, const std::vector<bool>& objectMoves, bool split, LinkSet& fixed,
                     LinkSet& moving, const std::vector<int>& rigidGroup = {});

// The room an array that grows with a count gets: a quarter more, so that the next frames' changes
// fit.
uint32_t withMargin(uint32_t needed);

// When a pair is split rather than stored.
struct LinkCriteria {
  float epsilon;  // the form-factor estimate above which the larger node is split
  // Solid angles above which a sender, or a receiver seen from its sender, is split (κ·Ω of a bin);
  // 3.4e38: never.
  float largeSender, largeReceiver;
  // Whether senders behind the receiver's horizon are linked too (ar: antiradiance reaches a
  // surface's back); and then the form-factor estimate takes |cos| on both sides.
  bool bothSides;
  // The solid angle above which a receiver seen from an emitting sender (LinkWork::emitters nonzero)
  // is split (0: down to its surfels).
  float emitterReceiver;
  // iv: each leaf re-bins every sender of its root path from its own position, so a sender that
  // cannot be split is linked to its receiver whole: splitting the receiver would only give each of
  // its leaves the same sender through more links.
  bool receiverStaysWhole;
  // Whether a sender all of whose surfels lie inside another object (LinkWork::buried) is left out.
  bool skipBuriedSenders;
};

// What the refinement works in: its two worklists, the dispatch arguments between its levels, per
// node whether it counts as an emitter (nonzero rgb: iv's emission, ar's bright emitters; its links
// carry kEmitterBit), per node how many surfels below it lie inside another object for as long as
// the set's links stand (SceneBuffers::nodeBuried for links made whenever the geometry moved,
// nodeStillBuried for links made once; a node all of whose surfels do is no sender), and a pool that
// holds the trees ("tree"), their node states ("nodes"), "nodeLeaves" and iv's "nodeFlags"
// (gpu::kNodeClosed: a sender turned wholly away from its receiver is no sender where the criteria
// leave out the back of surfaces).
struct LinkWork {
  const vk::Buffer &args, &worklistA, &worklistB, &emitters, &buried;
  vk::Bindings pool;
};

class LinkCreation {
 public:
  explicit LinkCreation(const vk::Context& ctx);
  void record(VkCommandBuffer cmd, LinkSet& set, const LinkWork& work, const Hierarchy& hierarchy,
              const LinkCriteria& criteria, uint32_t worklistCapacity) const;

 private:
  vk::Program refine_, count_, scan_, scatter_;
};

}  // namespace ivgi::gi

#pragma once
// The room of the arrays that grow with the link counts: the refinement's worklists, each link
// set's links and its surviving leaf links. Link counts are known only once the GPU made them, so
// the room starts from a guess, grows when a frame overflowed (the frame is then redone) and gives
// back what stays unused. Where device memory cannot hold them, the largest go to host memory, which
// the device reads across its bus (slower); a request beyond that, or
// beyond the device's limits on one array, is refused with a message that names the settings to
// change.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/gi/iv/buffers.h"
#include "engine/gi/iv/settings.h"
#include "engine/gi/links.h"

namespace ivgi::gi {

class LinkRoom {
 public:
  LinkRoom(const vk::Context& ctx, const IvSettings& settings, IvBuffers& buffers, LinkSet& staticSet,
           LinkSet& frameSet, vk::Allocations& allocations);

  // A first guess for every set (from the leaves each prunes in full or merges), allocated; where
  // it does not fit the device, a small start that grows to what the first frame counts.
  void guess(const std::vector<uint32_t>& leafMoves, uint32_t nodeCount);
  uint32_t worklistCapacity() const { return worklistCapacity_; }

  // What a frame ran out of, from the link sets' counters.
  struct Overflow {
    bool any = false;         // the frame must be redone
    bool loopBudget = false;  // a prune workgroup ran out of loop rounds
    bool staticSet = false;   // the static set's links must be made again
  };
  // Where rigid leaves are pruned the first time they are receivers (Prune::pruneRigidWhenListed),
  // the static set's surviving links grow from frame to frame: its links are kept for them, and
  // its leaf links grow keeping what they hold.
  void keepStaticGrowing(bool grows) { staticGrows_ = grows; }
  // After a frame: grows what overflowed (and allocates it). `staticLinked`: the frame made the
  // static set's links (its static pass is redone whatever overflowed).
  Overflow grow(bool staticLinked);
  // After a frame that stands: gives back the leaf-link room it left unused, keeping the links the
  // sets hold, and frees the static pairs' links once `staticLinked`.
  void releaseUnused(bool staticLinked);
  // The texel views the leaf links' arrays are bound in at their room now: 1 or kTexelParts
  // (shaders/common/parted_texels.glsl). The passes that read them are made for that many.
  uint32_t leafLinkTexelViews() const;
  // The bytes of link arrays held in host memory (where the device's could not hold them).
  uint64_t hostBytes() const;

 private:
  // An array that grows with a count; bound as texels (imageBuffers), so that maxTexelBufferElements
  // limits it rather than maxStorageBufferRange. The leaf links' arrays, which grow as the bins
  // squared, are bound in kTexelParts views, so that only the largest allocation limits them.
  struct Array {
    vk::Buffer* buffer;
    uint64_t count, elementBytes;
    const char* what;
    const LinkSet* leafLinksOf = nullptr;    // the set whose surviving links it holds (kept when it shrinks)
    const LinkSet* linksOf = nullptr;        // the set whose links it holds (kept when it shrinks)
    vk::Memory memory = vk::Memory::Device;  // where it is to be (place())
    bool parted() const { return leafLinksOf != nullptr; }   // the leaf links' arrays
    bool kept() const { return buffer->size() >= bytes(); }  // it keeps its buffer, and its memory
    uint64_t elements() const { return std::max<uint64_t>(count, 1); }
    uint64_t bytes() const { return elements() * elementBytes; }
  };
  // At the capacities the link sets hold now, each placed: in device memory while it holds them,
  // else (`hostAllowed`) the largest of those allocated anew in host memory.
  std::vector<Array> arrays(bool hostAllowed = true) const;
  void place(std::vector<Array>& arrays, bool hostAllowed) const;
  uint64_t deviceBudget() const;  // --max-memory, else the device's heap
  // Why those arrays cannot be allocated on this device (empty: they can).
  std::string refusal(const std::vector<Array>& arrays) const;
  // Allocates the arrays at their capacities; `keepStatic`: the static set's leaf links keep what
  // they hold.
  void allocate(bool keepStatic = false);
  uint32_t firstLeafLinkGuess(const LinkSet& set, const std::vector<uint32_t>& leafMoves) const;
  uint64_t mostLeafLinks() const;                // the most leaf links their texel views hold
  uint32_t leafLinkRoom(uint32_t needed) const;  // room for `needed` leaf links, with a margin

  const vk::Context& ctx_;
  const IvSettings& settings_;
  IvBuffers& b_;
  LinkSet& staticSet_;
  LinkSet& frameSet_;
  vk::Allocations& allocations_;
  uint32_t worklistCapacity_ = 0;
  bool staticGrows_ = false;
};

}  // namespace ivgi::gi

#include "engine/gi/iv/link_room.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/core/errors.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

LinkRoom::LinkRoom(const vk::Context& ctx, const IvSettings& settings, IvBuffers& buffers, LinkSet& staticSet,
                   LinkSet& frameSet, vk::Allocations& allocations)
    : ctx_(ctx),
      settings_(settings),
      b_(buffers),
      staticSet_(staticSet),
      frameSet_(frameSet),
      allocations_(allocations) {}

// A first guess at a set's surviving links, so that the first frame is not pruned twice (once to
// count them): a leaf the set prunes in full keeps about the bins of its hemisphere, 3N² (fewer in
// an open scene, whose surplus the first frame gives back); a static leaf merging the frame's
// senders re-emits only the bins they touch, about N²/2; plus the usual margin.
uint32_t LinkRoom::firstLeafLinkGuess(const LinkSet& set, const std::vector<uint32_t>& leafMoves) const {
  if (set.empty()) return 0;
  const uint64_t hemisphere = 3ull * settings_.bins * settings_.bins, merged = hemisphere / 6;
  uint64_t guess = 0;
  for (uint32_t moves : leafMoves)
    guess += &set == &staticSet_ ? (moves ? 0 : hemisphere) : (moves ? hemisphere : merged);
  return withMargin(uint32_t(std::min<uint64_t>(guess, 0xFFFFFFF0u)));
}

void LinkRoom::guess(const std::vector<uint32_t>& leafMoves, uint32_t nodeCount) {
  const uint32_t surfelCount = uint32_t(leafMoves.size());
  // A first frame whose room falls short is redone (its links at least), so the guesses are generous
  // and what stays unused is given back once the frame stands. Refinement makes tens of links a
  // node, more with more bins, and past a hundred where nested parts' bounds overlap
  // (2CylinderEngine.glb: 104); its widest level holds ten to twenty pairs a node (the engine: 20).
  const uint64_t rootPairs = std::max(staticSet_.rootPairs.size(), frameSet_.rootPairs.size()) / 2;
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    set->linkCapacity = set->empty() ? 0 : 128 * nodeCount + 1024;
    set->leafLinkCapacity = firstLeafLinkGuess(*set, leafMoves);
  }
  worklistCapacity_ = uint32_t(std::max<uint64_t>(rootPairs, 32ull * nodeCount + 1024));
  // A guess that does not fit the device shrinks to what does, down to a small start that grows to
  // what the first frame counts: the leaf links first (their overflow costs the whole frame again),
  // then the links and worklists (theirs only the links).
  const uint64_t smallLeafLinks = uint64_t(surfelCount) * std::min(6 * settings_.bins * settings_.bins, 128u) + 1024;
  const uint64_t smallLinks = 48ull * nodeCount + 1024,
                 smallWorklist = std::max<uint64_t>(rootPairs, 16ull * nodeCount + 1024);
  auto shrink = [](uint32_t& capacity, uint64_t least) {
    if (capacity <= least) return false;
    capacity = uint32_t(std::max<uint64_t>(uint64_t(capacity) * 3 / 4, least));
    return true;
  };
  while (!refusal(arrays(false)).empty()) {
    bool shrunk = false;
    for (LinkSet* set : {&staticSet_, &frameSet_}) shrunk |= shrink(set->leafLinkCapacity, smallLeafLinks);
    if (!shrunk) {
      for (LinkSet* set : {&staticSet_, &frameSet_}) shrunk |= !set->empty() && shrink(set->linkCapacity, smallLinks);
      shrunk |= shrink(worklistCapacity_, smallWorklist);
    }
    if (!shrunk) break;  // allocate() puts the rest in host memory, or names what does not fit
  }
  allocate();
}

uint64_t LinkRoom::mostLeafLinks() const { return uint64_t(gpu::kTexelParts) << ctx_.texelPartBits(); }

uint32_t LinkRoom::leafLinkRoom(uint32_t needed) const {
  // The margin only where it fits: leaf links that fit their views exactly are not refused.
  return uint32_t(std::min<uint64_t>(withMargin(needed), std::max<uint64_t>(needed, mostLeafLinks())));
}

uint32_t LinkRoom::leafLinkTexelViews() const {
  const uint64_t most = std::max(staticSet_.leafLinkCapacity, frameSet_.leafLinkCapacity);
  return most > (uint64_t(1) << ctx_.texelPartBits()) ? gpu::kTexelParts : 1u;
}

std::vector<LinkRoom::Array> LinkRoom::arrays(bool hostAllowed) const {
  // All are texels (imageBuffers), whose views reach past one storage binding.
  std::vector<Array> arrays = {
      {&b_.worklistA, worklistCapacity_, 8, "refinement worklist"},
      {&b_.worklistB, worklistCapacity_, 8, "refinement worklist"},
      {&b_.leafLinks, frameSet_.leafLinkCapacity, 8, "leaf links", &frameSet_},
      {&b_.staticLinks, staticSet_.leafLinkCapacity, 8, "static leaf links", &staticSet_},
      {&b_.staticBins, staticSet_.leafLinkCapacity, 4, "static leaf links' bins", &staticSet_},
      {&b_.staticDepths, staticSet_.leafLinkCapacity, 4, "static leaf links' depths", &staticSet_}};
  for (LinkSet* set : {&staticSet_, &frameSet_})
    arrays.insert(arrays.end(), {{&set->links, set->linkCapacity, 8, "links", nullptr, set},
                                 {&set->senders, set->linkCapacity, 4, "links", nullptr, set}});
  place(arrays, hostAllowed);
  return arrays;
}

uint64_t LinkRoom::deviceBudget() const { return ctx_.deviceBudget(settings_.memoryBudget); }

void LinkRoom::place(std::vector<Array>& arrays, bool hostAllowed) const {
  // An array that keeps its buffer keeps its memory; one allocated anew (its predecessor freed
  // first) goes to the device while the device holds it, the largest first to the host if not.
  uint64_t device = allocations_.deviceBytes();
  std::vector<Array*> anew;
  for (Array& a : arrays) {
    if (a.kept()) {
      a.memory = a.buffer->memory();
      continue;
    }
    if (a.buffer->memory() == vk::Memory::Device) device -= a.buffer->size();
    device += a.bytes();
    anew.push_back(&a);
  }
  std::stable_sort(anew.begin(), anew.end(), [](const Array* a, const Array* b) { return a->bytes() > b->bytes(); });
  for (Array* a : anew) {
    if (!hostAllowed || device <= deviceBudget()) break;
    a->memory = vk::Memory::Host;
    device -= a->bytes();
  }
}

namespace {
std::string mebibytes(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, bytes >= (1u << 20) ? "%.0f MiB" : "%.3g MiB", double(bytes) / double(1u << 20));
  return text;
}
}  // namespace

std::string LinkRoom::refusal(const std::vector<Array>& arrays) const {
  // Links grow about as 1/ε, leaf links as N²: the settings that would fit, were `over` the excess.
  auto refused = [&](uint64_t bytes, const std::string& what, const std::string& limit, uint64_t limitBytes) {
    const double over = double(bytes) / double(std::max<uint64_t>(limitBytes, 1)) * 1.25;
    char fit[160];
    std::snprintf(fit, sizeof fit, "--eps %.3g or --bins %u would fit (links grow about as 1/eps, leaf links as N^2)",
                  settings_.epsilon * over, std::max(1u, uint32_t(double(settings_.bins) / std::sqrt(over))));
    // Every surfel a receiver (a GPU's default) holds every surfel's leaf links: fewer receivers hold fewer.
    char fewer[96] = "";
    if (*settings_.receiverTolerance <= 0.0f)
      std::snprintf(fewer, sizeof fewer, "; or --receiver-tol %g (receivers where the lighting needs them)",
                    kCpuReceiverTolerance);
    return "the iv solver needs " + mebibytes(bytes) + " of " + what + ", above " + limit + " of " +
           mebibytes(limitBytes) + ": about " + fit + fewer;
  };
  const VkPhysicalDeviceLimits& limits = ctx_.limits();
  // Once every array has its new size, where place() put it.
  uint64_t device = allocations_.deviceBytes(), host = allocations_.hostBytes();
  for (const Array& a : arrays) {
    const uint64_t texelLimit = a.parted() ? mostLeafLinks() : uint64_t(limits.maxTexelBufferElements);
    if (a.elements() > texelLimit)
      return refused(a.bytes(), a.what,
                     a.parted() ? "the " + std::to_string(gpu::kTexelParts) + " texel views it is bound in"
                                : std::string("the device's maxTexelBufferElements"),
                     texelLimit * a.elementBytes);
    if (a.bytes() > ctx_.maxAllocationBytes())
      return refused(a.bytes(), a.what, "the device's maxMemoryAllocationSize", ctx_.maxAllocationBytes());
    if (a.kept()) continue;
    (a.buffer->memory() == vk::Memory::Host ? host : device) -= a.buffer->size();
    (a.memory == vk::Memory::Host ? host : device) += a.bytes();
  }
  if (device > deviceBudget()) {
    const std::string limit = settings_.memoryBudget ? "--max-memory" : "the device's memory heap";
    const bool linksMoved = std::any_of(arrays.begin(), arrays.end(),
                                        [](const Array& a) { return !a.kept() && a.memory == vk::Memory::Host; });
    if (!linksMoved) return refused(device, "device memory in all", limit, deviceBudget());
    // What stays on the device is the scene's and the receivers' own: it follows the surfels and the bins.
    return "the iv solver needs " + mebibytes(device) + " of device memory besides the links it can hold in host " +
           "memory, above " + limit + " of " + mebibytes(deviceBudget()) +
           ": a coarser --tessellate (fewer surfels) or fewer --bins would need less";
  }
  if (ctx_.hostHeapIsDeviceHeap() ? device + host > ctx_.hostHeapBytes() : host > ctx_.hostHeapBytes())
    return refused(device + host, "memory in all, the links past the device's in host memory", "the host's memory heap",
                   ctx_.hostHeapBytes());
  return {};
}

void LinkRoom::allocate(bool keepStatic) {
  const std::vector<Array> all = arrays();
  if (std::string why = refusal(all); !why.empty()) throw SettingsError(why);
  const uint64_t held = keepStatic ? staticSet_.leafLinksHeld() : 0;
  for (const Array& a : all) {
    if (a.buffer->size() >= a.bytes()) continue;  // keeps what it holds
    if (held > 0 && a.leafLinksOf == &staticSet_) {
      // The links that fitted, all within the old room (the count passed it where they overflowed).
      const uint64_t kept = std::min(held, a.buffer->size() / a.elementBytes);
      vk::Buffer grown(ctx_, a.bytes(), a.memory, &allocations_);
      ctx_.submitAndWait([&](VkCommandBuffer cmd) {
        vk::copyRegion(cmd, *a.buffer, grown, {0, 0, kept * a.elementBytes});
      });
      *a.buffer = std::move(grown);
      continue;
    }
    *a.buffer = vk::Buffer();  // before its successor: the two need not fit at once
    *a.buffer = vk::Buffer(ctx_, a.bytes(), a.memory, &allocations_);
  }
}

uint64_t LinkRoom::hostBytes() const {
  uint64_t host = 0;
  for (const Array& a : arrays())
    if (a.buffer->memory() == vk::Memory::Host) host += a.buffer->size();
  return host;
}

LinkRoom::Overflow LinkRoom::grow(bool staticLinked) {
  Overflow overflow;
  bool keepStatic = false;
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    if (set->empty()) continue;
    const std::vector<uint32_t> c = set->refinedCounters();
    const uint32_t bits = c[gpu::kCounterOverflow];
    if (bits == 0) continue;
    set->growLinks(c, worklistCapacity_);
    if (bits & gpu::kOverflowLeafLinks)
      set->leafLinkCapacity = std::max(set->leafLinkCapacity, leafLinkRoom(c[gpu::kCounterLeafLinks]));
    overflow.loopBudget |= (bits & gpu::kOverflowLoopBudget) != 0;
    overflow.any = true;
    // A frame set's overflow leaves the static links whole; so does a static set's whose rigid
    // leaves pruned when listed ran out of room, which stay unpruned for the frame's redo.
    const bool keeps = staticGrows_ && !staticLinked && bits == gpu::kOverflowLeafLinks;
    keepStatic |= set == &staticSet_ && keeps;
    overflow.staticSet |= set == &staticSet_ && !keeps;
  }
  if (overflow.any) allocate(keepStatic);
  if (keepStatic)
    ctx_.submitAndWait([&](VkCommandBuffer cmd) {
      const uint32_t none = 0;
      vk::updateBuffer(cmd, staticSet_.counters, gpu::kCounterOverflow * sizeof(uint32_t), sizeof none, &none);
    });
  return overflow;
}

void LinkRoom::releaseUnused(bool staticLinked) {
  // The static set's surviving links are made once and never grow: they keep exactly their room,
  // and the links they were pruned from are not needed again; unless rigid leaves are pruned when
  // listed (keepStaticGrowing), which read those links and add to these later. What grows from
  // frame to frame keeps the margin, and shrinks only past a third unused, lest every frame
  // reallocate.
  bool shrinks = !staticSet_.empty() && staticLinked && staticSet_.linkCapacity > 0 && !staticGrows_;
  if (shrinks) staticSet_.linkCapacity = 0;
  auto fit = [&](uint32_t& capacity, uint32_t used) {
    const uint32_t fitted = withMargin(used);
    if (uint64_t(capacity) * 2 > uint64_t(fitted) * 3) capacity = fitted, shrinks = true;
  };
  auto exact = [&](uint32_t& capacity, uint32_t used) {
    if (capacity > used) capacity = used, shrinks = true;
  };
  uint32_t worklistPeak = 0;
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    if (set->empty()) continue;
    const bool isStatic = set == &staticSet_;
    if (isStatic && (!staticGrows_ || settings_.exactStaticRoom))
      exact(set->leafLinkCapacity, set->leafLinksHeld());
    else
      fit(set->leafLinkCapacity, set->leafLinksHeld());
    if (isStatic && staticLinked && !staticGrows_) continue;  // its links are not made again
    const std::vector<uint32_t> c = set->readCounters();
    if (!isStatic || staticGrows_) fit(set->linkCapacity, c[gpu::kCounterLinks]);
    if (!(isStatic && staticLinked)) worklistPeak = std::max(worklistPeak, c[gpu::kCounterWorklistPeak]);
  }
  fit(worklistCapacity_, worklistPeak);
  if (!shrinks) return;
  for (const Array& a : arrays()) {
    if (std::max(a.bytes(), vk::Buffer::kMinBytes) >= a.buffer->size()) continue;
    vk::Buffer kept(ctx_, a.bytes(), a.buffer->memory(), &allocations_);
    const uint64_t used = a.leafLinksOf ? a.leafLinksOf->leafLinksHeld()
                          : a.linksOf   ? std::min(a.count, uint64_t(a.linksOf->readCounters()[gpu::kCounterLinks]))
                                        : 0;
    if (used > 0)  // the links it holds
      ctx_.submitAndWait([&](VkCommandBuffer cmd) {
        vk::copyRegion(cmd, *a.buffer, kept, {0, 0, used * a.elementBytes});
      });
    *a.buffer = std::move(kept);
  }
}

}  // namespace ivgi::gi

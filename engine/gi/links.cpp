#include "engine/gi/links.h"

#include <algorithm>
#include <array>

#include "engine/gi/pass.h"

namespace ivgi::gi {

void LinkSet::allocateLists(const vk::Context& ctx, uint32_t nodeCount, vk::Allocations* allocations) {
  roots = vk::makeBuffer(ctx, empty() ? std::vector<uint32_t>{0, 0} : rootPairs, vk::Memory::Device, allocations);
  counters = vk::makeBuffer(ctx, std::vector<uint32_t>(gpu::kCounterSlots, 0u), vk::Memory::Host, allocations);
  counts = vk::Buffer(ctx, std::max(empty() ? 0u : nodeCount, 1u) * sizeof(uint32_t), vk::Memory::Device, allocations);
  starts = vk::makeBuffer(ctx, std::vector<uint32_t>(nodeCount + 1, 0u), vk::Memory::Device, allocations);
}

std::vector<uint32_t> LinkSet::readCounters() const { return counters.read<uint32_t>(gpu::kCounterSlots); }

std::vector<uint32_t> LinkSet::refinedCounters() const {
  std::vector<uint32_t> c = readCounters();
  if (uint32_t left = c[levels % 2]; left != 0)
    throw vk::VulkanError("link creation left " + std::to_string(left) + " pairs unrefined after " +
                          std::to_string(levels) + " levels");
  return c;
}

bool LinkSet::growLinks(const std::vector<uint32_t>& c, uint32_t& worklistCapacity) {
  const uint32_t bits = c[gpu::kCounterOverflow];
  if (bits & gpu::kOverflowWorklist)
    worklistCapacity = std::max(worklistCapacity, withMargin(c[gpu::kCounterWorklistPeak]));
  if (bits & gpu::kOverflowLinks) linkCapacity = std::max(linkCapacity, withMargin(c[gpu::kCounterLinks]));
  return (bits & (gpu::kOverflowWorklist | gpu::kOverflowLinks)) != 0;
}

bool mixesStaticAndMoving(const std::vector<bool>& objectMoves, size_t rootCount) {
  if (objectMoves.empty()) return false;
  const size_t moving = size_t(std::count(objectMoves.begin(), objectMoves.begin() + rootCount, true));
  return moving > 0 && moving < rootCount;
}

void assignRootPairs(const Hierarchy& h, const std::vector<bool>& objectMoves, bool split, LinkSet& fixed,
                     LinkSet& moving, const std::vector<int>& rigidGroup) {
  auto moves = [&](size_t root) { return objectMoves.empty() || objectMoves[root]; };
  // Each node's height (levels below it): the nodes lie level by level, children after parents.
  std::vector<uint32_t> height(h.nodes.size(), 0);
  for (size_t i = h.nodes.size(); i-- > 0;)
    for (uint32_t c = h.nodes[i].firstChild; c < h.nodes[i].firstChild + h.nodes[i].childCount; ++c)
      height[i] = std::max(height[i], height[c] + 1);
  for (size_t a = 0; a < h.roots.size(); ++a)
    for (size_t b = 0; b < h.roots.size(); ++b) {
      const bool together = !rigidGroup.empty() && rigidGroup[a] >= 0 && rigidGroup[a] == rigidGroup[b];
      const bool once = split && ((!moves(a) && !moves(b)) || together);
      LinkSet& set = once ? fixed : moving;
      set.rootPairs.insert(set.rootPairs.end(), {h.roots[a], h.roots[b]});
      set.levels = std::max(set.levels, height[h.roots[a]] + height[h.roots[b]] + 1);
    }
}

uint32_t withMargin(uint32_t needed) {
  return uint32_t(std::min<uint64_t>(uint64_t(needed) * 5 / 4 + 1024, 0xFFFFFFF0u));
}

uint32_t LinkSet::leafLinksHeld() const { return std::min(leafLinkCapacity, readCounters()[gpu::kCounterLeafLinks]); }

LinkCreation::LinkCreation(const vk::Context& ctx)
    : refine_(shaderProgram(ctx, "refine_links")),
      count_(shaderProgram(ctx, "count_links")),
      scan_(shaderProgram(ctx, "scan_counts")),
      scatter_(shaderProgram(ctx, "scatter_links")) {}

void LinkCreation::record(VkCommandBuffer cmd, LinkSet& set, const LinkWork& b, const Hierarchy& h,
                          const LinkCriteria& criteria, uint32_t worklistCapacity) const {
  // The first level's list (the root pairs), counted as the longest so far, and its dispatch size;
  // each level's last workgroup sizes the next (refine_links).
  const uint32_t rootPairs = uint32_t(set.rootPairs.size() / 2);
  std::array<uint32_t, gpu::kCounterWorklistPeak + 1> start{};
  start[gpu::kCounterWorklistA] = start[gpu::kCounterWorklistPeak] = rootPairs;
  const glm::uvec4 firstLevel = gpu::linkGroupsFor(rootPairs);
  vk::fillBuffer(cmd, set.counters, 0u);
  vk::fillBuffer(cmd, set.counts, 0u);
  vk::updateBuffer(cmd, set.counters, 0, sizeof(start), start.data());
  vk::updateBuffer(cmd, b.args, gpu::kLinkArgsLevel * sizeof(glm::uvec4), sizeof(firstLevel), &firstLevel);
  vk::copyRegion(cmd, set.roots, b.worklistA, {0, 0, set.rootPairs.size() * sizeof(uint32_t)});
  for (uint32_t level = 0; level < set.levels; ++level) {
    const uint32_t in = level % 2, out = 1 - in;
    refine_.dispatchIndirect(cmd, b.args, gpu::kLinkArgsLevel * sizeof(glm::uvec4),
                             b.pool.with({{"pairs", in ? b.worklistB : b.worklistA},
                                          {"nextWorklist", in ? b.worklistA : b.worklistB},
                                          {"links", set.links},
                                          {"counters", set.counters},
                                          {"args", b.args},
                                          {"emitters", b.emitters},
                                          {"nodeBuried", b.buried}}),
                             gpu::RefinePush{.source = in,
                                             .target = out,
                                             .capacity = worklistCapacity,
                                             .linkCapacity = set.linkCapacity,
                                             .epsilon = criteria.epsilon,
                                             .largeSender = criteria.largeSender,
                                             .largeReceiver = criteria.largeReceiver,
                                             .bothSides = criteria.bothSides ? 1u : 0u,
                                             .emitterReceiver = criteria.emitterReceiver,
                                             .receiverStaysWhole = criteria.receiverStaysWhole ? 1u : 0u,
                                             .skipBuriedSenders = criteria.skipBuriedSenders ? 1u : 0u});
  }
  // Links sorted by receiver: count, scan, scatter.
  const VkDeviceSize sortArgs = gpu::kLinkArgsSort * sizeof(glm::uvec4);
  const gpu::SortLinksPush sort{.linkCapacity = set.linkCapacity};
  count_.dispatchIndirect(cmd, b.args, sortArgs,
                          {{"links", set.links}, {"counts", set.counts}, {"counters", set.counters}}, sort);
  scan_.dispatch(cmd, {}, {{"counts", set.counts}, {"starts", set.starts}},
                 gpu::CountPush{.count = uint32_t(h.nodes.size())});
  scatter_.dispatchIndirect(cmd, b.args, sortArgs,
                            {{"links", set.links},
                             {"counts", set.counts},
                             {"senders", set.senders},
                             {"counters", set.counters},
                             {"emitters", b.emitters}},
                            sort);
}

}  // namespace ivgi::gi

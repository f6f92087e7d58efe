#include "engine/gi/iv/prune.h"

#include <algorithm>
#include <bit>
#include <string>

#include "engine/core/errors.h"
#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

constexpr uint32_t kMinGroups = 512;     // workgroups a dispatch runs at least, where there are leaves enough
constexpr uint32_t kLeavesPerGroup = 8;  // leaves a workgroup walks in one dispatch, unless the settings say

// A workgroup starts with as few subgroups as lavapipe's loop budget allows. lavapipe runs a
// workgroup's subgroups one after another on one thread, switching at every barrier, so fewer are
// faster; but each subgroup has a budget of 65,535 loop rounds (common.glsl), which the rounds of its
// workgroup's leaves, shared among its subgroups, must stay within. A leaf's rounds grow with N² and
// with its root path, which grows with the scene: (N/16)² subgroups, or one per 16,384 surfels at 16
// bins (a power of two), at most 8. Where one runs out the frame is redone with twice as many.
uint32_t firstSubgroups(uint32_t n, uint32_t surfels) {
  const uint64_t perSurfels = (uint64_t(surfels) * n + 16 * 16384 - 1) / (16 * 16384);
  return std::clamp<uint32_t>(std::max<uint64_t>(n * n / (16 * 16), std::bit_ceil(perSurfels)), 1u, 8u);
}

uint32_t maxGroupSize(const vk::Context& ctx) {
  const VkPhysicalDeviceLimits& limits = ctx.limits();
  return std::min({256u, limits.maxComputeWorkGroupSize[0], limits.maxComputeWorkGroupInvocations});
}

// Whole subgroups of at least 8 invocations (the prune files a wide sender's pieces 8 lanes apiece).
uint32_t groupSizeOf(const vk::Context& ctx, uint32_t subgroups) {
  return std::min(std::max(ctx.subgroupSize(), 8u) * subgroups, maxGroupSize(ctx));
}

}  // namespace

bool Prune::binsFitShared(const vk::Context& ctx, uint32_t n) {
  // bins and coverage; per mask word the mask, grown mask, word start, two half-covered masks and
  // static mask word; partial sums (of the largest workgroup); the chunk of root-path senders and its
  // wide ones; the emitter queue and its sorted copy (prune_bins.comp)
  const uint64_t bytes = uint64_t(6) * n * n * (8 + 4) + uint64_t(gpu::maskWordsFor(n)) * 28 + maxGroupSize(ctx) * 16 +
                         16 + gpu::kPathChunk * 8 + 4 + gpu::kEmitterQueue * 8 + 4;
  return ctx.sharedInt64Atomics() && bytes <= ctx.limits().maxComputeSharedMemorySize;
}

Prune::Prune(const vk::Context& ctx, const IvSettings& settings, uint32_t surfelCount, const IvBuffers& b,
             const LinkSet& staticSet, const LinkSet& frameSet)
    : ctx_(ctx),
      settings_(settings),
      surfelCount_(surfelCount),
      b_(b),
      staticSet_(staticSet),
      frameSet_(frameSet),
      sharedBins_(binsFitShared(ctx, settings.bins)),
      subgroups_(firstSubgroups(settings.bins, surfelCount)) {
  makePrograms();
}

void Prune::makePrograms() {
  const uint32_t n = settings_.bins;
  for (bool pass : {true, false}) {
    const vk::Specialization specialization{.constants = {{"kN", n},
                                                          {"kSharedBins", sharedBins_ ? 1u : 0u},
                                                          {"kSharedSlots", sharedBins_ ? 6 * n * n : 1u},
                                                          {"kMaskWords", gpu::maskWordsFor(n)},
                                                          {"kStaticPass", pass ? 1u : 0u},
                                                          {"texelViews", texelViews_}},
                                            .localSizeX = groupSize()};
    (pass ? static_ : frame_).emplace(ctx_, "prune_bins", shaderCode("prune_bins"), specialization);
  }
}

uint32_t Prune::groupSize() const { return groupSizeOf(ctx_, subgroups_); }

uint32_t Prune::leavesPerGroup() const { return settings_.pruneLeaves > 0 ? settings_.pruneLeaves : kLeavesPerGroup; }

uint32_t Prune::groups() const {
  const uint32_t leaves = leavesPerGroup();
  uint32_t groups = std::min(std::max(surfelCount_, 1u), std::max(kMinGroups, (surfelCount_ + leaves - 1) / leaves));
  if (!sharedBins_) {  // every workgroup owns a slot of 6·N² bins in one buffer within the device's range
    const uint64_t slotBytes = uint64_t(6) * settings_.bins * settings_.bins * 8;  // the larger of the two slot arrays
    const uint64_t room = std::min<uint64_t>(ctx_.limits().maxStorageBufferRange, 512ull << 20);
    groups = std::min<uint32_t>(groups, uint32_t(std::max<uint64_t>(1, room / slotBytes)));
  }
  return settings_.pruneGroups > 0 ? std::min(groups, settings_.pruneGroups) : groups;
}

uint32_t Prune::batch() const { return groups() * leavesPerGroup(); }

uint32_t Prune::batches() const { return (surfelCount_ + batch() - 1) / batch(); }

void Prune::allocateBins(IvBuffers& b, vk::Allocations& allocations) const {
  const uint64_t slots = sharedBins_ ? 0 : uint64_t(groups()) * 6 * settings_.bins * settings_.bins;
  b.globalBins = vk::Buffer(ctx_, slots * 8, vk::Memory::Device, &allocations);
  b.globalCoverage = vk::Buffer(ctx_, slots * 4, vk::Memory::Device, &allocations);
}

void Prune::clearBins(VkCommandBuffer cmd) const {
  vk::fillBuffer(cmd, b_.globalBins, 0xFFFFFFFFu);
  vk::fillBuffer(cmd, b_.globalCoverage, 0u);
}

void Prune::clearIfDirty(VkCommandBuffer cmd) {
  if (!binsDirty_) return;
  clearBins(cmd);
  binsDirty_ = false;
}

vk::Bindings Prune::bindings(const LinkSet& set) const {
  return b_.pool().with({{"starts", set.starts},
                         {"senders", set.senders},
                         {"counters", set.counters},
                         {"staticCounters", staticSet_.counters}});
}

gpu::PrunePush Prune::push(const LinkSet& set, uint32_t first, uint32_t end, bool listed) const {
  return {.firstSurfel = first,
          .endSurfel = end,
          .listed = listed ? 1u : 0u,
          .linkCapacity = set.leafLinkCapacity,
          .lightCount = b_.scene.lightCount,
          .environmentOn = b_.scene.environmentOn ? 1u : 0u,
          .staticCapacity = staticSet_.leafLinkCapacity,
          .emittersByMaps = b_.scene.emittersByMaps() ? 1u : 0u,
          .poseBase = b_.scene.nodeCount,
          .rigidWhenListed = rigidWhenListed_ ? 1u : 0u};
}

void Prune::recordStatic(VkCommandBuffer cmd, const vk::Buffer& nodes) {
  clearIfDirty(cmd);
  recordPass(cmd, *static_, staticSet_, vk::Bindings::pool({{"nodes", nodes}}).plus(bindings(staticSet_)));
}

void Prune::recordFrame(VkCommandBuffer cmd) {
  clearIfDirty(cmd);
  recordPass(cmd, *frame_, frameSet_, bindings(frameSet_));
}

// Batches of at most leavesPerGroup() leaves a workgroup: one batch where the bins are shared
// memory, several where each workgroup's global-memory slot limits how many there can be.
void Prune::recordPass(VkCommandBuffer cmd, const vk::Program& pass, const LinkSet& set,
                       const vk::Bindings& bound) const {
  const uint32_t groupCount = groups(), leaves = batch();
  for (uint32_t first = 0; first < surfelCount_; first += leaves)
    pass.dispatch(cmd, pass.groupsFor(groupCount, 1), bound,
                  push(set, first, std::min(surfelCount_, first + leaves), false));
}

void Prune::recordReceivers(VkCommandBuffer cmd) { recordListed(cmd, *frame_, frameSet_, bindings(frameSet_)); }

void Prune::recordStaticReceivers(VkCommandBuffer cmd, const vk::Buffer& nodes) {
  recordListed(cmd, *static_, staticSet_, vk::Bindings::pool({{"nodes", nodes}}).plus(bindings(staticSet_)));
}

void Prune::recordListed(VkCommandBuffer cmd, const vk::Program& pass, const LinkSet& set, const vk::Bindings& bound) {
  clearIfDirty(cmd);
  const uint32_t leaves = batch();
  for (uint32_t k = 0; k < batches(); ++k)
    pass.dispatchIndirect(cmd, b_.receiverArgs, (gpu::kArgsPruneBatches + k) * sizeof(glm::uvec4), bound,
                          push(set, k * leaves, (k + 1) * leaves, true));
}

void Prune::onLoopBudgetSpent() {
  if (groupSize() == maxGroupSize(ctx_))
    throw SettingsError("iv: pruning a leaf takes more loop rounds than this device allows a workgroup of " +
                        std::to_string(maxGroupSize(ctx_)) +
                        " invocations (lavapipe: 65,535 a subgroup); use fewer --bins or a larger --eps");
  subgroups_ *= 2;
  makePrograms();
  binsDirty_ = !sharedBins_;  // the leaves cut short may have left their bins
}

void Prune::readTexelViews(uint32_t views) {
  if (views == texelViews_) return;
  texelViews_ = views;
  makePrograms();
}

}  // namespace ivgi::gi

#pragma once
// Bin pruning and push-down (shaders/iv/prune_bins.comp): each leaf re-bins the links of itself
// and its ancestors from its own position and keeps the nearest sender per direction bin. Objects
// that cannot move are pruned once (the static pass); every frame prunes what the frame's links
// reach. This record sizes the prune's workgroups and dispatches, and owns its bins when they do not
// fit in shared memory.
#include <optional>

#include "engine/gi/iv/buffers.h"
#include "engine/gi/iv/settings.h"
#include "engine/gi/links.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

class Prune {
 public:
  // Records into the buffers `b` of the solver, for the links of its two sets.
  Prune(const vk::Context& ctx, const IvSettings& settings, uint32_t surfelCount, const IvBuffers& b,
        const LinkSet& staticSet, const LinkSet& frameSet);
  // Whether 6·N² bins fit the device's shared memory (else the global-memory path runs).
  static bool binsFitShared(const vk::Context& ctx, uint32_t n);

  bool sharedBins() const { return sharedBins_; }
  uint32_t groupSize() const;  // invocations a workgroup has
  uint32_t batches() const;    // dispatches one prune takes
  // The bins of the global-memory path, a slot of 6·N² per workgroup (a stand-in on the shared path).
  void allocateBins(IvBuffers& b, vk::Allocations& allocations) const;
  // Empty bins in every global-memory slot. Each leaf empties the bins it touched; a prune cut short
  // (lavapipe's loop budget) may not have, so a redo starts from this.
  void clearBins(VkCommandBuffer cmd) const;

  // Records the static pass: the static leaves (and those of objects that move rigidly) against the
  // static set's links, made on `nodes` (the rigid objects' at rest).
  void recordStatic(VkCommandBuffer cmd, const vk::Buffer& nodes);
  // Records the frame's prune of every leaf against the frame set's links (static leaves merge with
  // what the static pass kept).
  void recordFrame(VkCommandBuffer cmd);
  // Where `later`, the static pass leaves the rigid leaves unpruned, and recordStaticReceivers()
  // prunes each against the static set's links the first time it is a receiver.
  void pruneRigidWhenListed(bool later) { rigidWhenListed_ = later; }
  bool rigidWhenListed() const { return rigidWhenListed_; }
  // Records the static pass of the rigid leaves still unpruned among the receivers a refinement
  // round listed (pruneRigidWhenListed), before their frame prune merges with it.
  void recordStaticReceivers(VkCommandBuffer cmd, const vk::Buffer& nodes);
  // Records the frame's prune of the receivers a refinement round listed, one batch after another
  // with the dispatch sizes receiver_args.glsl wrote from how many there are.
  void recordReceivers(VkCommandBuffer cmd);
  // How the prune of listed receivers is batched: what receiver_args.glsl sizes it by.
  struct Batching {
    uint32_t batch, leavesPerGroup, maxGroups, batches;
  };
  Batching batching() const { return {batch(), leavesPerGroup(), groups(), batches()}; }
  // A workgroup ran out of lavapipe's loop budget: twice the subgroups share it from the next frame.
  // Throws SettingsError where the workgroup cannot grow.
  void onLoopBudgetSpent();
  // The leaf links are bound in `views` texel views (shaders/common/parted_texels.glsl): 1 or kTexelParts.
  void readTexelViews(uint32_t views);

 private:
  void makePrograms();
  void recordPass(VkCommandBuffer cmd, const vk::Program& pass, const LinkSet& set, const vk::Bindings& bound) const;
  void recordListed(VkCommandBuffer cmd, const vk::Program& pass, const LinkSet& set, const vk::Bindings& bound);
  // The buffers a prune of `set`'s links binds, and its push constants for the leaves [first, end).
  vk::Bindings bindings(const LinkSet& set) const;
  gpu::PrunePush push(const LinkSet& set, uint32_t first, uint32_t end, bool listed) const;
  void clearIfDirty(VkCommandBuffer cmd);
  uint32_t groups() const;  // workgroups a dispatch runs
  uint32_t leavesPerGroup() const;
  uint32_t batch() const;  // leaves one dispatch walks

  const vk::Context& ctx_;
  const IvSettings& settings_;
  uint32_t surfelCount_;
  const IvBuffers& b_;
  const LinkSet &staticSet_, &frameSet_;
  bool sharedBins_;
  uint32_t subgroups_;      // subgroups a workgroup has
  bool binsDirty_ = false;  // a prune was cut short: the global-memory bins may hold its leaves' keys
  bool rigidWhenListed_ = false;
  uint32_t texelViews_ = 1;
  std::optional<vk::Program> static_, frame_;
};

}  // namespace ivgi::gi

#pragma once
// Receivers (docs/design.md §2.4): irradiance is solved at a subset of the surfels, chosen each
// frame where the lighting needs them, and interpolated to every other surfel. The refinement
// starts from the roots and goes down the trees a level a round: the representatives of the
// candidate nodes' children become receivers (select_receivers), are pruned and their direct
// irradiance estimated; each child gets a need from how near its surroundings are against its size
// and how far its sample misses its prediction from the samples around it (refine_receivers), and
// where that passes kRefineFrom, the child is the next round's candidate. Then the sampled nodes'
// roles (receiver_roles), how far their supports reach (receiver_reach), per group of surfels the
// nodes that may weigh for it (neighbour_lists) and each surfel's interpolation
// (interpolation_weights); a surfel that no receiver's support holds becomes one. With
// --receiver-tol 0 every surfel is a receiver taking its own irradiance.
#include "engine/gi/hierarchy.h"
#include "engine/gi/iv/buffers.h"
#include "engine/gi/iv/prune.h"
#include "engine/gi/iv/settings.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

class Receivers {
 public:
  // Allocates the receivers' buffers into `b` and records into them; with every surfel a receiver,
  // fills them for good.
  Receivers(const vk::Context& ctx, const Hierarchy& h, const IvSettings& settings, IvBuffers& b,
            vk::Allocations& allocations);
  bool everySurfel() const { return *settings_.receiverTolerance <= 0.0f; }
  // Rounds a refinement takes at most: one per level with children.
  uint32_t rounds() const { return levels_ > 1 ? levels_ - 1 : 1; }

  // No receivers yet; the roots are the first round's candidates (their dispatch size set).
  void recordStart(VkCommandBuffer cmd) const;
  // A round's first step: its candidates' children's representatives become receivers, and the
  // dispatch sizes for pruning (in `batching`'s batches) and estimating them are set.
  void recordSelect(VkCommandBuffer cmd, uint32_t round, const Prune::Batching& batching) const;
  // A round's last step, after the new receivers' estimates: which children are cells and which
  // the next round's candidates (their dispatch size set, and the next round's over no receivers).
  void recordRefine(VkCommandBuffer cmd, uint32_t round, const Prune::Batching& batching) const;
  // Each surfel's interpolation; surfels no receiver reaches are listed as the next receivers to
  // prune (their dispatch sizes set).
  void recordWeights(VkCommandBuffer cmd, const Prune::Batching& batching) const;
  // Whether the refinement judges the surfaces the image does not show at --unseen-tol, and the
  // renderer's marks of what it shows (gpu's kShown bits), which recordStart() then reads.
  bool guidedByView() const { return !everySurfel() && settings_.viewGuided && settings_.unseenTolerance > 1.0f; }
  void useView(const vk::Buffer& shown, const vk::Buffer& camera) { shown_ = &shown, camera_ = &camera; }

  struct Counts {
    uint32_t receivers, fills;
  };
  Counts counts() const;

 private:
  struct Lists {  // the counter slots of the candidate list a step reads and of the one it writes
    uint32_t in, out;
  };
  static Lists listsOf(uint32_t round);
  const vk::Buffer& listBuffer(uint32_t slot) const;
  void recordArgs(VkCommandBuffer cmd, uint32_t mode, Lists lists, const Prune::Batching& batching) const;
  gpu::ReceiverPush push(Lists lists, const Prune::Batching& batching = {}) const;
  // Guided by the view, and given the marks of what the image shows (without them every node is
  // judged alike).
  bool followsView() const { return guidedByView() && shown_ != nullptr; }
  void makeEverySurfelReceiver(const vk::Context& ctx, IvBuffers& b) const;

  const IvSettings& settings_;
  const IvBuffers& b_;
  uint32_t surfelCount_, nodeCount_, levels_, groupCount_, rootCount_;
  float largestCell_;
  vk::Program args_, select_, refine_, roles_, reach_, neighbours_, weights_, seen_;
  vk::Buffer roots_;  // the first round's candidates, rootCount_ of them (the buffer may hold more room)
  const vk::Buffer* shown_ = nullptr;
  const vk::Buffer* camera_ = nullptr;
};

}  // namespace ivgi::gi

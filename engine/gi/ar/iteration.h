#pragma once
// One ar iteration as its passes (docs/design.md §2.2): the local pass (K and J at every surfel,
// its intensity per bin), the intensities pulled up the trees, the global pass (U over the links
// into each node's gathered table), the inner nodes' gathered tables summed down the trees, and
// each surfel's incident light and irradiance.
#include "engine/gi/ar/buffers.h"
#include "engine/gi/ar/settings.h"
#include "engine/gi/hierarchy.h"
#include "engine/gi/links.h"
#include "engine/vk/program.h"
#include "engine/vk/timer.h"

namespace ivgi::gi {

class ArIteration {
 public:
  // The passes at the settings' `dirs` (a constant of their programs); the pull-up takes `h`'s inner
  // nodes.
  ArIteration(const vk::Context& ctx, const Hierarchy& h, const ArSettings& settings, vk::Allocations& allocations);
  // Records one iteration; `radianceStep`: the local pass reflects the incident light (else it keeps
  // the radiance: an antiradiance step); `slot`: where its incident pass leaves its sums. The global
  // pass walks each receiver's links of both sets, the static pairs' first, in push.chunks
  // dispatches (push.chunkLinks links of a list each). Each pass is timed where `timed`.
  void record(VkCommandBuffer cmd, vk::PassTimer& timer, bool timed, const ArBuffers& b, const Hierarchy& h,
              const LinkSet& staticLinks, const LinkSet& frameLinks, gpu::ArPush push, bool radianceStep,
              uint32_t slot) const;
  // Workgroups of the incident pass, each leaving one gpu::IterationSum an iteration.
  uint32_t sumGroups(uint32_t surfelCount) const;

 private:
  vk::Program local_, pullUp_, gather_, sumDown_, incident_;
  // The inner nodes level by level, and per level holding any (deepest first) its range of them:
  // the pull-up's dispatches, and in reverse the sum-down's.
  vk::Buffer innerNodes_;
  std::vector<gpu::LevelPush> innerLevels_;
};

}  // namespace ivgi::gi

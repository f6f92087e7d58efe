#pragma once
// One ar iteration as its passes (docs/design.md §2.2): the local pass (K and J at every surfel,
// its intensity per bin), the intensities pulled up the trees, the global pass (U over the links
// into each node's gathered table), the inner nodes' gathered tables summed down the trees, and
// each surfel's incident light and irradiance.
#include "engine/gi/ar/buffers.h"
#include "engine/gi/ar/settings.h"
#include "engine/gi/hierarchy.h"
#include "engine/gi/links.h"
#include "engine/gi/pass.h"
#include "engine/scene/geometry.h"
#include "engine/vk/program.h"
#include "engine/vk/timer.h"

namespace ivgi::gi {

// What changes between the iterations a solver records.
struct ArStep {
  bool radianceStep;  // the local pass reflects the incident light (else it keeps the radiance)
  uint32_t sumSlot;   // where the incident pass leaves its sums
  // The global pass walks each receiver's links in `chunks` dispatches of `chunkLinks` links each.
  uint32_t chunks, chunkLinks;
  float damping;  // the share of the step taken (ArIncidentPush::damping)
  bool timed;     // each pass timed on its own (else the caller times the iterations together)
};

class ArIteration {
 public:
  // The passes at the settings' `dirs` (a constant of their programs), recording into the solver's
  // buffers `b` over the links of its two sets (the static pairs' first); the pull-up takes `h`'s
  // inner nodes. Where some of `g`'s lobes (bases) send their light far from evenly, the glossy
  // leaves send them by direction. Its back surfels (scene::Geometry::backSurfels) let no light
  // through.
  ArIteration(const vk::Context& ctx, const Hierarchy& h, const ArSettings& settings, const ArBuffers& b,
              const LinkSet& staticLinks, const LinkSet& frameLinks, const scene::Geometry& g,
              vk::Allocations& allocations);
  void record(VkCommandBuffer cmd, vk::PassTimer& timer, const ArStep& step) const;
  // Workgroups of the incident pass, each leaving one gpu::IterationSum an iteration.
  uint32_t sumGroups() const;

 private:
  const ArBuffers& b_;
  const LinkSet &staticLinks_, &frameLinks_;
  const uint32_t surfelCount_, firstBackSurfel_, nodeCount_, bins_;
  vk::Program local_, pullUp_, gather_, sumDown_, incident_;
  // The inner nodes level by level, and per level holding any (deepest first) its range of them:
  // the pull-up's dispatches, and in reverse the sum-down's.
  vk::Buffer innerNodes_;
  std::vector<NodeRange> innerLevels_;
};

}  // namespace ivgi::gi

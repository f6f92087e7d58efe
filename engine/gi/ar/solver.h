#pragma once
// The ar solver (Dachsbacher et al. 2007; docs/design.md §2.2): unoccluded hierarchical transport
// of radiance less antiradiance, whose go-through operator J cancels, behind every surface, the
// light that U carries past it, so that no pass ever decides visibility. Per frame, as passes:
// refit and link creation (both sides of every node, split while either side spans more than κ
// bins from the other) where the geometry moved, then iterations of the local pass, the pull-up,
// the global pass and the incident light, until the irradiance settles (or a given count), with
// divergence watched.
#include <vector>

#include "engine/gi/ar/buffers.h"
#include "engine/gi/ar/iteration.h"
#include "engine/gi/ar/settings.h"
#include "engine/gi/hierarchy.h"
#include "engine/gi/links.h"
#include "engine/gi/refit.h"
#include "engine/gi/solver.h"
#include "engine/scene/geometry.h"

namespace ivgi::gi {

class ArSolver final : public Solver {
 public:
  // Validates the settings (SettingsError) and allocates, refusing in one line what does not fit.
  // `objectMoves`, per hierarchy root: whether its object can move (movingRoots); empty: any may,
  // and every pair is relinked whenever the geometry moved.
  ArSolver(const vk::Context& ctx, const scene::Geometry& geometry, Hierarchy hierarchy, const ArSettings& settings,
           const std::vector<bool>& objectMoves = {});

  int chainStart(int frame) const override;
  void beginFrame(int frame) override;
  void setLights(const std::vector<gpu::PunctualLight>& lights) override;
  // The emitters' light then comes inside each surfel's irradiance; the surfels send only what they
  // reflect.
  bool useDirectLight(const vk::Buffer& surfelDirect, const vk::Buffer& surfelArrival, bool withEnvironment) override;
  void record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Buffer& surfels, bool geometryMoved) override;
  bool frameMustBeRedone() override;
  bool wantsMorePasses() const override;
  void recordMorePasses(VkCommandBuffer cmd, vk::PassTimer& timer) override;
  void frameStands() override;
  std::vector<std::pair<std::string, double>> frameFigures() const override;
  bool reflectsLobes() const override { return b_.scene.glossy; }
  void recordReflections(VkCommandBuffer cmd, vk::PassTimer& timer, glm::vec4 eye, const vk::Buffer& shown,
                         const vk::Buffer& lobes) override;
  const vk::Buffer& irradiance() const override { return b_.irradiance; }
  const vk::Buffer& surfelBuried() const override { return b_.scene.surfelBuried; }
  uint64_t allocatedBytes() const override { return allocations_.bytes(); }

  ArStats stats() const;
  // Readback for tests: per surfel, the irradiance of the last iteration.
  std::vector<glm::vec4> surfelIrradiance() const { return b_.irradiance.read<glm::vec4>(surfelCount_); }
  const Hierarchy& hierarchy() const { return hierarchy_; }
  // Readback for tests: per node its refit state, and the table of what it sends (6·N² bins a node)
  // and exitance that the last iteration's local pass and pull-up left.
  std::vector<gpu::NodeState> nodeStates() const { return b_.scene.nodes.read<gpu::NodeState>(nodeCount_); }
  std::vector<glm::vec4> intensities() const {
    return b_.intensity.read<glm::vec4>(size_t(nodeCount_) * 6 * settings_.dirs * settings_.dirs);
  }
  std::vector<glm::vec4> exitances() const { return b_.exitance.read<glm::vec4>(nodeCount_); }
  // Readback for tests: each receiver node's senders in the order the global pass walks them, of
  // the links made once between static objects or of the frame's.
  std::vector<std::vector<uint32_t>> senderLists(bool staticLinks) const;
  // The bytes of the directional tables for a scene of these counts (each node: gathered and
  // intensity; each surfel: incident, and where frames chain, the start of the frame's iteration),
  // before anything is allocated (ivgi info).
  static uint64_t tableBytes(uint64_t nodes, uint64_t surfels, uint32_t dirs, bool chained);

 private:
  // The link arrays at their capacities: in device memory while it holds them, else in host memory.
  void allocateLinks();
  uint64_t deviceBudget() const;  // --max-memory, else the device's heap
  bool mustRedo();                // frameMustBeRedone's decision (it counts and remembers it)
  void recordLinks(VkCommandBuffer cmd, LinkSet& set);
  void recordIterations(VkCommandBuffer cmd, vk::PassTimer& timer, uint32_t steps);
  // The start of the frame's iteration: from the emission, or from the frame before's solution.
  void recordStart(VkCommandBuffer cmd, vk::PassTimer& timer);
  // How many iterations the next submission records.
  uint32_t nextSteps() const;
  uint32_t longestList() const;  // the most links a receiver node has, of both sets
  uint32_t chunkLinks() const { return settings_.gatherChunkLinks ? settings_.gatherChunkLinks : gpu::kArGatherChunk; }
  // Reads the sums of the iterations recorded since the last look and decides whether to go on
  // (wantsMorePasses() asks, so what it decides is mutable).
  void judge() const;
  uint32_t iterationLimit() const;

  const vk::Context& ctx_;
  const Hierarchy hierarchy_;
  const ArSettings settings_;
  const uint32_t surfelCount_, nodeCount_;
  vk::Allocations allocations_;  // before the buffers, which count themselves into it
  ArBuffers b_;
  // The links of the pairs of two static objects (made once, when some other object moves) and of
  // the rest (made whenever the geometry moved).
  LinkSet staticSet_, frameSet_;
  uint32_t worklistCapacity_ = 0;
  Refit refit_;
  LinkCreation linkCreation_;
  ArIteration iteration_;
  vk::Program sortSenders_, sortLongSenders_, queueArgs_, orderReceivers_, reflect_;
  uint32_t sumGroups_ = 0;
  // Dispatches of the global pass an iteration, each walking chunkLinks() links of a list; more
  // where a frame found a longer list (it is redone).
  uint32_t gatherChunks_ = 1;
  bool linked_ = false, staticLinked_ = false;
  bool saidHostMemory_ = false;  // the note that tables or links are in host memory, once
  // The frame being solved (beginFrame), the frame whose solution that stood (not diverged, not to
  // be redone) the tables hold (negative: none), and whether this frame starts from it; a frame
  // redone starts again from what it started from, kept in `b_.start*`.
  int frame_ = -1, solved_ = -1;
  bool warm_ = false, redoing_ = false;
  // A frame stood since the links were made (diverged or not), and nothing moved since: this
  // frame shows that frame's solution (record() recorded nothing).
  bool standing_ = false, reused_ = false;
  bool shownWarm_ = false;  // whether the solution shown started from the frame before it
  // The frame's iterations: recorded, judged (their sums read), and whether they are done.
  uint32_t recorded_ = 0;
  mutable uint32_t judged_ = 0;
  mutable bool done_ = false;
  mutable std::vector<float> residuals_, negatives_;
  // Where the iteration diverges, the frame is redone with each step damped to half the step before
  // (down to ArSettings::leastDamping); where it still diverges, once more up to its best iteration
  // (cap_).
  // Every frame starts undamped, so that an image never depends on the frames before it.
  mutable float damping_ = 1.0f;
  float frameDamping_ = 1.0f;  // the damping the last frame that stood was solved with
  mutable uint32_t cap_ = 0;
  mutable bool diverged_ = false, redo_ = false;
  // Why the frame's plain iteration diverges, named in its one line on stderr (divergence()).
  mutable std::string firstDivergence_;
  uint32_t framesRedone_ = 0;
};

}  // namespace ivgi::gi

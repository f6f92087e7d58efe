#pragma once
// The iv solver (design.md §1.2, §2 passes 3–6): refit, link creation, bin pruning and push-down,
// bounces. Every step is a compute pass; the host only sizes buffers, from a first guess and then
// from the counts the GPU reports: it grows them when a frame overflowed, shrinks what stays unused.
#include <glm/glm.hpp>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "engine/gi/hierarchy.h"
#include "engine/gi/shared.h"
#include "engine/scene/animation.h"
#include "engine/scene/geometry.h"
#include "engine/vk/buffer.h"
#include "engine/vk/program.h"
#include "engine/vk/timer.h"

namespace ivgi::gi {

struct IvSettings {
  uint32_t bins = 16;        // N: 6×N×N direction bins
  float epsilon = 0.02f;     // refine while the form-factor estimate is above it
  uint32_t bounces = 2;      // indirect bounces; 0 = direct light only
  float kappa = 1.0f;        // refine while a sender covers more than κ average bins
  std::vector<glm::vec4> environment;  // radiance per bin (6·N² entries); empty: no environment
  // The most workgroups one prune dispatch runs; 0: as many as the scene and the device allow. Fewer
  // prune in more dispatches (batches) with the same result; tests batch small scenes with it.
  uint32_t pruneGroups = 0;
  // Leaves a prune workgroup walks in one dispatch; 0: 8. Tests run many to spend lavapipe's loop
  // budget (common.glsl), which the solver must notice and redo.
  uint32_t pruneLeaves = 0;
};

// The scene's punctual lights in world space at `pose`.
std::vector<GpuLight> worldLights(const scene::Scene& scene, const scene::Pose& pose);

struct IvStats {
  uint32_t nodes = 0, levels = 0, links = 0, leafLinks = 0;
  uint32_t staticLinks = 0, staticLeafLinks = 0;  // of those, made once between objects that cannot move
  uint64_t bytes = 0;
  bool sharedBins = true;
  uint32_t pruneBatches = 0;  // dispatches a prune takes (each of at most a few leaves a workgroup)
  uint32_t pruneGroupSize = 0;  // invocations a prune workgroup has (more when one ran out of loop rounds)
  // The prune's work: root-path senders its leaves walked, in the last relinked frame and in the
  // static pass (once; the frame then walks only the senders of the pairs with a moving side).
  uint64_t sendersWalked = 0, staticSendersWalked = 0;
  // Since the solver was made: frames redone because their links outgrew the room they had or a
  // prune workgroup its loop budget (the timings are the redone frame's), and static passes run (1
  // once the static links are whole).
  uint32_t framesRedone = 0, staticPasses = 0;
};

// What the iv solver of a frame is made from: the hierarchy over the rest-pose surfels, the user's
// settings, and which objects can move.
struct IvSetup {
  Hierarchy hierarchy;
  IvSettings settings;
  // Per hierarchy root: whether its object can move (scene::movingInstances). Empty: every object
  // may move, and everything is linked and pruned whenever the geometry moved.
  std::vector<bool> objectMoves;
};
// The setup for `scene`; `animation` says which objects can move (-1 none: all static; absent: any).
IvSetup makeIvSetup(const scene::Scene& scene, const scene::Geometry& geometry, const IvSettings& settings,
                    std::optional<int> animation = std::nullopt);
// Sets setup.objectMoves from what `animation` moves.
void markMovingObjects(IvSetup& setup, const scene::Scene& scene, const scene::Geometry& geometry, int animation);

class IvSolver {
 public:
  // Keeps a reference to `setup`.
  IvSolver(const vk::Context& ctx, const scene::Geometry& geometry, const IvSetup& setup);

  void setLights(const std::vector<GpuLight>& lights);
  // Records the solver's passes. `relink`: geometry moved (or first frame), so refit, link creation
  // and pruning run; otherwise only the bounces.
  void record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Buffer& surfels, bool relink);
  // After the frame completed: grows what overflowed and returns true when the frame must be redone.
  bool growIfOverflowed();
  // After a frame that needed no redo: gives back the leaf-link room it left unused (the first
  // frame's guess, or a frame that needed far fewer), keeping the links it holds, and frees the
  // static pairs' links once their survivors are made.
  void releaseUnusedLinks();

  const vk::Buffer& irradiance() const { return irradiance_; }
  IvStats stats() const;
  const Hierarchy& hierarchy() const { return hierarchy_; }
  std::vector<glm::vec4> leafRadiosity() const;  // per surfel, after the last bounce
  struct LeafLink {
    uint32_t sender;
    float formFactor;
  };
  // Per surfel: its surviving links (a static leaf: the frame's, then its static ones not overridden).
  std::vector<std::vector<LeafLink>> leafLinks() const;
  struct NodeState {  // std430 `NodeState` in common.glsl, as the last refit left it
    glm::vec4 positionArea, normalCone, shape;
  };
  std::vector<NodeState> nodeStates() const;

  // Bins and form factors of the solver's bin table (unit centre direction, solid angle).
  static std::vector<glm::vec4> binTable(uint32_t n);
  // Whether 6·N² bins fit the device's shared memory (else the global-memory path runs).
  static bool binsFitShared(const vk::Context& ctx, uint32_t n);

 private:
  // Links made from a list of root pairs and sorted by receiver, with the counters of their making.
  // The solver has one set for the pairs of static objects (made once) and one for the pairs with a
  // moving side (made whenever the geometry moved).
  struct LinkSet {
    std::vector<uint32_t> rootPairs;  // receiver root, sender root
    vk::Buffer roots, counters, links, counts, starts, senders;
    uint32_t linkCapacity = 0, leafLinkCapacity = 0;
  };
  // An array that grows with the link counts, and how it is bound (limits: a storage buffer
  // maxStorageBufferRange; texels, read as imageBuffers, maxTexelBufferElements).
  struct LinkArray {
    vk::Buffer* buffer;
    uint64_t count, elementBytes;
    bool texels;
    const char* what;
    const LinkSet* leafLinksOf;  // the set whose surviving links it holds (kept when it shrinks), or null
    uint64_t elements() const { return std::max<uint64_t>(count, 1); }
    uint64_t bytes() const { return elements() * elementBytes; }
  };
  std::vector<LinkArray> linkArrays();  // at the capacities the link sets hold now
  // Why those arrays cannot be allocated on this device (empty: they can).
  std::string linkArraysRefusal(const std::vector<LinkArray>& arrays) const;
  void allocateLinks();  // the arrays that grow with the link counts, after checking the device's limits
  uint32_t firstLeafLinkGuess(const LinkSet& set, const std::vector<uint32_t>& leafMoves) const;
  uint32_t leafLinksHeld(const LinkSet& set) const;  // the surviving links the last prune wrote (those that fit)
  uint64_t allocatedBytes() const;
  void recordLinks(VkCommandBuffer cmd, LinkSet& set);
  void recordPrune(VkCommandBuffer cmd, const vk::Program& pass, LinkSet& set);
  void clearGlobalBins(VkCommandBuffer cmd);
  void makePrunePasses();  // the static and the frame prune, with pruneSubgroups_ subgroups a workgroup
  uint32_t refineIterations() const;  // refinement levels: each splits one side of every pair
  uint32_t pruneGroups() const;
  uint32_t leavesPerGroup() const;
  uint32_t pruneBatch() const;  // leaves one prune dispatch walks
  uint32_t maskWords() const;
  bool splitsStatic() const { return !staticSet_.rootPairs.empty(); }

  const vk::Context& ctx_;
  const Hierarchy& hierarchy_;
  IvSettings settings_;
  uint32_t surfelCount_, nodeCount_;
  uint32_t worklistCapacity_;
  bool sharedBins_;
  bool linked_ = false, staticLinked_ = false;
  uint32_t framesRedone_ = 0, staticPasses_ = 0;
  uint32_t pruneSubgroups_;  // subgroups a prune workgroup has (doubled when one ran out of loop rounds)
  bool globalBinsDirty_ = false;  // a prune was cut short: the global-memory bins may hold its leaves' keys
  LinkSet staticSet_, frameSet_;

  vk::Buffer tree_, leafOfSurfel_, leafMoves_, albedo_, emission_, binTable_, environment_, lights_;
  vk::Buffer nodes_, args_, worklistA_, worklistB_;
  vk::Buffer globalBins_, globalCoverage_, ranges_, leafLinks_, overrides_, external_, radiosityA_, radiosityB_, irradiance_;
  vk::Buffer staticRanges_, staticLinks_, staticBins_, staticDepths_, staticMasks_, staticEnvironment_;
  vk::Buffer staticEmitters_, staticEmitterCounts_, staticCorrection_;
  uint32_t lightCount_ = 0;
  uint32_t finalRadiosity_ = 0;  // 0: A, 1: B

  vk::Program refit_, linkArgs_, refine_, countLinks_, scanCounts_, scatterLinks_, emit_, gather_, pullUp_;
  std::optional<vk::Program> pruneStatic_, pruneFrame_;
};

}  // namespace ivgi::gi

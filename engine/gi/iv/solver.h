#pragma once
// The iv solver (Dong et al. 2007; docs/design.md §2.1): hierarchical radiosity whose visibility is the
// nearest link per direction bin. Per frame, as passes: refit, link creation, the receivers chosen
// where the lighting needs them (each pruned: bin pruning and push-down), bounces. Objects that
// cannot move are linked and pruned once. The host only sizes buffers (LinkRoom), from a guess and
// then from the counts the GPU reports.
#include <glm/glm.hpp>

#include <optional>
#include <vector>

#include "engine/gi/hierarchy.h"
#include "engine/gi/iv/bounces.h"
#include "engine/gi/iv/buffers.h"
#include "engine/gi/iv/link_room.h"
#include "engine/gi/iv/prune.h"
#include "engine/gi/iv/receivers.h"
#include "engine/gi/iv/settings.h"
#include "engine/gi/links.h"
#include "engine/gi/refit.h"
#include "engine/gi/solver.h"
#include "engine/scene/animation.h"
#include "engine/scene/geometry.h"

namespace ivgi::gi {

// What the iv solver of a scene is made from: the hierarchy over the rest-pose surfels, the user's
// settings, and which objects can move.
struct IvSetup {
  Hierarchy hierarchy;
  IvSettings settings;
  // Per hierarchy root: whether its object can move (scene::movingInstances). Empty: every object
  // may move, and everything is linked and pruned whenever the geometry moved.
  std::vector<bool> objectMoves;
  // Per root: whether its object moves rigidly (scene::rigidlyMovingInstances); empty: none does.
  std::vector<bool> objectRigid;
  // The scene's rest pose: a rigid object's links to itself are made and pruned on its surfels
  // there, the same wherever a run starts, and its pose is its motion back to there.
  scene::FrameInputs restPose;
};
// The setup for `scene`; `animation` says which objects can move (-1 none: all static; absent: any).
IvSetup makeIvSetup(const scene::Scene& scene, const scene::Geometry& geometry, const IvSettings& settings,
                    std::optional<int> animation = std::nullopt);
// Sets setup.objectMoves from what `animation` moves.
void markMovingObjects(IvSetup& setup, const scene::Scene& scene, const scene::Geometry& geometry, int animation);

class IvSolver final : public Solver {
 public:
  // Validates the settings (SettingsError) and allocates from a first guess at the link counts.
  IvSolver(const vk::Context& ctx, const scene::Geometry& geometry, IvSetup setup);

  void setLights(const std::vector<gpu::PunctualLight>& lights) override;
  void setObjectMatrices(const std::vector<glm::mat4>& matrices) override;
  bool useDirectLight(const vk::Buffer& surfelDirect, const vk::Buffer& surfelArrival, bool withEnvironment) override {
    b_.scene.takeDirectLight(surfelDirect, surfelArrival, withEnvironment);
    return true;
  }
  void record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Buffer& surfels, bool geometryMoved) override;
  bool guidedByView() const override { return receivers_.guidedByView(); }
  bool solvesFrame(bool geometryMoved) const override { return geometryMoved || !linked_; }
  void useView(const vk::Buffer& shown, const vk::Buffer& camera) override { receivers_.useView(shown, camera); }
  bool solvePending() const override { return solvePending_; }
  // Grows what overflowed; a frame that overflowed is redone.
  bool frameMustBeRedone() override;
  bool wantsMorePasses() const override;
  void recordMorePasses(VkCommandBuffer cmd, vk::PassTimer& timer) override;
  std::vector<std::pair<std::string, double>> frameFigures() const override;
  // Gives back the leaf-link room the frame left unused and the static pairs' links once made.
  void frameStands() override;
  bool reflectsLobes() const override { return b_.scene.glossy; }
  void recordReflections(VkCommandBuffer cmd, vk::PassTimer& timer, glm::vec4 eye, const vk::Buffer& shown,
                         const vk::Buffer& lobes) override;
  const vk::Buffer& irradiance() const override { return b_.irradiance; }
  const vk::Buffer& surfelBuried() const override { return b_.scene.surfelBuried; }
  uint64_t allocatedBytes() const override { return allocations_.bytes(); }

  IvStats stats() const;
  // The settings as solved with: --receiver-tol settled for the device.
  const IvSettings& settings() const { return settings_; }
  const Hierarchy& hierarchy() const { return setup_.hierarchy; }
  // Readbacks for tests: per surfel, its radiosity after the last bounce and its surviving links (a
  // static leaf: the frame's, then its static ones not overridden); the nodes as the refit left them.
  std::vector<glm::vec4> leafRadiosity() const;
  struct LeafLink {
    uint32_t sender;
    float formFactor;
  };
  std::vector<std::vector<LeafLink>> leafLinks() const;
  std::vector<gpu::NodeState> nodeStates() const;
  // The last relinked frame's receivers.
  std::vector<uint32_t> receiverSurfels() const;
  // Those of them made for surfels no other receiver's support holds (fills).
  std::vector<uint32_t> fillSurfels() const;
  // The still surfels by a concave crease (creases.h), in order.
  const std::vector<uint32_t>& creaseSurfels() const { return creases_; }
  // Per surfel, the receivers its irradiance is interpolated from and their coefficients.
  struct Tap {
    uint32_t receiver;
    float coefficient;
  };
  std::vector<std::vector<Tap>> interpolationTaps() const;

 private:
  bool splitsStatic() const { return !staticSet_.empty(); }
  bool rigid(size_t root) const;
  // The runs of surfels the rigid objects hold (nodeFlags' kNodeRigid), their surfels at rest on
  // the device, and room for the static set's surfels and nodes.
  void keepRestPose(const scene::Geometry& g, const std::vector<uint32_t>& nodeFlags);
  // The nodes at rest where an object moves rigidly (the others' as the surfels give them), into
  // restNodes_; the refit leaves them in the scene's nodes until the frame's refit.
  void recordRestNodes(VkCommandBuffer cmd, const vk::Buffer& surfels);
  // The nodes the static set's links are made and pruned on.
  const vk::Buffer& staticNodes() const { return anyRigid_ ? restNodes_ : b_.scene.nodes; }
  // Makes the passes that read the leaf links for the texel views their room is bound in.
  void readLeafLinkViews();
  void uploadScene(const scene::Geometry& g, const std::vector<uint32_t>& nodeFlags, bool split, uint64_t maskWords);
  // The frame's receivers, pruned as they are chosen (by their direct light and where their
  // surroundings are near), and the interpolation to every surfel.
  void recordReceivers(VkCommandBuffer cmd, vk::PassTimer& timer);
  void recordSolve(VkCommandBuffer cmd, vk::PassTimer& timer);
  void recordFirstBounces(VkCommandBuffer cmd, vk::PassTimer& timer);
  bool overflowed() const;

  const vk::Context& ctx_;
  const IvSetup setup_;
  const IvSettings& settings_;
  const uint32_t surfelCount_, nodeCount_;
  vk::Allocations allocations_;  // before the buffers, which count themselves into it
  IvBuffers b_;
  LinkSet staticSet_, frameSet_;
  Refit refit_;
  LinkCreation links_;
  Prune prune_;
  Bounces bounces_;
  Receivers receivers_;
  LinkRoom room_;
  bool linked_ = false, staticLinked_ = false;
  bool solvePending_ = false;    // the frame's links are recorded, its prune and bounces not yet
  bool reused_ = false;          // nothing moved: the last frame's bounces stand for this one
  bool roomProven_ = false;      // a frame stood since the link room last grew
  bool saidHostMemory_ = false;  // the note that links are in host memory, once
  bool linkStatic_ = false;      // the frame makes the static set's links
  uint32_t framesRedone_ = 0, staticPasses_ = 0;
  uint32_t gathersRecorded_ = 0;  // this frame's, so far
  // Per root: its instance's world matrix (scene::FrameInputs::matrices), where the objects' poses
  // start in b_.nodeFlags, and whether any object's links to itself are pruned once.
  std::vector<uint32_t> objectMatrix_;
  // The surfels at rest, the runs of them the rigid objects hold, the surfels the static set is made
  // on (the rigid objects' at rest) and their nodes.
  vk::Buffer restSurfels_, staticSurfels_, restNodes_;
  std::vector<VkBufferCopy> rigidRuns_;
  std::vector<float> poses_;  // the frame's, as the nodes' flags hold them (kPoseWords a root)
  uint32_t poseBase_ = 0;
  bool anyRigid_ = false;
  std::vector<uint32_t> creases_;  // creaseSurfels()
};

}  // namespace ivgi::gi

#pragma once
// The iv solver (design.md §1.2, §2 passes 3–6): refit, link creation, bin pruning and push-down,
// bounces. Every step is a compute pass; the host only sizes buffers from the counts the GPU reports
// and grows them when a frame overflowed.
#include <glm/glm.hpp>

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
};

// The scene's punctual lights in world space at `pose`.
std::vector<GpuLight> worldLights(const scene::Scene& scene, const scene::Pose& pose);

struct IvStats {
  uint32_t nodes = 0, levels = 0, links = 0, leafLinks = 0;
  uint64_t bytes = 0;
  bool sharedBins = true;
};

// What the iv solver of a frame is made from: the hierarchy over the rest-pose surfels and the
// user's settings.
struct IvSetup {
  Hierarchy hierarchy;
  IvSettings settings;
};
IvSetup makeIvSetup(const scene::Scene& scene, const scene::Geometry& geometry, const IvSettings& settings);

class IvSolver {
 public:
  IvSolver(const vk::Context& ctx, const scene::Geometry& geometry, const Hierarchy& hierarchy, const IvSettings& settings);

  void setLights(const std::vector<GpuLight>& lights);
  // Records the solver's passes. `relink`: geometry moved (or first frame), so refit, link creation
  // and pruning run; otherwise only the bounces.
  void record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Buffer& surfels, bool relink);
  // After the frame completed: grows what overflowed and returns true when the frame must be redone.
  bool growIfOverflowed();

  const vk::Buffer& irradiance() const { return irradiance_; }
  IvStats stats() const;
  const Hierarchy& hierarchy() const { return hierarchy_; }
  std::vector<glm::vec4> leafRadiosity() const;  // per surfel, after the last bounce
  struct LeafLink {
    uint32_t sender;
    float formFactor;
  };
  std::vector<std::vector<LeafLink>> leafLinks() const;  // per surfel: its surviving links, in bin order

  // Bins and form factors of the solver's bin table (unit centre direction, solid angle).
  static std::vector<glm::vec4> binTable(uint32_t n);
  // Whether 6·N² bins fit the device's shared memory (else the global-memory path runs).
  static bool binsFitShared(const vk::Context& ctx, uint32_t n);

 private:
  void allocateLinks();
  uint32_t refineIterations() const;  // refinement levels: each splits one side of every pair
  uint32_t pruneGroups() const;

  const vk::Context& ctx_;
  const Hierarchy& hierarchy_;
  IvSettings settings_;
  uint32_t surfelCount_, nodeCount_;
  uint32_t worklistCapacity_, linkCapacity_, leafLinkCapacity_;
  bool sharedBins_;
  bool linked_ = false;
  std::vector<uint32_t> rootPairs_;

  vk::Buffer tree_, leafOfSurfel_, albedo_, emission_, binTable_, environment_, lights_;
  vk::Buffer nodes_, counters_, args_, roots_, worklistA_, worklistB_, links_, counts_, starts_, senders_;
  vk::Buffer globalBins_, globalCoverage_, ranges_, leafLinks_, external_, radiosityA_, radiosityB_, irradiance_;
  uint32_t lightCount_ = 0;
  uint32_t finalRadiosity_ = 0;  // 0: A, 1: B

  vk::Program refit_, linkArgs_, refine_, countLinks_, scanCounts_, scatterLinks_, prune_, emit_, gather_, pullUp_;
};

}  // namespace ivgi::gi

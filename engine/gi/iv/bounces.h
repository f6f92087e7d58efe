#pragma once
// The bounces: emitted radiosity at the leaves, pulled up the trees (the prune credits emitters
// through it, and the bounces start from it); then per bounce a gather at the receivers over their
// surviving links, the interpolation to every surfel (receivers.h), a pull-up to the parents, so
// that coarse senders send the new value, and a check (shaders/iv/bounce_check.comp) of whether
// the bounces are done: until the light with the geometric tail of the bounces not run settles
// within a tolerance (the tail then added at every surfel), or a given count. Bounces are recorded
// in steps that run zero workgroups once the check says done; where a frame's steps ran out first,
// the solver records more.
#include <optional>

#include "engine/gi/hierarchy.h"
#include "engine/gi/iv/buffers.h"
#include "engine/gi/iv/settings.h"
#include "engine/gi/links.h"
#include "engine/scene/geometry.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

class Bounces {
 public:
  // Records into the solver's buffers `b`, over the links of its two sets, for the materials of `g`:
  // where some surface's lobe is far from even (Geometry::directionalLobes), recordReflections has
  // work, and where in some the lobe reflects most (a metal: Geometry::lobeDominatedMaterials), it
  // sends the first bounce's light along it.
  Bounces(const vk::Context& ctx, const Hierarchy& h, const IvSettings& settings, const IvBuffers& b,
          const LinkSet& staticSet, const LinkSet& frameSet, const scene::Geometry& g, vk::Allocations& allocations);
  // π·Le into nodeEmission at the leaves, pulled up, and copied to radiosityA (where bounces start).
  void recordEmission(VkCommandBuffer cmd) const;
  // The frame's first gather comes next, over the receivers listed. `estimated`: every one went
  // through recordEstimate this frame, which left what glossy senders send it along their lobes of
  // the direct light.
  void recordStart(VkCommandBuffer cmd, bool estimated) const;
  // The irradiance the receivers' refinement judges by: the direct light of the round's new
  // receivers, gathered from the emission.
  void recordEstimate(VkCommandBuffer cmd) const;
  // The buffer holding the radiosity of the last gather recorded so far (state().gathers of them).
  const vk::Buffer& solution(uint32_t gathers) const { return gathers % 2 ? b_.radiosityB : b_.radiosityA; }
  // `steps` more gathers (each with its interpolation, pull-up and check), from the frame's gather
  // `first` on; radiosityA and radiosityB take turns.
  void recordSteps(VkCommandBuffer cmd, uint32_t first, uint32_t steps) const;
  // The gathers before the first bounce's light: 1 (the direct light's) where the bins carry the
  // direct light, 0 where the depth maps give it.
  uint32_t directGathers() const { return b_.scene.emittersByMaps() ? 0u : 1u; }
  // The gathers a frame runs at most: the bounces asked for (or kMaxBounces) after the direct ones.
  uint32_t maxGathers() const { return (settings_.bounces ? *settings_.bounces : kMaxBounces) + directGathers(); }
  // After the bounces, per surfel into `lobes`: what each glossy surfel's specular lobe reflects
  // toward `eye` of the light its receivers' links bring (shaders/iv/lobe_links.glsl), found at the
  // receivers and interpolated to the surfels; only at those `shown` marks kShownFit, through the
  // receivers it then marks kShownTap (mark_taps).
  void recordReflections(VkCommandBuffer cmd, glm::vec4 eye, const vk::Buffer& shown, const vk::Buffer& lobes) const;
  // The still surfels by a concave crease (creases.h), which take their still senders' light from
  // their own static links each bounce (gather_creases.comp); none before this is called.
  void setCreases(const std::vector<uint32_t>& surfels, vk::Allocations& allocations);
  // The leaf links are bound in `views` texel views (shaders/common/parted_texels.glsl): 1 or kTexelParts.
  void readTexelViews(uint32_t views);
  // After the frame's steps ran: how far the bounces got.
  gpu::BounceState state() const { return state_.read<gpu::BounceState>(1)[0]; }

 private:
  void pullUp(VkCommandBuffer cmd, const vk::Buffer& radiosity, bool indirect) const;
  // The gather's buffers, reading the radiosity `in`.
  vk::Bindings gatherBindings(const vk::Buffer& in) const;
  // `arrival`: the gather adds what metals send along their lobes of the first bounce.
  gpu::GatherPush gatherPush(uint32_t newOnly, bool arrival = false, bool directKnown = false) const;
  // The buffers of the glossy lobes' passes: pool() with the lobes' own.
  vk::Bindings lobeBindings() const;
  // A scene with a metal's, before the first gather: what glossy senders send along their lobes
  // toward every receiver of the direct light (unless `estimated`, recordStart's), and the metals
  // of the first bounce's (mark_arrival, arrival_lobes, send_arrival, lobe_excess with kArrival).
  void recordArrival(VkCommandBuffer cmd, bool estimated) const;
  // What glossy senders send along their lobes to the receivers (lobe_excess.comp), at those the
  // receiver dispatch arguments `args` cover: every one, or (newOnly) the round's new ones.
  void recordLobeExcess(VkCommandBuffer cmd, uint32_t args, uint32_t newOnly) const;
  void makeLinkReaders();  // for texelViews_

  const vk::Context& ctx_;
  const IvSettings& settings_;
  const IvBuffers& b_;
  const LinkSet &staticSet_, &frameSet_;
  const uint32_t surfelCount_, nodeCount_;
  const bool glossy_;  // some lobe is far from even: glossy leaves send their lobes (sender_lobes.glsl)
  const bool metal_;   // some material's lobe reflects most: it sends the first bounce's light along it too
  const bool bases_;   // some dielectric's base sends far from evenly (Geometry::directionalBases)
  vk::Program emit_, interpolate_, pullUp_, check_, tail_;
  uint32_t texelViews_ = 1;
  // The passes that read the links: made again for more texel views.
  std::optional<vk::Program> gather_, gatherCreases_, markTaps_, reflectReceivers_, reflectSurfels_, lobeExcess_;
  // A scene with a metal's: lobe_excess for both lobes (kArrival), mark_arrival, arrival_lobes, send_arrival.
  std::optional<vk::Program> lobeExcessBoth_, markArrival_, arrivalLobes_, sendArrival_;
  uint32_t interpolateGroups_;
  vk::Buffer sums_, state_, fullArgs_, args_;  // per gather workgroup; the state; dispatch sizes, full and next
  vk::Buffer change_;                          // per surfel, the irradiance's change at the last gather
  vk::Buffer receiverLobe_;                    // per surfel, at receivers: what reflect_receivers found
  vk::Buffer receiverExcess_;                  // per surfel, at receivers: what lobe_excess found
  vk::Buffer arrivalExcess_;                   // the same of the first bounce's light
  vk::Buffer receiverArrival_;                 // per surfel, at the receivers metal surfels tap: arrival_lobes'
  vk::Buffer senderArrival_;                   // per node: send_arrival's
  vk::Buffer arrivalTaps_;                     // per surfel: mark_arrival's
  vk::Buffer stillGathered_;                   // per surfel: the static links' light (gather, gather_creases)
  vk::Buffer creaseSurfels_, surfelCrease_;    // the surfels by a crease; per surfel, 1 where it is one
  uint32_t creaseCount_ = 0;
};

}  // namespace ivgi::gi

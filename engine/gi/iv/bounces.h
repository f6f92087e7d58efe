#pragma once
// Pass 6, bounces: emitted radiosity at the leaves, pulled up the trees (the prune credits emitters
// through it, and the bounces start from it); then per bounce a gather at the leaves over their
// surviving links and a pull-up to the parents, so that coarse senders send the new value.
#include "engine/gi/hierarchy.h"
#include "engine/gi/iv/buffers.h"
#include "engine/gi/iv/links.h"
#include "engine/gi/iv/settings.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

class Bounces {
 public:
  explicit Bounces(const vk::Context& ctx);
  // π·Le into radiosityA at the leaves, pulled up.
  void recordEmission(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h) const;
  // K + 1 gathers for K bounces, alternating radiosityA and radiosityB; returns which holds the
  // result (0: A, 1: B).
  uint32_t record(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h, const LinkSet& staticSet,
                  const LinkSet& frameSet, const IvSettings& settings) const;

 private:
  void pullUp(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h, const vk::Buffer& radiosity) const;
  vk::Program emit_, gather_, pullUp_;
};

}  // namespace ivgi::gi

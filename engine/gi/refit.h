#pragma once
// Pass 3, refit (shaders/refit.comp): the trees' node attributes from the frame's surfels,
// bottom-up in one dispatch: area, area-weighted position and normal, the cone of normals,
// a bounding radius, and the rectangle of the node's area. The trees' topology never changes.
#include "engine/gi/hierarchy.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

class Refit {
 public:
  explicit Refit(const vk::Context& ctx);
  // `tree`: the hierarchy's nodes (gpu::TreeNode); `nodes`: their gpu::NodeState, written;
  // `arrivals`: a count per node, zero before and after (shaders/climb.glsl).
  void record(VkCommandBuffer cmd, const Hierarchy& h, const vk::Buffer& tree, const vk::Buffer& surfels,
              const vk::Buffer& nodes, const vk::Buffer& arrivals) const;

 private:
  vk::Program program_;
};

}  // namespace ivgi::gi

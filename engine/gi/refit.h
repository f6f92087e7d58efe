#pragma once
// The refit (shaders/gi/refit.comp): the trees' node attributes from the frame's surfels, bottom-up
// in one dispatch: area, area-weighted position and normal, the cone of normals, a bounding radius,
// and the rectangle of the node's area. The trees' topology never changes.
#include "engine/gi/scene_buffers.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

class Refit {
 public:
  explicit Refit(const vk::Context& ctx);
  // Writes scene.nodes from the trees and the frame's `surfels` (gpu::Surfel).
  void record(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& surfels) const;

 private:
  vk::Program program_;
};

}  // namespace ivgi::gi

#pragma once
// The refit (shaders/gi/refit.comp): the trees' node attributes from the frame's surfels, bottom-up
// in one dispatch: area, area-weighted position and normal, the cone of normals, a bounding radius,
// the rectangle of the node's area, and its vector area. The trees' topology never changes. Then
// which surfels lie inside another object (shaders/gi/buried_surfels.comp), from those nodes: the
// resolve's vertices take their light from the surfels outside (vertex_irradiance), so that a
// surface an object stands on is not drawn dark along the contact.
#include "engine/gi/scene_buffers.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

class Refit {
 public:
  explicit Refit(const vk::Context& ctx);
  // Writes scene.nodes and scene.nodeVectorArea from the trees and the frame's `surfels`
  // (gpu::Surfel), then scene.surfelBuried, scene.nodeBuried and scene.nodeStillBuried. After the
  // first, only what moves: the trees of the objects that move, and the burial of surfels by or in
  // them (what stays still keeps its nodes and its burial from the first).
  void record(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& surfels);
  // The node attributes alone (a rest pose's nodes, which no image reads for burial).
  void recordNodes(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& surfels) const;
  // After recordNodes at the rest pose: which surfels of the objects that move rigidly
  // (gpu::kRootRigid) lie inside another part of their own, found there and kept for every frame
  // (gpu::kBuriedInItself), so that a frame's burial does not hang on the frame it starts from.
  void recordRestBurial(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& restSurfels);

 private:
  vk::Program refit_, burial_;
  bool stillKnown_ = false;   // the still objects' nodes and burial stand from a pass before
  bool shapesKnown_ = false;  // recordRestBurial ran
};

}  // namespace ivgi::gi

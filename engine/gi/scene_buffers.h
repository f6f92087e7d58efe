#pragma once
// The scene as both solvers read it on the device, one buffer and one name per quantity: what iv's
// and ar's passes bind under these names is the same data. A solver uploads it once, at the bins of
// its own settings (iv's --bins, ar's --dirs), and holds it in its buffers (iv/buffers.h,
// ar/buffers.h).
#include <optional>
#include <vector>

#include "engine/gi/bins.h"
#include "engine/gi/hierarchy.h"
#include "engine/scene/environment.h"
#include "engine/scene/geometry.h"
#include "engine/vk/buffer.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

struct SceneBuffers {
  // Uploaded once: the trees (gpu::TreeNode), per node where a depth-first walk that skips it goes
  // on (Hierarchy::skip), each surfel's leaf, the surfels' albedo and emission (Le), per bin ∫ω dω
  // and its solid angle (binVectorTable), the environment's radiance per bin.
  vk::Buffer tree, skip, leafOfSurfel, albedo, emission, binTable, environment;
  // Where some material is glossy (else one-element stand-ins): each surfel's BRDF
  // (Geometry::surfelBrdf) and the specular albedo table (engine/scene/reflectance.h), for what the
  // lobes reflect of the indirect light.
  vk::Buffer surfelBrdf, specularAlbedo;
  // Per node, where some lobe sends by direction (Geometry::directionalLobes; else one element):
  // what a glossy leaf sends along its lobe (shaders/common/send_lobe.glsl), written each frame by
  // the solver; zeros elsewhere, and inner nodes, never written, send evenly.
  vk::Buffer senderLobes;
  // Per frame: the punctual lights (host-visible), and the nodes' states (gpu::NodeState, refit)
  // with the refit's arrival counts (shaders/common/climb.glsl: zero between dispatches).
  vk::Buffer lights, nodes, arrivals;
  // Per frame, per node (refit): Σ a·n over its surfels (vec4, w unused).
  vk::Buffer nodeVectorArea;
  // Per frame, per surfel: 1 where it lies inside another object (gi::Refit), else 0; per node,
  // how many of the surfels below it do, how many of those belong to an object that stays still and
  // lie inside one that does too, and (uploaded once) how many surfels lie below it.
  vk::Buffer surfelBuried, nodeBuried, nodeStillBuried, nodeLeaves;
  // Per root (uploaded once): gpu::kRootEncloses where it may hold other objects' surfels
  // (Hierarchy::rootEncloses), gpu::kRootStill where its object does not move, gpu::kRootRigid where
  // it moves rigidly (what it buries of itself found at rest).
  vk::Buffer rootFlags;
  // The leaves of the objects that move (uploaded once; every leaf where none stays still): once
  // every tree is refit, a frame refits theirs alone.
  vk::Buffer movingLeaves;
  uint32_t movingLeafCount = 0;
  vk::Buffer surfelRoot;        // per surfel (uploaded once): its tree's root (Hierarchy::rootOfSurfel)
  bool movingEncloses = false;  // some object that moves encloses a volume (may bury others' surfels)
  // Per surfel, the emitters' direct light from depth maps (engine/gi/direct_light.h) where the
  // frame gives it (Solver::useDirectLight): the solver then transports only the light the surfels
  // reflect. Else zeros (`noDirectLight`), the solver carrying the emitters' light itself.
  // With it, where some lobe sends by direction, the mean direction it arrives from
  // (DirectLight::surfelArrival).
  const vk::Buffer* directLight = nullptr;
  const vk::Buffer* directArrival = nullptr;
  vk::Buffer noDirectLight;
  uint32_t nodeCount = 0, surfelCount = 0, lightCount = 0, rootCount = 0;
  bool environmentOn = false;
  bool glossy = false;  // some material is not Lambertian

  bool emittersByMaps() const { return directLight != nullptr; }
  // Some object stays still over the frames rendered.
  bool anyStill() const { return movingLeafCount < surfelCount; }
  // The surfels' direct light from the maps, with the environment's (which the bins then leave out) or not.
  void takeDirectLight(const vk::Buffer& surfelDirect, const vk::Buffer& surfelArrival, bool withEnvironment) {
    directLight = &surfelDirect;
    directArrival = &surfelArrival;
    if (withEnvironment) environmentOn = false;
  }
  const vk::Buffer& surfelDirect() const { return directLight ? *directLight : noDirectLight; }
  const vk::Buffer& surfelArrival() const { return directArrival ? *directArrival : noDirectLight; }

  SceneBuffers() = default;
  // Per root: `objectMoves`, whether its object moves over the frames rendered (empty: every one
  // may); `objectRigid`, whether it moves rigidly and what it buries of itself is found at its rest
  // pose (Refit::recordRestBurial; empty: none).
  // `bins` lie in `frame` (iv's: each receiver's normal; ar's: the world's).
  SceneBuffers(const vk::Context& ctx, const scene::Geometry& geometry, const Hierarchy& hierarchy, uint32_t bins,
               BinFrame frame, const std::optional<scene::Environment>& environment,
               const std::vector<bool>& objectMoves, const std::vector<bool>& objectRigid,
               vk::Allocations& allocations);
  // The frame's punctual lights in world space (the buffer grows where they do not fit).
  void setLights(const vk::Context& ctx, const std::vector<gpu::PunctualLight>& frameLights,
                 vk::Allocations& allocations);
  // Every buffer above by the name the shaders bind it under.
  vk::Bindings pool() const;
};

}  // namespace ivgi::gi

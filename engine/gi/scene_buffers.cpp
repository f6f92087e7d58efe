#include "engine/gi/scene_buffers.h"

#include "engine/gi/bins.h"
#include "engine/scene/reflectance.h"

namespace ivgi::gi {

SceneBuffers::SceneBuffers(const vk::Context& ctx, const scene::Geometry& g, const Hierarchy& h, uint32_t bins,
                           BinFrame frame, const std::optional<scene::Environment>& sky,
                           const std::vector<bool>& objectMoves, const std::vector<bool>& objectRigid,
                           vk::Allocations& allocations)
    : nodeCount(uint32_t(h.nodes.size())),
      surfelCount(uint32_t(h.leafOfSurfel.size())),
      rootCount(uint32_t(h.roots.size())),
      environmentOn(sky.has_value()),
      glossy(g.glossyMaterials) {
  vk::Allocations* tally = &allocations;
  const size_t nodeCount = std::max<size_t>(h.nodes.size(), 1);
  tree = vk::makeBuffer(ctx, h.nodes, vk::Memory::Device, tally);
  skip = vk::makeBuffer(ctx, h.skip, vk::Memory::Device, tally);
  leafOfSurfel = vk::makeBuffer(ctx, h.leafOfSurfel, vk::Memory::Device, tally);
  albedo = vk::makeBuffer(ctx, g.surfelAlbedo, vk::Memory::Device, tally);
  emission = vk::makeBuffer(ctx, g.surfelEmission, vk::Memory::Device, tally);
  binTable = vk::makeBuffer(ctx, binVectorTable(bins, frame), vk::Memory::Device, tally);
  environment = vk::makeBuffer(ctx, environmentTable(sky, bins), vk::Memory::Device, tally);
  surfelBrdf = vk::makeBuffer(ctx, glossy ? g.surfelBrdf : std::vector<gpu::SurfaceBrdf>(1), vk::Memory::Device, tally);
  specularAlbedo = vk::makeBuffer(ctx, glossy ? scene::SpecularAlbedo::table().texels() : std::vector<glm::vec4>(1),
                                  vk::Memory::Device, tally);
  senderLobes = vk::makeBuffer(ctx, std::vector<glm::vec4>(g.directionalLobes ? 2 * nodeCount : 1, glm::vec4(0.0f)),
                               vk::Memory::Device, tally);
  lights = vk::Buffer(ctx, sizeof(gpu::PunctualLight), vk::Memory::Host, tally);
  noDirectLight =
      vk::makeBuffer(ctx, std::vector<glm::vec4>(std::max<size_t>(h.leafOfSurfel.size(), 1), glm::vec4(0.0f)),
                     vk::Memory::Device, tally);
  nodes = vk::Buffer(ctx, nodeCount * sizeof(gpu::NodeState), vk::Memory::Device, tally);
  arrivals = vk::makeBuffer(ctx, std::vector<uint32_t>(nodeCount, 0u), vk::Memory::Device, tally);
  surfelBuried = vk::deviceArray<uint32_t>(ctx, std::max<size_t>(h.leafOfSurfel.size(), 1), allocations);
  nodeBuried = vk::deviceArray<uint32_t>(ctx, nodeCount, allocations);
  nodeStillBuried = vk::deviceArray<uint32_t>(ctx, nodeCount, allocations);
  nodeVectorArea = vk::deviceArray<glm::vec4>(ctx, nodeCount, allocations);
  std::vector<uint32_t> leaves(nodeCount, 0u);
  for (size_t i = h.nodes.size(); i-- > 0;) {  // deeper levels come later
    if (h.nodes[i].childCount == 0) leaves[i] = 1;
    if (h.nodes[i].parent >= 0) leaves[size_t(h.nodes[i].parent)] += leaves[i];
  }
  nodeLeaves = vk::makeBuffer(ctx, leaves, vk::Memory::Device, tally);
  std::vector<uint32_t> flags(std::max<size_t>(h.roots.size(), 1), 0u);
  for (size_t r = 0; r < h.roots.size(); ++r) {
    flags[r] = (h.rootEncloses[r] ? gpu::kRootEncloses : 0u) |
               (!objectMoves.empty() && !objectMoves[r] ? gpu::kRootStill : 0u) |
               (!objectRigid.empty() && objectRigid[r] ? gpu::kRootRigid : 0u);
    movingEncloses = movingEncloses || (flags[r] & (gpu::kRootEncloses | gpu::kRootStill)) == gpu::kRootEncloses;
  }
  rootFlags = vk::makeBuffer(ctx, flags, vk::Memory::Device, tally);
  std::vector<uint32_t> moving;
  for (size_t s = 0; s < h.leafOfSurfel.size(); ++s)
    if (!(flags[h.rootOfSurfel[s]] & gpu::kRootStill)) moving.push_back(h.leafOfSurfel[s]);
  surfelRoot = vk::makeBuffer(ctx, h.rootOfSurfel.empty() ? std::vector<uint32_t>{0u} : h.rootOfSurfel,
                              vk::Memory::Device, tally);
  movingLeafCount = uint32_t(moving.size());
  if (moving.empty()) moving.push_back(0u);  // a one-element stand-in, never read
  movingLeaves = vk::makeBuffer(ctx, moving, vk::Memory::Device, tally);
}

void SceneBuffers::setLights(const vk::Context& ctx, const std::vector<gpu::PunctualLight>& frameLights,
                             vk::Allocations& allocations) {
  if (lights.size() < frameLights.size() * sizeof(gpu::PunctualLight))
    lights = vk::Buffer(ctx, frameLights.size() * sizeof(gpu::PunctualLight), vk::Memory::Host, &allocations);
  lights.upload(frameLights);
  lightCount = uint32_t(frameLights.size());
}

vk::Bindings SceneBuffers::pool() const {
  return vk::Bindings::pool({{"tree", tree},
                             {"skip", skip},
                             {"leafOfSurfel", leafOfSurfel},
                             {"albedo", albedo},
                             {"emission", emission},
                             {"binTable", binTable},
                             {"environment", environment},
                             {"lights", lights},
                             {"nodes", nodes},
                             {"arrivals", arrivals},
                             {"surfelBuried", surfelBuried},
                             {"nodeBuried", nodeBuried},
                             {"nodeStillBuried", nodeStillBuried},
                             {"nodeVectorArea", nodeVectorArea},
                             {"nodeLeaves", nodeLeaves},
                             {"rootFlags", rootFlags},
                             {"surfelRoot", surfelRoot},
                             {"movingLeaves", movingLeaves},
                             {"surfelDirect", surfelDirect()},
                             {"surfelArrival", surfelArrival()},
                             {"surfelBrdf", surfelBrdf},
                             {"specularAlbedo", specularAlbedo},
                             {"senderLobes", senderLobes}});
}

}  // namespace ivgi::gi

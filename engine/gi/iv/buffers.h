#pragma once
// The iv solver's device memory, by what it holds: the scene both solvers read (scene_buffers.h)
// and iv's own; the link sets (links.h) hold what each set of root pairs links. The passes bind
// these by the names their shaders give them: each dispatch takes what its shader names from pool()
// and lists only what differs (a link set's, a bounce's).
#include "engine/gi/scene_buffers.h"
#include "engine/vk/buffer.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

struct IvBuffers {
  SceneBuffers scene;
  // Per node, uploaded once: whether it moves, whether its surface is closed and whether it moves
  // rigidly (gpu::kNodeMoves, kNodeClosed, kNodeRigid), and its object's root; then per object
  // (root) its pose (gpu::kPoseWords), rewritten each frame.
  vk::Buffer nodeFlags;
  // Per frame: emitted radiosity π·Le per node (pulled up), radiosity per node (bounces read one and
  // write the other), irradiance per surfel, and per surfel the irradiance from lights and the
  // environment with the environment's rotation gradient (gpu::kExternalTexels).
  vk::Buffer nodeEmission, radiosityA, radiosityB, irradiance, externalLight;
  // Link creation's two worklists and the indirect dispatch arguments between its levels.
  vk::Buffer args, worklistA, worklistB;
  // Each leaf's surviving links (texels, past one storage binding), and per static leaf and mask
  // word the bins the frame's senders override.
  vk::Buffer ranges, leafLinks, overrides;
  // What a static leaf keeps between frames: its survivors among static senders (links, packed bin
  // and coverage, key depths), its bins as mask words, what it sums of them (gpu::StaticLeaf) and
  // the emitters it lists.
  vk::Buffer staticRanges, staticLinks, staticBins, staticDepths, staticMasks, staticLeaves, staticEmitters;
  // The prune's bins where they do not fit in shared memory: a slot of 6·N² per workgroup.
  vk::Buffer globalBins, globalCoverage;
  // Receivers (receivers.h). Per node: its representative surfel, its need, presence and role, and
  // the reach of the supports at and below it; where each level starts. The receivers listed this
  // frame, their counters and the dispatch sizes they need, the refinement's two candidate lists.
  // Per surfel: its support radius (kNotReceiver: not a receiver), how near what it sees is, the
  // irradiance gathered (at receivers) and its first bounce's rotation gradient (three vec4: r, g,
  // b), and the interpolation's taps. The groups of neighbouring surfels, each surfel's group, and
  // per group the sampled nodes whose receivers may weigh for its surfels.
  vk::Buffer representatives, levelStarts, receivers, receiverCounts, receiverArgs, receiverRadius;
  vk::Buffer candidatesA, candidatesB, reach, gathered, rotationGradients, tapCounts, taps, proximity;
  vk::Buffer needs, presences, roles, groups, groupOfSurfel, neighbourCounts, neighbours;
  vk::Buffer seenNodes;

  // Every buffer above by the name the shaders bind it under.
  vk::Bindings pool() const {
    return scene.pool().plus(vk::Bindings::pool({{"nodeFlags", nodeFlags},
                                                 {"nodeEmission", nodeEmission},
                                                 {"irradiance", irradiance},
                                                 {"externalLight", externalLight},
                                                 {"args", args},
                                                 {"ranges", ranges},
                                                 {"leafLinks", leafLinks},
                                                 {"overrides", overrides},
                                                 {"staticRanges", staticRanges},
                                                 {"staticLinks", staticLinks},
                                                 {"staticBins", staticBins},
                                                 {"staticDepths", staticDepths},
                                                 {"staticMasks", staticMasks},
                                                 {"staticLeaves", staticLeaves},
                                                 {"staticEmitters", staticEmitters},
                                                 {"globalBins", globalBins},
                                                 {"globalCoverage", globalCoverage},
                                                 {"representatives", representatives},
                                                 {"levelStarts", levelStarts},
                                                 {"needs", needs},
                                                 {"seenNodes", seenNodes},
                                                 {"presences", presences},
                                                 {"roles", roles},
                                                 {"groups", groups},
                                                 {"groupOfSurfel", groupOfSurfel},
                                                 {"neighbourCounts", neighbourCounts},
                                                 {"neighbours", neighbours},
                                                 {"receivers", receivers},
                                                 {"receiverCounts", receiverCounts},
                                                 {"receiverArgs", receiverArgs},
                                                 {"receiverRadius", receiverRadius},
                                                 {"reach", reach},
                                                 {"gathered", gathered},
                                                 {"rotationGradients", rotationGradients},
                                                 {"tapCounts", tapCounts},
                                                 {"taps", taps},
                                                 {"proximity", proximity}}));
  }
};

}  // namespace ivgi::gi

#pragma once
// The iv solver's device memory, by what it holds. The passes bind these by the names their shaders
// give them (the same names as here), and the link sets (links.h) hold what each set of root pairs
// links.
#include "engine/vk/buffer.h"

namespace ivgi::gi {

struct IvBuffers {
  // The scene, uploaded once: the trees, which surfels are leaves and which move, their albedo and
  // emission, the table of bins (unit centre direction, solid angle), the environment per bin, the
  // frame's punctual lights.
  vk::Buffer tree, leafOfSurfel, leafMoves, albedo, emission, binTable, environment, lights;
  // Per frame: node attributes (refit), radiosity per node (bounces read one and write the other),
  // irradiance per surfel, and per surfel the irradiance from lights and the environment.
  vk::Buffer nodes, radiosityA, radiosityB, irradiance, externalLight;
  // Link creation's two worklists and the indirect dispatch arguments between its levels.
  vk::Buffer args, worklistA, worklistB;
  // Each leaf's surviving links (texels, past one storage binding), and per static leaf and mask
  // word the bins the frame's senders override.
  vk::Buffer ranges, leafLinks, overrides;
  // What a static leaf keeps between frames: its survivors among static senders (links, packed bin
  // and coverage, key depths), its bins as mask words, the environment through them, the emitters it
  // lists and the emission its static bins credited.
  vk::Buffer staticRanges, staticLinks, staticBins, staticDepths, staticMasks, staticEnvironment;
  vk::Buffer staticEmitters, staticEmitterCounts, staticCorrection;
  // The prune's bins where they do not fit in shared memory: a slot of 6·N² per workgroup.
  vk::Buffer globalBins, globalCoverage;
};

}  // namespace ivgi::gi

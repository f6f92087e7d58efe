#pragma once
// The ar solver's device memory, by what it holds; the passes bind these by the names their shaders
// give them (pool()). The directional tables hold 6·N² bins per node or surfel, as rgba32f texels
// (their views reach past one storage binding).
#include "engine/vk/buffer.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

struct ArBuffers {
  // The scene, uploaded once: the trees, each surfel's leaf, albedo and emission (Le), per bin
  // ∫ω dω and Ω, the environment per bin, the frame's punctual lights.
  vk::Buffer tree, leafOfSurfel, albedo, emission, binVectors, environment, lights;
  // Per frame: node attributes (refit); link creation's worklists and dispatch sizes. Per node, the
  // emission of its bright emitters (static), whose links link creation takes down to the
  // receivers' surfels (ar reads the radiance itself).
  vk::Buffer nodes, nodeEmission, args, worklistA, worklistB;
  // Per node, the refit's arrival counts (shaders/climb.glsl): zero between dispatches.
  vk::Buffer arrivals;
  // The directional tables: per node the radiance less antiradiance it gathered over its links
  // (looking directions) and what it sends (travel directions; a flat node: its antiradiance times
  // its area, the rest: its intensity); per surfel its incident
  // light (its own and its ancestors' gathered, the environment, the lights).
  vk::Buffer gathered, intensity, incident;
  // The nodes in the order the global pass takes them as receivers (ar_order_receivers).
  vk::Buffer gatherOrder;
  // The nodes whose senders' lists are too long for one invocation to sort: a count, then the nodes.
  vk::Buffer longSorts;
  // Per node: the exitance (area · L) of a flat node, whose intensity table holds its antiradiance
  // alone (the cosines applied where it is read).
  vk::Buffer exitance;
  // Per node: the vector sum of what it gathered (radiance × solid angle × direction; x, y, z texels
  // of RGB), from which each surfel's irradiance takes every sender's own direction.
  vk::Buffer gatheredVector;
  // Per surfel: radiance (Le + ρE/π, from the last radiance step) and irradiance; per iteration and
  // workgroup of the incident pass, what the host judges the iteration by.
  vk::Buffer radiance, irradiance, sums;
  // Where frames chain: the incident tables, radiance and irradiance a warm frame started from, so
  // that a frame redone starts from the same.
  vk::Buffer startIncident, startRadiance, startIrradiance;
  // Set by the global pass where a receiver's list was longer than its chunks walked (host-visible).
  vk::Buffer gatherFlags;

  vk::Bindings pool() const {
    return vk::Bindings::pool({{"tree", tree},
                               {"leafOfSurfel", leafOfSurfel},
                               {"albedo", albedo},
                               {"emission", emission},
                               {"binVectors", binVectors},
                               {"environment", environment},
                               {"lights", lights},
                               {"nodes", nodes},
                               {"nodeEmission", nodeEmission},
                               {"gathered", gathered},
                               {"gatheredVector", gatheredVector},
                               {"intensity", intensity},
                               {"exitance", exitance},
                               {"gatherOrder", gatherOrder},
                               {"longSorts", longSorts},
                               {"incident", incident},
                               {"radiance", radiance},
                               {"irradiance", irradiance},
                               {"sums", sums},
                               {"gatherFlags", gatherFlags}});
  }
};

}  // namespace ivgi::gi

#pragma once
// The ar solver's device memory, by what it holds: the scene both solvers read (scene_buffers.h)
// and ar's own; the passes bind these by the names their shaders give them (pool()). The
// directional tables hold 6·N² bins per node or surfel, as rgba32f texels (their views reach past
// one storage binding).
#include "engine/gi/scene_buffers.h"
#include "engine/vk/buffer.h"
#include "engine/vk/program.h"

namespace ivgi::gi {

struct ArBuffers {
  SceneBuffers scene;
  // Per node, uploaded once: the emission of its bright emitters, whose links link creation takes
  // down to the receivers' surfels (LinkWork::emitters; ar reads the radiance itself). Link
  // creation's dispatch sizes and worklists.
  vk::Buffer brightEmitters, args, worklistA, worklistB;
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
    return scene.pool().plus(vk::Bindings::pool({{"gathered", gathered},
                                                 {"gatheredVector", gatheredVector},
                                                 {"intensity", intensity},
                                                 {"exitance", exitance},
                                                 {"gatherOrder", gatherOrder},
                                                 {"longSorts", longSorts},
                                                 {"incident", incident},
                                                 {"radiance", radiance},
                                                 {"irradiance", irradiance},
                                                 {"sums", sums},
                                                 {"gatherFlags", gatherFlags}}));
  }
};

}  // namespace ivgi::gi

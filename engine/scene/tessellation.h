#pragma once
// Tessellation of coarse meshes (docs/design.md §2.4): the iv solver's receivers are chosen among
// the surfels where the lighting needs them, so a surface must offer surfels at least as fine as
// the lighting's detail may be. Triangles are split, conformingly, until no edge is longer than a
// length; the surfaces do not change (every new vertex lies on an edge, with its attributes
// interpolated), only how finely they are sampled.
#include <glm/glm.hpp>

#include <cstddef>

#include "engine/scene/scene.h"

namespace ivgi::scene {

// `p` with every edge longer than `maxEdge` (measured after `toWorld`) split at its middle: a
// triangle with one long edge into two, one with more into four (a second long edge splits its
// third too, so that neighbours share every new vertex), repeated until none is longer or the
// primitive holds `maxVertices` (it is then left as far as it got).
Primitive tessellated(const Primitive& p, const glm::mat4& toWorld, float maxEdge, size_t maxVertices);

}  // namespace ivgi::scene

#pragma once
// Tessellation of coarse meshes (docs/design.md §2.1, §2.4): the iv solver's receivers are chosen
// among the surfels where the lighting needs them, so a surface must offer surfels at least as fine
// as the lighting's detail may be: nowhere coarser than a share of the scene, and near a smaller
// object (a pebble on a large floor) about as fine as their distance, down to the object's size. Triangles are split,
// conformingly; the surfaces do not change (every new vertex lies on an edge, with its attributes interpolated), only
// how finely they are sampled.
#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "engine/scene/scene.h"

namespace ivgi::scene {

// The longest edge a surface may keep at a point: `uniform` everywhere, and where a surface smaller
// than that (another primitive) lies nearer than the edge is long, no longer than the larger of
// their distance (to its bounds) and that surface's extent (its bounds' diagonal): a receiver no
// larger than the objects beside it, which it could otherwise sample as wholly covered or see only
// edge-on.
class EdgeLimits {
 public:
  explicit EdgeLimits(float uniform) : uniform_(uniform) {}
  // A surface's triangles in world space; `owner` tells surfaces apart (one per primitive drawn).
  void addSurface(uint32_t owner, const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices);
  // After the last surface: orders each cell's surfaces by extent, so that tooLong() stops at the
  // first too large to ask anything of an edge (many instances overlapping would each be walked).
  void finish();
  // Whether an edge of `length` with its middle at `p`, on `owner`'s surface, must be split.
  bool tooLong(glm::vec3 p, float length, uint32_t owner) const;
  float uniform() const { return uniform_; }

 private:
  struct Box {  // a small surface's bounds
    glm::vec3 lo, hi;
    float extent;
    uint32_t owner;
  };
  glm::ivec3 cellOf(glm::vec3 p) const;
  float uniform_;
  std::vector<Box> boxes_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;  // boxes by the cells (of side uniform_) they reach
};

// `p` (placed by `toWorld`) with every edge that `limits` finds too long split at its middle: a
// triangle with one long edge into two, one with more into four (a second long edge splits its
// third too, so that neighbours share every new vertex), as is one with one long edge and two longer
// than half their limit (a grid whose diagonals alone are too long halves its spacing), repeated until none is too long
// or the primitive holds `maxVertices` (it is then left as far as it got).
Primitive tessellated(const Primitive& p, const glm::mat4& toWorld, const EdgeLimits& limits, uint32_t owner,
                      size_t maxVertices);

}  // namespace ivgi::scene

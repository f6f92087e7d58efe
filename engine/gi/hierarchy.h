#pragma once
// The surfel hierarchy of docs/design.md §2.1: one tree per drawn instance, built once on the rest
// pose. A node whose surfels' normals fall into groups apart (faces meeting at an edge) splits
// between them first; otherwise a UV quadtree where the mesh has a usable UV atlas (as in Dong et
// al.), a median split of the rest-pose positions where it has not. Leaves are surfels. Nodes are
// numbered level by level over all trees, so that the refit runs one dispatch per level, deepest
// first.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/scene/geometry.h"
#include "engine/scene/scene.h"
#include "shaders/interface.h"

namespace ivgi::gi {

struct Hierarchy {
  std::vector<gpu::TreeNode> nodes;
  std::vector<uint32_t> levelStart;    // level l holds nodes [levelStart[l], levelStart[l + 1])
  std::vector<uint32_t> roots;         // one per object (drawn instance with surfels)
  std::vector<uint32_t> rootInstance;  // per root: its instance
  std::vector<uint32_t> leafOfSurfel;
  std::vector<uint32_t> rootOfSurfel;  // per surfel: its tree's root (roots are nodes 0 to roots − 1)
  // Per node: the surfel that stands for it as a receiver (docs/design.md §2.4), one of its
  // children's, the one nearest its rest-pose centroid; so a node's receiver is also one of each
  // ancestor's it stands for.
  std::vector<uint32_t> representatives;
  // Per node: the node a depth-first walk goes on to when it skips this node's subtree (its next
  // sibling, else its parent's), nodes.size() past the last; so a walk needs no stack.
  std::vector<uint32_t> skip;
  // Groups of neighbouring surfels, each a node two levels above their leaves (or a root), and per
  // surfel its group: the interpolation lists candidates once per group (docs/design.md §2.4).
  std::vector<uint32_t> groups, groupOfSurfel;
  std::vector<uint8_t> uvTree;  // per root: 1 if built as a UV quadtree
  // Per root: 1 where its surface at rest, normals out, encloses a volume (it may hold other
  // objects' surfels inside it).
  std::vector<uint8_t> rootEncloses;
  // Per root: the axes its surfaces follow at rest, as rows (gi::objectAxes), which its leaves' bins
  // tilt from.
  std::vector<glm::mat3> rootAxes;
  float size = 0;  // how far the surfels reach across at rest (extentOf: the same however the scene turns)
  uint32_t levels() const { return uint32_t(levelStart.size() - 1); }
  uint32_t maxDepth() const { return levels() ? levels() - 1 : 0; }
};

// Whether the UVs of instance triangles form a usable atlas: present, finite, and not overlapping
// (the UV area adds up to what the triangles cover on a 512² grid, within 5 %).
bool usableUvAtlas(const std::vector<glm::vec2>& uvs, const std::vector<glm::uvec3>& triangles);

Hierarchy buildHierarchy(const scene::Geometry& geometry, const std::vector<scene::Surfel>& restSurfels);
// The hierarchy over the scene's surfels at its rest pose.
Hierarchy restPoseHierarchy(const scene::Scene& scene, const scene::Geometry& geometry);
// Per root of `hierarchy`: whether its object moves under `animation` (-1: none does).
std::vector<bool> movingRoots(const Hierarchy& hierarchy, const scene::Scene& scene, const scene::Geometry& geometry,
                              int animation);
// Per root of `hierarchy`: whether `animation` moves its object rigidly, keeping its shape
// (scene::rigidlyMovingInstances).
std::vector<bool> rigidRoots(const Hierarchy& hierarchy, const scene::Scene& scene, const scene::Geometry& geometry,
                             int animation);

}  // namespace ivgi::gi

#pragma once
// The surfel hierarchy of docs/design.md §2.1: one tree per drawn instance, built once on the rest pose —
// a UV quadtree where the mesh has a usable UV atlas (as in Dong et al.), a median split of the
// rest-pose positions where it has not. Leaves are surfels. Nodes are numbered level by level over
// all trees, so that the refit runs one dispatch per level, deepest first.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/scene/geometry.h"
#include "shaders/interface.h"

namespace ivgi::gi {

struct Hierarchy {
  std::vector<gpu::TreeNode> nodes;
  std::vector<uint32_t> levelStart;    // level l holds nodes [levelStart[l], levelStart[l + 1])
  std::vector<uint32_t> roots;         // one per object (drawn instance with surfels)
  std::vector<uint32_t> rootInstance;  // per root: its instance
  std::vector<uint32_t> leafOfSurfel;
  std::vector<uint8_t> uvTree;  // per root: 1 if built as a UV quadtree
  uint32_t levels() const { return uint32_t(levelStart.size() - 1); }
  uint32_t maxDepth() const { return levels() ? levels() - 1 : 0; }
};

// Whether the UVs of instance triangles form a usable atlas: present, finite, and not overlapping
// (the UV area adds up to what the triangles cover on a 512² grid, within 5 %).
bool usableUvAtlas(const std::vector<glm::vec2>& uvs, const std::vector<glm::uvec3>& triangles);

Hierarchy buildHierarchy(const scene::Geometry& geometry, const std::vector<scene::Surfel>& restSurfels);

}  // namespace ivgi::gi

#pragma once
// The triangles depth maps are drawn from. A map cannot resolve a surface finer than its texels, so
// each rigid instance is drawn as simplified as the frame's lights allow: its surface at a ladder of
// errors (meshoptimizer's edge collapses), the level taken per frame from the error a caller names.
// The simplified triangles keep the instance's own vertices, so the frame's animated positions place
// them. Skinned and morphed instances bend, so they are drawn as planarFaces leaves them. An
// instance whose material's alpha takes surface away (alphaMode MASK or BLEND) is drawn as given: its texture
// coordinates place the cuts.
#include <cstdint>
#include <map>
#include <vector>

#include "engine/scene/geometry.h"

namespace ivgi::scene {

class MapMeshes {
 public:
  // One drawn instance of `triangles` (of `geometry`).
  struct Part {
    uint32_t instance = 0;
    bool rigid = false;                           // neither skinned nor morphed
    bool cutout = false;                          // its alpha cuts it (MASK, BLEND): drawn as given
    glm::vec3 centre{0.0f};                       // the mean of its vertices, in its primitive's space,
    float radius = 0.0f;                          // and the farthest of them from it
    std::vector<Triangle> exact;                  // planarFaces
    std::vector<uint32_t> corners;                // the triangles' corners as indices of `positions`:
    std::vector<glm::vec3> positions;             // the part's vertices, one per position
    std::vector<uint32_t> vertexAt;               // a geometry vertex at each of `positions`
    uint32_t material = 0;                        // carried by the simplified triangles (the maps draw none)
    std::map<int, std::vector<Triangle>> levels;  // simplified, by level, as first asked for
  };

  MapMeshes(const Geometry& geometry, const std::vector<Triangle>& triangles);

  const std::vector<Part>& parts() const { return parts_; }
  // Triangles of every part as drawn exactly: the most draw() returns; and as given.
  size_t exactCount() const { return exactCount_; }
  // Whether some part's material cuts its surface away, which the raster then reads.
  bool cutouts() const { return cutouts_; }
  size_t triangleCount() const { return triangleCount_; }

  // The triangles, each part drawn within `errors[p]` (in its primitive's space; 0: exactly): at
  // the coarsest level of the ladder whose error does not exceed it and that has fewer triangles
  // than the exact surface.
  std::vector<Triangle> draw(const std::vector<float>& errors);

  // The ladder: level k's error is the part's radius × 2^-k, for k from kCoarsestLevel to
  // kFinestLevel; an error under the finest level's draws the part exactly. Every vertex of a part
  // lies within its level's error of the level's triangles (measured as each level is made).
  static constexpr int kCoarsestLevel = 2, kFinestLevel = 16;
  static int levelWithin(const Part& part, float error);  // kFinestLevel + 1: exactly

 private:
  const std::vector<Triangle>& level(Part& part, int level);

  std::vector<Part> parts_;
  size_t exactCount_ = 0, triangleCount_ = 0;
  bool cutouts_ = false;
};

// The distance from p to the triangle abc (to its nearest point, found by the regions of its plane).
double distanceToTriangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c);

}  // namespace ivgi::scene

#pragma once
// Fewer triangles for depth maps: a surface meshed finer than its shape (a wall as a grid, a face the
// tessellation split for the surfels) is drawn as its shape.
#include <vector>

#include "engine/scene/geometry.h"

namespace ivgi::scene {

// The surfaces of `triangles` (of `geometry`) in as few triangles as their shape takes: where the
// triangles of a rigid instance that lie in one plane and meet edge to edge make one convex polygon
// without holes, the polygon's fan stands for them, wound as they were. Its corners are vertices of
// those triangles, so the frame's animated positions place it. Skinned and morphed instances bend,
// and keep their triangles; so do polygons that are not convex or not simply bounded.
std::vector<Triangle> planarFaces(const Geometry& geometry, const std::vector<Triangle>& triangles);

}  // namespace ivgi::scene

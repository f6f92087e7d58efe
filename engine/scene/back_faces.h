#pragma once
// The backs of open double-sided surfaces (docs/design.md §2.1). glTF lights a double-sided
// material's back with its normal reversed. iv's and ar's surfels are one-sided, so where such a
// surface is open (a sheet, a lampshade, a leaf) its back gets surfels and triangles of its own: a
// copy of the faces turned the other way. Only the faces whose backs see out are copied: the inside
// of a nearly closed surface (a head whose eyes leave gaps) and the outside of a room that nothing
// lights are never lit and never seen.
#include <vector>

#include "engine/scene/scene.h"
#include "engine/scene/triangle_rays.h"
#include "shaders/interface.h"

namespace ivgi::scene {

// Whether light comes from open space, where rays that meet nothing go: an environment or a
// directional light lights the scene.
enum class OpenSpace { Lit, Dark };

// Which faces' backs see out, among a scene's faces at rest. A back sees out where some of the rays
// from just behind its face, spread over the hemisphere behind it, meets another object's surface
// or leaves the scene for lit open space, or where a light lies behind it (a point or spot light, a
// point on an emitter). The rays pass
// through the faces of the face's own object that they meet from the front (a fold, a part inside
// it); meeting the back of one, they are enclosed. A face's front is the side its vertex normals
// give (without normals, its corners' counter-clockwise side).
class BackExposure {
 public:
  // `positions`: the scene's vertices at rest, world space; `triangles`: its faces (gpu::Triangle),
  // and `objectOf` each one's object (faces of one object enclose together); `lights`: where its
  // point and spot lights are, and points on its emitters.
  BackExposure(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
               const std::vector<gpu::Triangle>& triangles, std::vector<uint32_t> objectOf,
               std::vector<glm::vec3> lights, OpenSpace openSpace);

  // Whether the back of face t sees out: a light, or through kLeastSeenOut of the kRays rays, an
  // eighth of its hemisphere (cosine-weighted). Through less, a gap passes a back little light and
  // shows it to few places: the inside of Blender's Suzanne, seen out through the gaps around her
  // eyes by 90 of her 62,976 faces, one ray each, would cost the room's animated frame a tenth.
  bool exposed(uint32_t t) const;
  // Of the kRays rays behind face t, how many see out (all where a light lies behind it).
  int seenOut(uint32_t t) const;
  static constexpr int kRays = 16, kLeastSeenOut = 2;

 private:
  // Where a ray from `origin`, behind face t, along unit d ends before `far`: past it (or in open
  // space), on another object, or on the inside of t's own.
  enum class Reach { Far, OtherObject, Enclosed };
  Reach reach(uint32_t t, glm::vec3 origin, glm::vec3 d, float far) const;

  std::vector<glm::vec3> front_, centroid_;
  std::vector<float> size_;
  std::vector<uint32_t> objectOf_;
  std::vector<glm::vec3> lights_;
  OpenSpace openSpace_;
  TriangleRays rays_;  // watertight: no ray slips out of a closed surface between two faces
};

// The back of p's triangles where `copied` says so: their vertices with reversed normals (and
// normal morph deltas), the triangles wound the other way, on material `material`. Empty where none
// is copied.
Primitive backOf(const Primitive& p, const std::vector<bool>& copied, int material);

}  // namespace ivgi::scene

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

// Which faces' backs see out, among a scene's faces at rest. A back sees out where a light lies
// behind its face (a point or spot light, a point on an emitter) and a ray reaches it, or where 2 of
// 16 rays from just behind the face, cosine-spread over the hemisphere behind it, meet another
// object's surface or leave the scene for lit open space. Through less than that eighth of its
// hemisphere, a gap passes a back little light and shows it to few places
// (docs/notes/gltf-conformance.md). The rays pass through the faces of the face's own object that
// they meet from the front (a fold, a part inside it); meeting the back of one, they are enclosed.
// A face's front is gpu::faceFront's.
class BackExposure {
 public:
  // `world`: the scene's vertices at rest; `triangles`: its faces, and `objectOf` each one's object
  // (faces of one object enclose together); `lights`: where its point and spot lights are, and
  // points on its emitters.
  BackExposure(const std::vector<gpu::WorldVertex>& world, const std::vector<gpu::Triangle>& triangles,
               std::vector<uint32_t> objectOf, std::vector<glm::vec3> lights, OpenSpace openSpace,
               TriangleRays::CutAway cutAway = {});

  // Whether the back of face t sees out.
  bool exposed(uint32_t t) const;

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

#pragma once
// Rays against a triangle mesh, through Embree: the path tracer's scene and the back faces'
// exposure (back_faces.h) are each one.
#include <embree3/rtcore.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "shaders/interface.h"

namespace ivgi::scene {

class TriangleRays {
 public:
  // Whether a triangle is cut away (alphaMode MASK or BLEND) at the barycentric weights (u, v) of its
  // second and third corners for a ray whose own uniform number in [0, 1) is `sample`: rays pass
  // there.
  using CutAway = std::function<bool(uint32_t triangle, glm::vec2 uv, float sample)>;

  // The first `count` of `triangles`, over the vertices `world`; `watertight`: no ray passes between
  // two faces that share an edge (Embree's robust mode, somewhat slower). Rays pass through the
  // points `cutAway` names, where one is given.
  TriangleRays(const std::vector<gpu::WorldVertex>& world, const std::vector<gpu::Triangle>& triangles, size_t count,
               bool watertight, CutAway cutAway = {});
  ~TriangleRays();
  TriangleRays(const TriangleRays&) = delete;
  TriangleRays& operator=(const TriangleRays&) = delete;

  struct Hit {
    uint32_t triangle;
    float t;       // along the ray, in units of its direction
    glm::vec2 uv;  // the barycentric weights of the triangle's second and third corners
  };
  // The nearest face the ray from `origin` along `d` meets between tnear and tfar.
  std::optional<Hit> nearest(glm::vec3 origin, glm::vec3 d, float tnear, float tfar) const;
  // Whether it meets any face before tfar.
  bool occluded(glm::vec3 origin, glm::vec3 d, float tfar) const;

 private:
  CutAway cutAway_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace ivgi::scene

#pragma once
// How much a surface point's material reflects: its BRDF's parameters (shaders/interface/brdf.h)
// from the material and its textures, and the directional albedo of glTF's specular layer, which
// weighs the dielectric's base so that a surface reflects no more than arrives (integrated once per
// process over the distribution's visible normals, tabulated by the direction's cosine and the
// roughness).
#include <glm/glm.hpp>

#include <vector>

#include "shaders/interface.h"

namespace ivgi::scene {

class SpecularAlbedo {
 public:
  static const SpecularAlbedo& table();  // computed on first use

  // (A, B) toward a direction at cos θ = mu for a roughness (gpu::layerAlbedo's table argument),
  // bilinear between the nodes.
  glm::vec2 at(float mu, float roughness) const;
  // Their cosine-weighted means over the hemisphere, 2 ∫ (A, B) μ dμ, at a roughness.
  glm::vec2 meanAt(float roughness) const;

  // The fraction of uniform incident light a material reflects toward a direction at cos θ = mu,
  // and over the hemisphere (what a diffuse solver's surface reflects: its base colour where the
  // material is Lambertian).
  glm::vec3 reflectance(const gpu::SurfaceBrdf& m, float mu) const;
  glm::vec3 meanReflectance(const gpu::SurfaceBrdf& m) const;

  // The nodes, row by roughness (gpu::kAlbedoTableSize each), then the means per roughness.
  const std::vector<glm::vec2>& values() const { return values_; }

 private:
  SpecularAlbedo();
  std::vector<glm::vec2> values_;
};

// The BRDF at a point: the material's factors times the base colour (its texture and vertex colour
// applied) and its metallic-roughness texel (B metal, G roughness).
gpu::SurfaceBrdf surfaceBrdf(const gpu::Material& m, glm::vec3 base, glm::vec4 metallicRoughness);

// What a surface point's BRDF needs of the table toward the view: its base weight's parts.
struct LayerAlbedo {
  float towardView = 0.0f, mean = 0.0f;  // E(μ_v), Ē
  LayerAlbedo() = default;
  LayerAlbedo(const gpu::SurfaceBrdf& m, float cosView);
  // The base's weight for light from a direction at cos θ = cosLight.
  float baseWeight(const gpu::SurfaceBrdf& m, float cosLight) const;
};

}  // namespace ivgi::scene

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

  // The nodes (row by roughness, gpu::kAlbedoTableSize each, then the means per roughness) as the
  // shaders read them (shaders/common/specular_albedo.glsl): each beside the next in its row (the
  // means: the next mean), so that a bilinear lookup fetches two texels, not four.
  std::vector<glm::vec4> texels() const;

 private:
  SpecularAlbedo();
  std::vector<glm::vec2> values_;
};

// How far from even a material's specular lobe sends the light it reflects: over light arriving
// from cosine-weighted directions, the mean of ∫ |π f(l, w) − a(l)| cos θ_w dω_w / π, the share of
// the arriving light that leaving evenly (a(l) the lobe's albedo toward l) would put elsewhere than
// the lobe does. The largest over the colour channels; 0 for a Lambertian material.
float lobeDeviation(const gpu::SurfaceBrdf& m);

// Where sending a lobe's light evenly, as the base's, misplaces less than this share of the light
// arriving (lobeDeviation), the solvers do so: a rough dielectric's lobe (0.4–0.6 % at roughness 1) is
// wide and reflects a few per cent. Polished and metallic lobes lie far above it (a dielectric's at
// roughness 0.8 1.5 %, at 0.5 6.5 %; a metal's at roughness 1 6.8 %).
constexpr float kEvenLobeDeviation = 0.01f;
// Whether m's lobe deviates that far; integrated only where its mean albedo, at least half the
// deviation, leaves it in doubt.
bool sendsLobeByDirection(const gpu::SurfaceBrdf& m);

// How far from even a material's diffuse base sends the light it reflects: under a dielectric's
// layer it leaves toward exit cosine μ as (1 − E(μ))/(1 − Ē) of even (gpu::baseWeight), so over
// cosine-weighted exit directions it puts the share ρ · mean |(1 − E(μ))/(1 − Ē) − 1| of the light
// arriving elsewhere than evenly (ρ the base's reflectance, largest channel). 0 for a Lambertian or
// metallic material.
float baseDeviation(const gpu::SurfaceBrdf& m);
// Whether m's base deviates as far as kEvenLobeDeviation.
bool sendsBaseByDirection(const gpu::SurfaceBrdf& m);

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

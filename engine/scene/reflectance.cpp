#include "engine/scene/reflectance.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/parallel.h"

namespace ivgi::scene {

namespace {

constexpr int kSize = int(gpu::kAlbedoTableSize);
constexpr int kStrata = 64;  // visible normals per node along each of their two coordinates

// (A, B) at one node: the mean over stratified visible normals of G2/G1 (the estimator of the
// specular lobe's albedo when its normals are drawn from D_v), split by Schlick's weight.
glm::vec2 integrate(float mu, float roughness) {
  const glm::vec3 v(std::sqrt(std::max(0.0f, 1.0f - mu * mu)), 0.0f, mu);
  const float alpha = gpu::alphaOf(roughness), a2 = alpha * alpha;
  glm::dvec2 sum(0.0);
  for (int i = 0; i < kStrata; ++i)
    for (int k = 0; k < kStrata; ++k) {
      const glm::vec3 h = gpu::sampleVisibleNormal(v, alpha, (i + 0.5f) / kStrata, (k + 0.5f) / kStrata);
      const float vh = glm::dot(v, h);
      const glm::vec3 l = glm::reflect(-v, h);
      if (l.z <= 0.0f || vh <= 0.0f) continue;
      const double g = 4.0 * gpu::smithVisibility(l.z, v.z, a2) * l.z * v.z / gpu::smithG1(v.z, a2);
      const double w = gpu::schlickWeight(vh);
      sum += glm::dvec2((1.0 - w) * g, w * g);
    }
  return glm::vec2(sum / double(kStrata * kStrata));
}

}  // namespace

SpecularAlbedo::SpecularAlbedo() {
  values_.resize(size_t(kSize) * kSize + kSize);
  parallelFor(kSize, [&](size_t row) {
    const int j = int(row);
    glm::dvec2 mean(0.0);  // 2 ∫ E μ dμ = 4 ∫ E s³ ds with μ = s²
    for (int i = 0; i < kSize; ++i) {
      const double s = (i + 0.5) / kSize;
      const double t = double(j) / double(kSize - 1);
      values_[size_t(j) * kSize + i] = integrate(float(s * s), float(t * t));
      mean += 4.0 * glm::dvec2(values_[size_t(j) * kSize + i]) * (s * s * s) / double(kSize);
    }
    values_[size_t(kSize) * kSize + j] = glm::vec2(mean);
  });
}

const SpecularAlbedo& SpecularAlbedo::table() {
  static const SpecularAlbedo computed;
  return computed;
}

std::vector<glm::vec4> SpecularAlbedo::texels() const {
  std::vector<glm::vec4> texels(values_.size());
  for (size_t i = 0; i < values_.size(); ++i)
    texels[i] = glm::vec4(values_[i], values_[std::min(i + 1, values_.size() - 1)]);
  return texels;
}

glm::vec2 SpecularAlbedo::at(float mu, float roughness) const {
  const glm::vec4 c = gpu::albedoTableCell(mu, roughness);
  const size_t x0 = size_t(c.x), y0 = size_t(c.y);
  auto node = [&](size_t i, size_t j) { return values_[j * kSize + i]; };
  return glm::mix(glm::mix(node(x0, y0), node(x0 + 1, y0), c.z), glm::mix(node(x0, y0 + 1), node(x0 + 1, y0 + 1), c.z),
                  c.w);
}

glm::vec2 SpecularAlbedo::meanAt(float roughness) const {
  const glm::vec4 c = gpu::albedoTableCell(1.0f, roughness);
  const glm::vec2* means = &values_[size_t(kSize) * kSize];
  return glm::mix(means[size_t(c.y)], means[size_t(c.y) + 1], c.w);
}

glm::vec3 SpecularAlbedo::reflectance(const gpu::SurfaceBrdf& m, float mu) const {
  return gpu::reflectanceOf(m, at(mu, std::sqrt(m.alpha)));
}

glm::vec3 SpecularAlbedo::meanReflectance(const gpu::SurfaceBrdf& m) const {
  return gpu::reflectanceOf(m, meanAt(std::sqrt(m.alpha)));
}

float lobeDeviation(const gpu::SurfaceBrdf& m) {
  if (gpu::isLambertian(m)) return 0.0f;
  // Cosine-weighted strata of the incident and the exit directions (μ = √u); the lobe is isotropic,
  // so the light arrives in one plane. A lobe narrower than the exit strata is undersampled, but its
  // deviation then stays near its albedo, far above kEvenLobeDeviation for any lobe that narrow.
  constexpr int kLight = 24, kExitMu = 48, kExitPhi = 96;
  glm::dvec3 sum(0.0);
  std::vector<glm::vec3> sent;  // π f(l, w) at each exit stratum
  sent.reserve(kExitMu * kExitPhi);
  for (int i = 0; i < kLight; ++i) {
    const float mu = std::sqrt((i + 0.5f) / kLight);
    const glm::vec3 l(std::sqrt(1.0f - mu * mu), 0.0f, mu);
    sent.clear();
    glm::dvec3 albedo(0.0);
    for (int j = 0; j < kExitMu; ++j)
      for (int k = 0; k < kExitPhi; ++k) {
        const float c = std::sqrt((j + 0.5f) / kExitMu), phi = 2.0f * gpu::kPi * (k + 0.5f) / kExitPhi;
        const float s = std::sqrt(1.0f - c * c);
        sent.push_back(gpu::kPi * gpu::evalBrdf(m, l, glm::vec3(s * std::cos(phi), s * std::sin(phi), c), 0.0f));
        albedo += glm::dvec3(sent.back());
      }
    albedo /= double(sent.size());
    glm::dvec3 deviation(0.0);
    for (const glm::vec3& f : sent) deviation += glm::abs(glm::dvec3(f) - albedo);
    sum += deviation / double(sent.size());
  }
  const glm::dvec3 mean = sum / double(kLight);
  return float(std::max(mean.x, std::max(mean.y, mean.z)));
}

bool sendsLobeByDirection(const gpu::SurfaceBrdf& m) {
  // Toward each light the deviation is at most ∫ π f cos dω / π + a = 2a: at most twice the mean albedo.
  const glm::vec3 albedo = gpu::lobeReflectanceOf(m, SpecularAlbedo::table().meanAt(std::sqrt(m.alpha)));
  if (2.0f * std::max(albedo.x, std::max(albedo.y, albedo.z)) < kEvenLobeDeviation) return false;
  return lobeDeviation(m) >= kEvenLobeDeviation;
}

float baseDeviation(const gpu::SurfaceBrdf& m) {
  if (gpu::isLambertian(m) || m.metallic >= 1.0f) return 0.0f;
  const SpecularAlbedo& t = SpecularAlbedo::table();
  const float roughness = std::sqrt(m.alpha);
  const glm::vec2 mean = t.meanAt(roughness);
  const float even = std::max(1.0f - gpu::layerAlbedo(m, mean), 1e-6f);
  constexpr int kExitMu = 256;  // cosine-weighted strata (μ = √u)
  double sum = 0.0;
  for (int j = 0; j < kExitMu; ++j) {
    const float mu = std::sqrt((j + 0.5f) / kExitMu);
    sum += std::abs((1.0f - gpu::layerAlbedo(m, t.at(mu, roughness))) / even - 1.0f);
  }
  return gpu::maxOf(gpu::baseReflectanceOf(m, mean)) * float(sum / kExitMu);
}

bool sendsBaseByDirection(const gpu::SurfaceBrdf& m) { return baseDeviation(m) >= kEvenLobeDeviation; }

gpu::SurfaceBrdf surfaceBrdf(const gpu::Material& m, glm::vec3 base, glm::vec4 metallicRoughness) {
  gpu::SurfaceBrdf out{};
  out.base = glm::vec4(base, 0.0f);
  out.specular = m.specular;
  out.metallic = m.metallic * metallicRoughness.b;
  out.alpha = gpu::alphaOf(m.roughness * metallicRoughness.g);
  return out;
}

LayerAlbedo::LayerAlbedo(const gpu::SurfaceBrdf& m, float cosView) {
  const SpecularAlbedo& t = SpecularAlbedo::table();
  const float roughness = std::sqrt(m.alpha);
  towardView = gpu::layerAlbedo(m, t.at(cosView, roughness));
  mean = gpu::layerAlbedo(m, t.meanAt(roughness));
}

float LayerAlbedo::baseWeight(const gpu::SurfaceBrdf& m, float cosLight) const {
  const float towardLight = gpu::layerAlbedo(m, SpecularAlbedo::table().at(cosLight, std::sqrt(m.alpha)));
  return gpu::baseWeight(towardLight, towardView, mean);
}

}  // namespace ivgi::scene

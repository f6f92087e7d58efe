#include "engine/scene/back_faces.h"

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <unordered_map>

#include "shaders/interface.h"

namespace ivgi::scene {

namespace {

constexpr int kPassesThrough = 8;  // fronts a ray may pass through before it counts as enclosed
constexpr int kRays = 16;          // rays behind a face
constexpr int kLeastSeenOut = 2;   // of them, that must see out: an eighth of the hemisphere

// Directions about +z, cosine-weighted: a Hammersley set.
std::vector<glm::vec3> hemisphere() {
  std::vector<glm::vec3> out;
  for (int i = 0; i < kRays; ++i) {
    uint32_t bits = uint32_t(i);
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    const float u = (float(i) + 0.5f) / float(kRays), v = float(bits) * 2.3283064365386963e-10f;
    const float r = std::sqrt(u), phi = 2.0f * glm::pi<float>() * v;
    out.emplace_back(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(1.0f - u, 0.0f)));
  }
  return out;
}

}  // namespace

BackExposure::BackExposure(const std::vector<gpu::WorldVertex>& world, const std::vector<gpu::Triangle>& triangles,
                           std::vector<uint32_t> objectOf, std::vector<glm::vec3> lights, OpenSpace openSpace,
                           TriangleRays::CutAway cutAway)
    : objectOf_(std::move(objectOf)),
      lights_(std::move(lights)),
      openSpace_(openSpace),
      rays_(world, triangles, triangles.size(), true, std::move(cutAway)) {
  front_.resize(triangles.size());
  centroid_.resize(triangles.size());
  size_.resize(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    const gpu::Triangle& x = triangles[t];
    const glm::vec3 a(world[x.v0].position), b(world[x.v1].position), c(world[x.v2].position);
    const glm::vec3 n = gpu::faceFront(
        a, b, c, glm::vec3(world[x.v0].normal) + glm::vec3(world[x.v1].normal) + glm::vec3(world[x.v2].normal),
        (x.material & gpu::kFlatShaded) != 0u);
    const float length = glm::length(n);
    centroid_[t] = (a + b + c) / 3.0f;
    size_[t] = glm::length(b - a) + glm::length(c - a);
    if (length > 0.0f && std::isfinite(length)) front_[t] = n / length;  // degenerate: none, never exposed
  }
}

BackExposure::Reach BackExposure::reach(uint32_t t, glm::vec3 origin, glm::vec3 d, float far) const {
  float from = 0.0f;
  for (int pass = 0; pass < kPassesThrough; ++pass) {
    const std::optional<TriangleRays::Hit> hit = rays_.nearest(origin, d, from, far);
    if (!hit) return Reach::Far;
    if (objectOf_[hit->triangle] != objectOf_[t]) return Reach::OtherObject;
    if (glm::dot(front_[hit->triangle], d) > 0.0f) return Reach::Enclosed;  // its own inside
    from = hit->t * (1.0f + 1e-5f) + 1e-6f * size_[t];                      // its own front: through it
  }
  return Reach::Enclosed;
}

bool BackExposure::exposed(uint32_t t) const {
  if (front_[t] == glm::vec3(0.0f)) return false;
  const glm::vec3 back = -front_[t], origin = centroid_[t] + 1e-4f * size_[t] * back;
  for (const glm::vec3& light : lights_) {
    const glm::vec3 toward = light - origin;
    const float distance = glm::length(toward);
    if (glm::dot(toward, back) > 0.0f && distance > 0.0f &&
        reach(t, origin, toward / distance, distance) != Reach::Enclosed)
      return true;
  }
  int out = 0;
  static const std::vector<glm::vec3> directions = hemisphere();
  glm::vec3 t1, t2;
  gpu::tangentFrame(back, t1, t2);
  for (size_t k = 0; k < directions.size() && out < kLeastSeenOut; ++k) {
    const glm::vec3& local = directions[k];
    const Reach r = reach(t, origin, local.x * t1 + local.y * t2 + local.z * back, 3.4e38f);
    out += r == Reach::OtherObject || (r == Reach::Far && openSpace_ == OpenSpace::Lit) ? 1 : 0;
  }
  return out >= kLeastSeenOut;
}

Primitive backOf(const Primitive& p, const std::vector<bool>& copied, int material) {
  Primitive back;
  back.material = material;
  back.targets.resize(p.targets.size());
  std::unordered_map<uint32_t, uint32_t> copyOf;  // p's vertex → the back's
  auto vertex = [&](uint32_t v) {
    auto [at, added] = copyOf.try_emplace(v, uint32_t(back.positions.size()));
    if (!added) return at->second;
    back.positions.push_back(p.positions[v]);
    if (!p.normals.empty()) back.normals.push_back(-p.normals[v]);
    if (!p.uvs.empty()) back.uvs.push_back(p.uvs[v]);
    if (!p.uvs1.empty()) back.uvs1.push_back(p.uvs1[v]);
    if (!p.colors.empty()) back.colors.push_back(p.colors[v]);
    if (!p.joints.empty()) back.joints.push_back(p.joints[v]), back.weights.push_back(p.weights[v]);
    for (size_t k = 0; k < p.targets.size(); ++k) {
      if (!p.targets[k].positions.empty()) back.targets[k].positions.push_back(p.targets[k].positions[v]);
      if (!p.targets[k].normals.empty()) back.targets[k].normals.push_back(-p.targets[k].normals[v]);
    }
    return at->second;
  };
  for (size_t t = 0; t < copied.size(); ++t)
    if (copied[t]) {
      const uint32_t a = vertex(p.indices[3 * t]), b = vertex(p.indices[3 * t + 1]), c = vertex(p.indices[3 * t + 2]);
      back.indices.insert(back.indices.end(), {a, c, b});
    }
  return back;
}

}  // namespace ivgi::scene

#pragma once
// Host twins of the definitions in shaders/common.glsl that are not plain data layouts.
#include <glm/glm.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "engine/scene/camera.h"
#include "engine/scene/geometry.h"

namespace ivgi::gi {

constexpr uint64_t kEmptyVisibility = ~0ull;

inline uint64_t packDepthKey(float depth, uint32_t id) { return uint64_t(std::bit_cast<uint32_t>(depth)) << 32 | id; }
inline uint32_t keyId(uint64_t key) { return uint32_t(key & 0xFFFFFFFFu); }
inline float keyDepth(uint64_t key) { return std::bit_cast<float>(uint32_t(key >> 32)); }

// A static leaf link's bin and covered solid angle (in 1/kCoverageUnit of the bin's, capped at the bin).
constexpr uint32_t kCoverageUnit = 65536u;
inline uint32_t packStaticBin(uint32_t bin, uint32_t covered) { return bin | std::min(covered, kCoverageUnit) << 15; }
inline uint32_t staticBinOf(uint32_t packed) { return packed & 0x7FFFu; }
inline uint32_t staticCoverageOf(uint32_t packed) { return packed >> 15; }

// std430 / push-constant layout of `Camera` in common.glsl.
struct GpuCamera {
  glm::vec4 origin;   // w: znear
  glm::vec4 right;    // scaled by tan(half horizontal fov)
  glm::vec4 up;       // scaled by tan(half vertical fov)
  glm::vec4 forward;  // w: zfar (0: none)
};

inline GpuCamera gpuCamera(const scene::CameraView& v, float aspect) {
  float ty = std::tan(0.5f * v.yfov), tx = ty * aspect;
  return {glm::vec4(v.origin, v.znear), glm::vec4(v.right * tx, 0.0f), glm::vec4(v.up * ty, 0.0f), glm::vec4(v.forward, v.zfar)};
}

// Direction of the camera ray through sample position `s` of an image `size` samples large.
inline glm::vec3 cameraRay(const GpuCamera& c, glm::vec2 s, glm::uvec2 size) {
  glm::vec2 ndc(2.0f * s.x / float(size.x) - 1.0f, 1.0f - 2.0f * s.y / float(size.y));
  return glm::vec3(c.forward) + ndc.x * glm::vec3(c.right) + ndc.y * glm::vec3(c.up);
}

// ---- Direction bins and form factors: the twins of common.glsl ----

constexpr float kPi = 3.14159265358979f;

inline uint32_t binOf(glm::vec3 d, uint32_t n) {
  glm::vec3 a = glm::abs(d);
  uint32_t axis = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
  float major = axis == 0u ? d.x : (axis == 1u ? d.y : d.z);
  glm::vec2 uv = axis == 0u ? glm::vec2(d.y, d.z) : (axis == 1u ? glm::vec2(d.z, d.x) : glm::vec2(d.x, d.y));
  uv /= std::abs(major);
  glm::uvec2 ij = glm::uvec2(glm::clamp(glm::floor((uv + 1.0f) * 0.5f * float(n)), glm::vec2(0.0f), glm::vec2(float(n - 1u))));
  uint32_t face = 2u * axis + (major < 0.0f ? 1u : 0u);
  return face * n * n + ij.y * n + ij.x;
}

inline glm::vec3 faceDirection(uint32_t face, glm::vec2 uv) {
  float s = (face & 1u) == 0u ? 1.0f : -1.0f;
  uint32_t axis = face / 2u;
  if (axis == 0u) return {s, uv.x, uv.y};
  if (axis == 1u) return {uv.y, s, uv.x};
  return {uv.x, uv.y, s};
}

inline glm::vec3 binDirection(uint32_t b, uint32_t n) {
  uint32_t face = b / (n * n), r = b % (n * n);
  return faceDirection(face, (glm::vec2(float(r % n), float(r / n)) + 0.5f) / float(n) * 2.0f - 1.0f);
}

inline uint32_t binOfCell(uint32_t face, glm::ivec2 cell, uint32_t n) {
  if (cell.x >= 0 && cell.y >= 0 && cell.x < int(n) && cell.y < int(n)) return face * n * n + uint32_t(cell.y) * n + uint32_t(cell.x);
  return binOf(faceDirection(face, (glm::vec2(cell) + 0.5f) / (0.5f * float(n)) - 1.0f), n);
}

inline float cubeAreaIntegral(float u, float v) { return std::atan2(u * v, std::sqrt(u * u + v * v + 1.0f)); }

inline float binSolidAngle(uint32_t b, uint32_t n) {
  uint32_t r = b % (n * n);
  float step = 2.0f / float(n);
  float u0 = -1.0f + float(r % n) * step, v0 = -1.0f + float(r / n) * step, u1 = u0 + step, v1 = v0 + step;
  return cubeAreaIntegral(u1, v1) - cubeAreaIntegral(u0, v1) - cubeAreaIntegral(u1, v0) + cubeAreaIntegral(u0, v0);
}

using scene::tangentFrame;  // the surfels' rectangles are laid out in it

inline float formFactor(float senderArea, float cosSender, float cosReceiver, float distance2) {
  return senderArea * std::max(cosSender, 0.0f) * std::max(cosReceiver, 0.0f) / (kPi * distance2 + senderArea);
}

inline constexpr uint64_t kFringeKey = 0x8000000000000000ull;
inline uint64_t packLinkKey(float distance2, uint32_t sender, bool fringe) {
  return packDepthKey(distance2, sender) | (fringe ? kFringeKey : 0ull);
}
inline float linkKeyDepth(uint64_t key) { return keyDepth(key & ~kFringeKey); }

// ---- Punctual lights (KHR_lights_punctual) ----

struct GpuLight {  // std430 `PunctualLight` in common.glsl
  glm::vec4 position;   // w: 0 directional, 1 point, 2 spot
  glm::vec4 direction;  // where the light points; w: range (0: none)
  glm::vec4 intensity;  // rgb: colour × intensity, radiometric
  glm::vec4 cone;       // cos outer, cos inner
};

// lightFalloff() of common.glsl: irradiance per unit intensity on a surface facing the light at p
// (1/d², the range window, the spot cone); `toLight` (not normalised) and its squared length
// (3.4e38 for a directional light) come back.
inline float lightFalloff(const GpuLight& light, glm::vec3 p, glm::vec3& toLight, float& dist2) {
  dist2 = 3.4e38f;
  if (light.position.w == 0.0f) {
    toLight = -glm::vec3(light.direction);
    return 1.0f;
  }
  toLight = glm::vec3(light.position) - p;
  dist2 = glm::dot(toLight, toLight);
  if (dist2 <= 0.0f) return 0.0f;
  float falloff = 1.0f / dist2;
  if (light.direction.w > 0.0f) {
    float window = std::clamp(1.0f - std::pow(std::sqrt(dist2) / light.direction.w, 4.0f), 0.0f, 1.0f);
    falloff *= window * window;
  }
  if (light.position.w == 2.0f) {
    float c = glm::dot(glm::normalize(-toLight), glm::vec3(light.direction));
    float t = std::clamp((c - light.cone.x) / std::max(light.cone.y - light.cone.x, 1e-6f), 0.0f, 1.0f);
    falloff *= t * t * (3.0f - 2.0f * t);  // GLSL smoothstep
  }
  return falloff;
}

}  // namespace ivgi::gi

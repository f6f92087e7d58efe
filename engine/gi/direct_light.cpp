#include "engine/gi/direct_light.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "engine/core/errors.h"
#include "engine/gi/pass.h"
#include "engine/image/colour.h"
#include "engine/scene/planar_faces.h"

namespace ivgi::gi {

namespace {

// The views of the depth maps of `settings` (light_views): a cube an emitter sample and a punctual
// light, one map an environment direction.
uint32_t viewCount(const DirectLightSettings& s, uint32_t samples, uint32_t environmentDirections) {
  return (samples + s.punctualLights) * gpu::kCubeFaces + environmentDirections;
}

// Their bytes: 32-bit depths.
uint64_t depthBytes(const DirectLightSettings& s, uint32_t views) {
  return uint64_t(views) * s.resolution * s.resolution * sizeof(uint32_t);
}

// A triangle's area at rest, in its primitive's own space.
double restArea(const scene::Geometry& g, const scene::Triangle& tri) {
  const glm::dvec3 a = g.vertices[tri.v0].position, b = g.vertices[tri.v1].position, c = g.vertices[tri.v2].position;
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

// The luminance of a triangle's emission factor (zero: it does not emit).
double emittedLuminance(const scene::Geometry& g, const scene::Triangle& tri) {
  return image::luminance(glm::dvec3(glm::vec3(g.materials[tri.material & ~gpu::kFlatShaded].emission)));
}

}  // namespace

void validate(const DirectLightSettings& s) {
  if (s.samples < 1 || s.samples > 4096)
    throw SettingsError("--light-samples " + std::to_string(s.samples) + ": must be 1 to 4096");
  if (s.environmentDirections > 4096)
    throw SettingsError("--env-directions " + std::to_string(s.environmentDirections) + ": must be 0 to 4096");
  if (s.resolution < 8 || s.resolution > 4096)
    throw SettingsError("--shadow-map " + std::to_string(s.resolution) + ": must be 8 to 4096");
}

std::vector<gpu::PunctualLight> DirectLightSettings::environmentLights() const {
  std::vector<gpu::PunctualLight> lights;
  if (!environment || environmentDirections == 0) return lights;
  for (const scene::Environment::Direction& d : environment->sampleDirections(environmentDirections))
    lights.push_back({.position = glm::vec4(0.0f, 0.0f, 0.0f, gpu::kLightDirectional),
                      .direction = glm::vec4(-d.towardSky, 0.0f),
                      .intensity = glm::vec4(d.irradiance, 0.0f),
                      .cone = glm::vec4(0.0f)});
  return lights;
}

double emissiveAreaShare(const scene::Geometry& g) {
  double emitting = 0, total = 0;
  for (const scene::Triangle& tri : g.triangles) {
    const double area = restArea(g, tri);
    total += area;
    if (emittedLuminance(g, tri) > 0) emitting += area;
  }
  return total > 0 ? emitting / total : 0.0;
}

std::vector<gpu::EmitterSample> emitterSamples(const scene::Geometry& g, uint32_t count) {
  // Each triangle's power at rest, in the primitive's own space: only the ratios between triangles
  // matter, and the frame's weight takes the triangle's area as it is then.
  std::vector<double> power(g.triangles.size(), 0.0);
  double total = 0;
  for (size_t t = 0; t < g.triangles.size(); ++t) {
    const double luminance = emittedLuminance(g, g.triangles[t]);
    if (!(luminance > 0)) continue;
    power[t] = restArea(g, g.triangles[t]) * luminance;
    total += power[t];
  }
  std::vector<gpu::EmitterSample> samples;
  if (!(total > 0) || count == 0) return samples;
  constexpr double kGolden = 0.6180339887498949;
  double before = 0;  // the power of the triangles before t
  size_t t = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const double target = (i + 0.5) / count * total;
    while (t + 1 < power.size() && (power[t] <= 0 || before + power[t] < target)) before += power[t++];
    const double u = std::clamp((target - before) / power[t], 0.0, 1.0), v = std::fmod((i + 0.5) * kGolden, 1.0);
    const double root = std::sqrt(u);  // uniform over the triangle
    const double area = restArea(g, g.triangles[t]);
    // pdf per area at rest: (power[t] / total) / area; the weight is its inverse over the count, per
    // unit of the triangle's area.
    samples.push_back({.triangle = uint32_t(t),
                       .b = float(root * (1 - v)),
                       .c = float(root * v),
                       .weightPerArea = float(total / (power[t] / area) / count / area)});
  }
  return samples;
}

namespace {

// The triangles of `geometry` that cannot move and those that can, by their instance's `moving`.
std::pair<std::vector<scene::Triangle>, std::vector<scene::Triangle>> byMotion(const scene::Geometry& g,
                                                                               const std::vector<bool>& moving) {
  std::pair<std::vector<scene::Triangle>, std::vector<scene::Triangle>> split;
  for (const scene::Triangle& t : g.triangles)
    (moving[g.vertices[t.v0].instance] ? split.second : split.first).push_back(t);
  return split;
}

// Whether any sample lies on a triangle that can move.
bool emittersMove(const scene::Geometry& g, const std::vector<gpu::EmitterSample>& samples,
                  const std::vector<bool>& moving) {
  return std::any_of(samples.begin(), samples.end(),
                     [&](const auto& s) { return moving[g.vertices[g.triangles[s.triangle].v0].instance]; });
}

}  // namespace

DirectLight::DirectLight(const vk::Context& ctx, const scene::Geometry& g, std::vector<gpu::EmitterSample> samples,
                         const std::vector<bool>& moving, const DirectLightSettings& settings, vk::Allocations* tally)
    : settings_(settings),
      environment_(settings.environmentLights()),
      sampleCount_(uint32_t(samples.size())),
      environmentCount_(uint32_t(environment_.size())),
      viewCount_(viewCount(settings, sampleCount_, environmentCount_)),
      surfelCount_(uint32_t(g.surfels.size())),
      vertexCount_(uint32_t(g.vertices.size())),
      splitsStatic_(!moving.empty() && !emittersMove(g, samples, moving)),
      lightViews_(shaderProgram(ctx, "light_views")),
      directSurfels_(shaderProgram(ctx, "direct_surfels")),
      worldBounds_(shaderProgram(ctx, "world_bounds")) {
  validate(settings);
  if (depthBytes(settings, viewCount_) > ctx.limits().maxStorageBufferRange)
    throw SettingsError("--light-samples " + std::to_string(settings.samples) +
                        (environmentCount_ > 0 ? " and --env-directions " + std::to_string(environmentCount_) : "") +
                        " with --shadow-map " + std::to_string(settings.resolution) + " need " +
                        std::to_string(depthBytes(settings, viewCount_) >> 20) +
                        " MiB of depth maps, above the device's maxStorageBufferRange (" +
                        std::to_string(ctx.limits().maxStorageBufferRange >> 20) + " MiB)");
  const uint32_t points = sampleCount_ + environmentCount_ + settings.punctualLights;
  if (points == 0) throw std::logic_error("DirectLight: nothing to light with");
  if (samples.empty()) samples.push_back({});  // bound, never read
  samples_ = vk::makeBuffer(ctx, samples, vk::Memory::Device, tally);
  punctual_ = vk::Buffer(ctx, std::max(environmentCount_ + settings.punctualLights, 1u) * sizeof(gpu::PunctualLight),
                         vk::Memory::Host, tally);
  if (environmentCount_ > 0) punctual_.upload(environment_);
  directional_ = environmentCount_ > 0;
  points_ = vk::Buffer(ctx, points * sizeof(gpu::LightPoint), vk::Memory::Device, tally);
  views_ = vk::Buffer(ctx, viewCount_ * sizeof(gpu::Camera), vk::Memory::Device, tally);
  depth_ = vk::Buffer(ctx, depthBytes(settings, viewCount_), vk::Memory::Device, tally);
  // The maps draw each surface as its shape, not as finely as the surfels sample it.
  if (splitsStatic_) {
    const auto [still, moves] = byMotion(g, moving);
    const std::vector<scene::Triangle> stillFaces = scene::planarFaces(g, still),
                                       movingFaces = scene::planarFaces(g, moves);
    staticRaster_.emplace(ctx, uint32_t(stillFaces.size()), tally, true);
    movingRaster_.emplace(ctx, uint32_t(movingFaces.size()), tally, true);
    staticTriangles_ = vk::makeBuffer(ctx, stillFaces, vk::Memory::Device, tally);
    movingTriangles_ = vk::makeBuffer(ctx, movingFaces, vk::Memory::Device, tally);
    movingCount_ = uint32_t(movingFaces.size());
    if (movingCount_ > 0) staticDepth_ = vk::Buffer(ctx, depth_.size(), vk::Memory::Device, tally);
  } else {
    const std::vector<scene::Triangle> faces = scene::planarFaces(g, g.triangles);
    allRaster_.emplace(ctx, uint32_t(faces.size()), tally, true);
    allTriangles_ = vk::makeBuffer(ctx, faces, vk::Memory::Device, tally);
  }
  sceneBounds_ = vk::Buffer(ctx, 6 * sizeof(uint32_t), vk::Memory::Device, tally);
  surfelDirect_ = vk::Buffer(ctx, std::max(surfelCount_, 1u) * sizeof(glm::vec4), vk::Memory::Device, tally);
  surfelUnshadowed_ = vk::Buffer(ctx, surfelDirect_.size(), vk::Memory::Device, tally);
}

void DirectLight::setLights(const std::vector<gpu::PunctualLight>& lights) {
  if (lights.size() != settings_.punctualLights)
    throw std::logic_error("DirectLight: the frame brings " + std::to_string(lights.size()) +
                           " punctual lights, the settings named " + std::to_string(settings_.punctualLights));
  if (!lit_ || lights.size() != lights_.size() ||
      (!lights.empty() && std::memcmp(lights.data(), lights_.data(), lights.size() * sizeof(gpu::PunctualLight)) != 0))
    lightsMoved_ = true;
  lights_ = lights;
  directional_ = environmentCount_ > 0 || std::any_of(lights.begin(), lights.end(), [](const gpu::PunctualLight& l) {
                   return l.position.w == gpu::kLightDirectional;
                 });
  if (!lights.empty())
    punctual_.upload(lights.data(), lights.size() * sizeof(gpu::PunctualLight),
                     environmentCount_ * sizeof(gpu::PunctualLight));
}

void DirectLight::record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Bindings& frame, bool geometryMoved) {
  if (lit_ && !geometryMoved && !lightsMoved_) return;  // the surfels' direct light stands
  // Their views moved: a light, or where a directional light's map covers the scene, the scene.
  if ((lightsMoved_ && settings_.punctualLights > 0) || (directional_ && geometryMoved)) staticDrawn_ = false;
  const vk::Bindings buffers =
      vk::Bindings::pool({{"emitterSamples", samples_}, {"punctualLights", punctual_}, {"sceneBounds", sceneBounds_}})
          .plus(pool())
          .plus(frame);
  const uint32_t points = sampleCount_ + environmentCount_ + settings_.punctualLights, views = viewCount_;
  const glm::uvec2 size(settings_.resolution);
  timedPass(cmd, timer, "direct light", [&] {
    if (directional_) {
      vk::fillBuffer(cmd, sceneBounds_, 0xFFFFFFFFu, 0, 3 * sizeof(uint32_t));  // min: the largest
      vk::fillBuffer(cmd, sceneBounds_, 0u, 3 * sizeof(uint32_t), 3 * sizeof(uint32_t));
      worldBounds_.dispatchItems(cmd, vertexCount_, buffers, gpu::CountPush{.count = vertexCount_});
    }
    lightViews_.dispatchItems(cmd, points, buffers,
                              gpu::LightViewsPush{.sampleCount = sampleCount_,
                                                  .punctualLights = environmentCount_ + settings_.punctualLights,
                                                  .environmentDirections = environmentCount_});
    if (!splitsStatic_) {
      allRaster_->record(cmd, frame.with({{"triangles", allTriangles_}}), views_, views, size, depth_);
    } else if (movingCount_ == 0) {  // nothing moves: the maps are drawn once
      if (!staticDrawn_)
        staticRaster_->record(cmd, frame.with({{"triangles", staticTriangles_}}), views_, views, size, depth_);
    } else {
      if (!staticDrawn_)
        staticRaster_->record(cmd, frame.with({{"triangles", staticTriangles_}}), views_, views, size, staticDepth_);
      vk::copyBuffer(cmd, staticDepth_, depth_);
      movingRaster_->record(cmd, frame.with({{"triangles", movingTriangles_}}), views_, views, size, depth_, false);
    }
    staticDrawn_ = true;
    directSurfels_.dispatchItems(cmd, surfelCount_, buffers,
                                 gpu::DirectLightPush{.count = surfelCount_,
                                                      .sampleCount = sampleCount(),
                                                      .resolution = settings_.resolution,
                                                      .punctualLights = settings_.punctualLights});
  });
  lit_ = true;
  lightsMoved_ = false;
}

}  // namespace ivgi::gi

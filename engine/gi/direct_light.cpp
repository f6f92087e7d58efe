#include "engine/gi/direct_light.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "engine/core/errors.h"
#include "engine/gi/pass.h"
#include "engine/image/colour.h"
#include "engine/scene/animation.h"
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

// The mean luminance of a triangle's emission cells (zero: it does not emit).
double meanLuminance(const std::vector<scene::EmissionCell>& cells) {
  double sum = 0;
  for (const scene::EmissionCell& c : cells) sum += image::luminance(glm::dvec3(c.emission));
  return cells.empty() ? 0.0 : sum / double(cells.size());
}

// The luminance of a triangle's mean emission, its texture's included (zero: it does not emit).
double emittedLuminance(const scene::Geometry& g, const scene::Triangle& tri) {
  return meanLuminance(scene::emissionCells(g, tri));
}

// A part of the emitters the points are spread over by power: a triangle's emission cell, with its
// area and power at rest, in the primitive's own space (only the ratios between them matter, and
// the frame's weight takes the triangle's area as it is then).
struct PoweredCell {
  uint32_t triangle;
  scene::EmissionCell cell;
  double area, triangleArea, power;
};

// A textured triangle's cells share its power by their emission, an eighth of it spread evenly
// over them: a cell whose centre looks up black may still hold texels that glow, and the points
// must reach every point that emits (the estimate stays unbiased).
constexpr double kEvenShare = 0.125;

std::vector<PoweredCell> poweredCells(const scene::Geometry& g) {
  std::vector<PoweredCell> out;
  for (size_t t = 0; t < g.triangles.size(); ++t) {
    const std::vector<scene::EmissionCell> cells = scene::emissionCells(g, g.triangles[t]);
    if (cells.empty()) continue;
    const double area = restArea(g, g.triangles[t]), cellArea = area / double(cells.size());
    const double mean = meanLuminance(cells);
    for (const scene::EmissionCell& c : cells) {
      const double luminance = image::luminance(glm::dvec3(c.emission));
      const double share = cells.size() == 1 ? luminance : (1.0 - kEvenShare) * luminance + kEvenShare * mean;
      if (cellArea * share > 0) out.push_back({uint32_t(t), c, cellArea, area, cellArea * share});
    }
  }
  return out;
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

double emitterPowerShare(const scene::Scene& s, const scene::Geometry& g) {
  const scene::Pose rest = scene::evaluatePose(s, -1, 0.0f);
  const std::vector<scene::WorldVertex> world = scene::animateOnHost(g, g.frameInputs(s, rest));
  double emitted = 0;
  for (const scene::Triangle& tri : g.triangles) {
    const double luminance = emittedLuminance(g, tri);
    if (!(luminance > 0)) continue;
    const glm::dvec3 a = world[tri.v0].position, b = world[tri.v1].position, c = world[tri.v2].position;
    emitted += gpu::kPi * luminance * 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  const scene::Bounds bounds = scene::worldBounds(world);
  const double radius = bounds.empty() ? 0.0 : 0.5 * glm::length(glm::dvec3(bounds.max - bounds.min));
  double punctual = 0;
  for (const scene::Node& n : s.nodes) {
    if (n.light < 0) continue;
    const scene::Light& l = s.lights[size_t(n.light)];
    const double intensity = image::luminance(glm::dvec3(l.color)) * l.intensity;
    switch (l.type) {
      case scene::Light::Type::Point: punctual += 4.0 * gpu::kPi * intensity; break;
      case scene::Light::Type::Spot: punctual += 2.0 * gpu::kPi * (1.0 - std::cos(l.outerCone)) * intensity; break;
      case scene::Light::Type::Directional: punctual += intensity * gpu::kPi * radius * radius; break;
    }
  }
  const double total = emitted + punctual;
  return total > 0 && std::isfinite(total) ? emitted / total : (punctual > 0 ? 0.0 : 1.0);
}

bool emits(const scene::Geometry& g) {
  return std::any_of(g.triangles.begin(), g.triangles.end(),
                     [&](const scene::Triangle& t) { return restArea(g, t) > 0 && emittedLuminance(g, t) > 0; });
}

std::vector<gpu::EmitterSample> emitterSamples(const scene::Geometry& g, uint32_t count) {
  const std::vector<PoweredCell> cells = poweredCells(g);
  double total = 0;
  for (const PoweredCell& c : cells) total += c.power;
  std::vector<gpu::EmitterSample> samples;
  if (!(total > 0) || count == 0) return samples;
  constexpr double kGolden = 0.6180339887498949;
  double before = 0;  // the power of the cells before k
  size_t k = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const double target = (i + 0.5) / count * total;
    while (k + 1 < cells.size() && before + cells[k].power < target) before += cells[k++].power;
    const PoweredCell& c = cells[k];
    const double u = std::clamp((target - before) / c.power, 0.0, 1.0), v = std::fmod((i + 0.5) * kGolden, 1.0);
    const double root = std::sqrt(u);  // uniform over the cell
    const glm::dvec2 p0 = c.cell.corners[0], p1 = c.cell.corners[1], p2 = c.cell.corners[2];
    const glm::dvec2 at = p0 + root * (1 - v) * (p1 - p0) + root * v * (p2 - p0);
    const float b = float(at.x), cw = float(at.y);
    // pdf per area at rest: (power / total) / area; the weight is its inverse over the count, per
    // unit of the triangle's area.
    samples.push_back({.triangle = c.triangle,
                       .b = b,
                       .c = cw,
                       .weightPerArea = float(total / (c.power / c.area) / count / c.triangleArea),
                       .radiance = glm::vec4(scene::emissionAt(g, g.triangles[c.triangle], b, cw), 0.0f)});
  }
  return samples;
}

namespace {

// The triangles of `geometry` that cannot move and those that can, by their instance's `moving`.
std::pair<std::vector<scene::Triangle>, std::vector<scene::Triangle>> byMotion(const scene::Geometry& g,
                                                                               const std::vector<bool>& moving) {
  std::pair<std::vector<scene::Triangle>, std::vector<scene::Triangle>> split;
  for (const scene::Triangle& t : frontTriangles(g))
    (moving[g.vertices[t.v0].instance] ? split.second : split.first).push_back(t);
  return split;
}

// Whether any sample lies on a triangle that can move.
bool emittersMove(const scene::Geometry& g, const std::vector<gpu::EmitterSample>& samples,
                  const std::vector<bool>& moving) {
  return std::any_of(samples.begin(), samples.end(),
                     [&](const auto& s) { return moving[g.vertices[g.triangles[s.triangle].v0].instance]; });
}

// The largest factor by which m stretches a length: its largest singular value, the root of mᵀm's
// largest eigenvalue (the closed form of a symmetric 3×3's eigenvalues).
double largestStretch(const glm::dmat3& m) {
  const glm::dmat3 a = glm::transpose(m) * m;
  const double offDiagonal = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
  if (offDiagonal == 0.0) return std::sqrt(std::max({a[0][0], a[1][1], a[2][2]}));
  const double q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
  const double p = std::sqrt(((a[0][0] - q) * (a[0][0] - q) + (a[1][1] - q) * (a[1][1] - q) +
                              (a[2][2] - q) * (a[2][2] - q) + 2.0 * offDiagonal) /
                             6.0);
  const double r = std::clamp(glm::determinant((a - q * glm::dmat3(1.0)) / p) / 2.0, -1.0, 1.0);
  return std::sqrt(std::max(q + 2.0 * p * std::cos(std::acos(r) / 3.0), 0.0));
}

// A cube face's narrowest texel, at its corner, subtends this many radians times the map's side:
// along x at (1, 1, 1), the step 2/side in the face's plane turns the ray by (2/side)·√2/3.
constexpr double kNarrowestTexel = 2.0 * 1.41421356 / 3.0;

// A part of the maps' meshes where the frame puts it: the sphere around it in world space, and how
// much its matrix stretches lengths at most and (a lower bound) at least.
struct PlacedPart {
  glm::dvec3 centre;
  double radius, stretch, leastStretch;
};

PlacedPart placed(const scene::MapMeshes::Part& part, const glm::mat4& matrix) {
  const glm::dmat3 m(matrix);
  const double stretch = largestStretch(m);
  return {glm::dvec3(matrix * glm::vec4(part.centre, 1.0f)), part.radius * stretch, stretch,
          stretch > 0.0 ? std::abs(glm::determinant(m)) / (stretch * stretch) : 0.0};
}

}  // namespace

DirectLight::Layer::Layer(const vk::Context& ctx, scene::MapMeshes m, uint32_t viewCount, vk::Allocations* tally,
                          bool viewsOnHost)
    : meshes(std::move(m)),
      drawn(meshes.draw({})),
      triangles(vk::makeBuffer(ctx, drawn, vk::Memory::Device, tally)),
      raster(ctx, uint32_t(meshes.exactCount()), tally, true, viewCount, meshes.cutouts(), viewsOnHost) {}

bool DirectLight::Layer::choose(const std::vector<float>& errors) {
  std::vector<scene::Triangle> now = meshes.draw(errors);
  if (now.size() == drawn.size() &&
      (now.empty() || std::memcmp(now.data(), drawn.data(), now.size() * sizeof(scene::Triangle)) == 0))
    return false;
  drawn = std::move(now);
  if (!drawn.empty()) triangles.upload(drawn);
  raster.setTriangleCount(uint32_t(drawn.size()));
  return true;
}

void DirectLight::Layer::record(VkCommandBuffer cmd, const vk::Bindings& frame, const vk::Buffer& views,
                                uint32_t viewCount, glm::uvec2 size, const vk::Buffer& target, bool clear,
                                uint32_t firstView) const {
  raster.record(cmd, vk::Bindings::pool({{"triangles", triangles}}).plus(frame), views, viewCount, size, target, clear,
                firstView);
}

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
      directSurfels_(shaderProgram(ctx, "direct_surfels",
                                   vk::Specialization{.constants = {{"kArrivals", g.directionalLobes ? 1u : 0u}}})),
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
  // The maps draw each surface as its shape, not as finely as the surfels sample it, and a back face
  // not at all: its front stands in the same place.
  if (splitsStatic_) {
    const auto [still, moves] = byMotion(g, moving);
    restoreViews_ = ctx.info().type == "cpu";
    still_.emplace(ctx, scene::MapMeshes(g, still), viewCount_, tally);
    moving_.emplace(ctx, scene::MapMeshes(g, moves), viewCount_, tally, restoreViews_);
    if (!moves.empty()) staticDepth_ = vk::Buffer(ctx, depth_.size(), vk::Memory::Device, tally);
  } else {
    all_.emplace(ctx, scene::MapMeshes(g, frontTriangles(g)), viewCount_, tally);
  }
  instances_ = g.instances;
  for (uint32_t i = 0; i < sampleCount_; ++i) {
    const gpu::EmitterSample& s = samples[i];
    const scene::Triangle& t = g.triangles[s.triangle];
    const glm::vec3 a = g.vertices[t.v0].position, b = g.vertices[t.v1].position, c = g.vertices[t.v2].position;
    samplePlaces_.emplace_back(g.vertices[t.v0].instance, a + s.b * (b - a) + s.c * (c - a));
  }
  sceneBounds_ = vk::Buffer(ctx, 6 * sizeof(uint32_t), vk::Memory::Device, tally);
  surfelDirect_ = vk::Buffer(ctx, std::max(surfelCount_, 1u) * sizeof(glm::vec4), vk::Memory::Device, tally);
  surfelUnshadowed_ = vk::Buffer(ctx, surfelDirect_.size(), vk::Memory::Device, tally);
  surfelArrival_ =
      vk::Buffer(ctx, g.directionalLobes ? surfelDirect_.size() : sizeof(glm::vec4), vk::Memory::Device, tally);
  surfelsLit_ = vk::Buffer(ctx, sizeof(uint32_t), vk::Memory::Device, tally);
}

void DirectLight::setFrame(const scene::FrameInputs& pose, const std::vector<gpu::PunctualLight>& lights,
                           const gpu::Camera& camera) {
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
  chooseMeshes(pose.matrices, camera);
}

namespace {

// The spheres a directional light's cascades cover: the camera's view from its origin out to
// distances spaced evenly in their logarithm between its near plane and the far side of the scene
// (whose own map is the next step), each the sphere around the view's slice up to there; those as
// large as the scene are left out.
std::vector<glm::vec4> cascadeSpheres(const gpu::Camera& camera, glm::dvec3 sceneCentre, double sceneRadius) {
  const glm::dvec3 origin(camera.origin), forward(camera.forward);
  const double far = glm::length(origin - sceneCentre) + sceneRadius,
               near = std::max(double(camera.origin.w), far * 1e-5);
  // A slice [0, d] of the view lies within the sphere around the point d/2 along it whose radius is
  // d·spread in perspective (the half-extents are at unit distance), and √(diagonal² + (d/2)²) for
  // an orthographic view (the half-extents are its own).
  const double diagonal2 = glm::dot(glm::dvec3(camera.right), glm::dvec3(camera.right)) +
                           glm::dot(glm::dvec3(camera.up), glm::dvec3(camera.up)),
               spread = std::sqrt(diagonal2 + 0.25);
  const bool orthographic = camera.up.w == gpu::kOrthographic;
  std::vector<glm::vec4> spheres;
  for (uint32_t k = 1; k <= gpu::kCascades && far > near; ++k) {
    const double d = near * std::pow(far / near, double(k) / double(gpu::kCascades + 1));
    const double radius = orthographic ? std::sqrt(diagonal2 + 0.25 * d * d) : d * spread;
    if (radius >= sceneRadius) break;
    spheres.emplace_back(glm::vec3(origin + 0.5 * d * forward), float(radius));
  }
  return spheres;
}

// A sphere around spheres (centre, radius; a point's radius is 0): centred on their box, out to the
// farthest.
glm::vec4 sphereAround(const std::vector<glm::dvec4>& spheres) {
  scene::Bounds box;
  for (const glm::dvec4& s : spheres) box.add(glm::vec3(glm::dvec3(s) - s.w)), box.add(glm::vec3(glm::dvec3(s) + s.w));
  const glm::dvec3 centre = 0.5 * (glm::dvec3(box.min) + glm::dvec3(box.max));
  double radius = 0.0;
  for (const glm::dvec4& s : spheres) radius = std::max(radius, glm::length(glm::dvec3(s) - centre) + s.w);
  return glm::vec4(glm::vec3(centre), float(radius));
}

}  // namespace

void DirectLight::chooseMeshes(const std::vector<glm::mat4>& matrices, const gpu::Camera& camera) {
  // The cubes' origins: the emitter samples and the point and spot lights. An emitter that bends
  // (skinned or morphed) is placed by the GPU alone, so then every part is drawn exactly.
  std::vector<glm::dvec3> origins;
  bool placedAll = true;
  for (const auto& [instance, p] : samplePlaces_) {
    const gpu::Instance& inst = instances_[instance];
    placedAll = placedAll && !inst.skinned && inst.morphTargets == 0;
    if (placedAll) origins.emplace_back(matrices[inst.matrix] * glm::vec4(p, 1.0f));
  }
  for (const gpu::PunctualLight& l : lights_)
    if (l.position.w != gpu::kLightDirectional) origins.emplace_back(glm::vec3(l.position));

  std::vector<Layer*> layers;
  for (std::optional<Layer>* layer : {&all_, &still_, &moving_})
    if (*layer) layers.push_back(&**layer);
  std::vector<std::vector<PlacedPart>> placedParts;
  // A lower bound of the radius of the scene's bounds, which a directional light's map spans
  // (light_views): the box holds every rigid part's centre (a mean of its vertices) and its vertices.
  scene::Bounds centres;
  double sceneRadius = 0.0;
  for (const Layer* layer : layers) {
    std::vector<PlacedPart>& placedLayer = placedParts.emplace_back();
    for (const scene::MapMeshes::Part& part : layer->meshes.parts()) {
      const PlacedPart& q = placedLayer.emplace_back(placed(part, matrices[instances_[part.instance].matrix]));
      if (!part.rigid) continue;  // a joint's matrix, not the part's: never simplified, and left out of the bound
      centres.add(glm::vec3(q.centre));
      sceneRadius = std::max(sceneRadius, 0.5 * part.radius * q.leastStretch);
    }
  }
  if (!centres.empty()) sceneRadius = std::max(sceneRadius, 0.5 * double(glm::length(centres.max - centres.min)));
  // The spheres that bound what a frame changes of the surfels' light: around the cubes' origins,
  // where all are placed, and around the moving parts, where all are rigid.
  std::vector<glm::dvec4> movingParts;
  double widest = 0.0;  // the largest part's radius, past any emitter triangle's
  for (size_t l = 0; l < layers.size(); ++l)
    for (size_t k = 0; k < placedParts[l].size(); ++k) {
      const PlacedPart& q = placedParts[l][k];
      widest = std::max(widest, q.radius);
      if (moving_ && layers[l] == &*moving_) movingParts.emplace_back(q.centre, q.radius);
    }
  if (moving_ && std::any_of(moving_->meshes.parts().begin(), moving_->meshes.parts().end(),
                             [](const scene::MapMeshes::Part& part) { return !part.rigid; }))
    movingParts.clear();  // a joint's matrix does not place its part
  placeChanges(placedAll ? origins : std::vector<glm::dvec3>{}, movingParts, widest);
  std::vector<glm::vec4> cascades;
  if (settings_.perPixel && !centres.empty() &&
      std::any_of(lights_.begin(), lights_.end(),
                  [](const gpu::PunctualLight& l) { return l.position.w == gpu::kLightDirectional; }))
    cascades = cascadeSpheres(camera, 0.5 * glm::dvec3(centres.min + centres.max), sceneRadius);
  if (cascades != cascades_) cascadesMoved_ = true;
  cascades_ = cascades;

  // A part's maps cannot resolve less than a texel where it is nearest to a light: its surface is
  // drawn within half the narrowest texel there (a cube's at its nearest origin, a directional
  // map's anywhere), which the lookup's bias (direct_light.glsl) also covers.
  const double side = settings_.resolution;
  for (size_t l = 0; l < layers.size(); ++l) {
    std::vector<float> errors;
    for (const PlacedPart& q : placedParts[l]) {
      double world = q.radius;  // coarser draws the same (MapMeshes::kCoarsestLevel)
      for (const glm::dvec3& o : origins)
        world = std::min(world, 0.5 * kNarrowestTexel * std::max(glm::length(o - q.centre) - q.radius, 0.0) / side);
      if (directional_) world = std::min(world, sceneRadius / side);
      for (const glm::vec4& c : cascades_)
        if (glm::length(glm::dvec3(c) - q.centre) <= double(c.w) + q.radius)
          world = std::min(world, double(c.w) / side);
      errors.push_back(settings_.simplifiedMeshes && placedAll && q.stretch > 0.0 ? float(world / q.stretch) : 0.0f);
    }
    if (layers[l]->choose(errors) && still_ && layers[l] == &*still_) staticDrawn_ = false;
  }
}

std::vector<std::pair<uint64_t, uint64_t>> DirectLight::directionalViewRanges() const {
  // The views: a cube each emitter sample, one each environment direction, a cube each punctual
  // light (light_views' firstView).
  std::vector<std::pair<uint64_t, uint64_t>> ranges;
  if (environmentCount_ > 0) ranges.emplace_back(uint64_t(gpu::kCubeFaces) * sampleCount_, environmentCount_);
  for (size_t j = 0; j < lights_.size(); ++j)
    if (lights_[j].position.w == gpu::kLightDirectional)
      ranges.emplace_back(gpu::kCubeFaces * (sampleCount_ + j) + environmentCount_, gpu::kCubeFaces);
  return ranges;
}

std::pair<size_t, size_t> DirectLight::trianglesDrawn() const {
  std::pair<size_t, size_t> drawn{0, 0};
  for (const std::optional<Layer>* layer : {&all_, &still_, &moving_})
    if (*layer) drawn.first += (*layer)->drawn.size(), drawn.second += (*layer)->meshes.triangleCount();
  return drawn;
}

void DirectLight::placeChanges(const std::vector<glm::dvec3>& origins, const std::vector<glm::dvec4>& movingParts,
                               double widest) {
  lightsSphere_.reset();
  movingSphere_.reset();
  if (origins.empty() || movingParts.empty() || directional_) return;
  std::vector<glm::dvec4> points;
  for (const glm::dvec3& o : origins) points.emplace_back(o, 0.0);
  glm::vec4 lights = sphereAround(points);
  // The cubes' origins stand off their samples by up to a thousandth of a triangle's size (light_views).
  lights.w += float(2e-3 * widest + 1e-6 * (glm::length(glm::vec3(lights)) + lights.w));
  lightsSphere_ = lights;
  movingSphere_ = sphereAround(movingParts);
}

uint32_t DirectLight::surfelsLit() const {
  if (!surfelsRelit_) return 0;
  return litChangedOnly_ ? surfelsLit_.read<uint32_t>(1)[0] : surfelCount_;
}

void DirectLight::restoreStill(VkCommandBuffer cmd, bool stillDrawn) {
  if (stillDrawn || !movingDrawn_ || !restoreViews_) return vk::copyBuffer(cmd, staticDepth_, depth_);
  std::vector<uint32_t> views = moving_->raster.drawnViewList();
  std::sort(views.begin(), views.end());
  const VkDeviceSize viewBytes = VkDeviceSize(settings_.resolution) * settings_.resolution * sizeof(uint32_t);
  std::vector<VkBufferCopy> runs;  // consecutive views in one region
  for (size_t i = 0; i < views.size(); ++i) {
    const VkDeviceSize at = views[i] * viewBytes;
    if (i > 0 && views[i] == views[i - 1] + 1)
      runs.back().size += viewBytes;
    else
      runs.push_back({at, at, viewBytes});
  }
  vk::copyRegions(cmd, staticDepth_, depth_, runs);
}

std::pair<uint32_t, uint32_t> DirectLight::movingViewsDrawn() const {
  return {moving_ && moving_->meshes.exactCount() > 0 ? moving_->raster.viewsDrawn() : 0u, viewCount_};
}

void DirectLight::record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Bindings& frame, bool geometryMoved) {
  if (lit_ && !geometryMoved && !lightsMoved_ && !cascadesMoved_) return;  // the surfels' direct light stands
  // The surfels look a directional light up in its view over the scene, not in the cascades: where
  // only those followed the camera, the maps are drawn again for the pixels alone.
  surfelsRelit_ = !lit_ || geometryMoved || lightsMoved_;
  // Their views moved: a light's; or where a directional light's map covers the scene and the
  // scene moved, or its cascades followed the camera, that light's alone.
  if (lightsMoved_ && settings_.punctualLights > 0) staticDrawn_ = false;
  const bool directionalMoved = (directional_ && geometryMoved) || cascadesMoved_;
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
    gpu::LightViewsPush push{.sampleCount = sampleCount_,
                             .punctualLights = environmentCount_ + settings_.punctualLights,
                             .environmentDirections = environmentCount_,
                             .cascadeCount = uint32_t(cascades_.size()),
                             .side = settings_.resolution};
    std::copy(cascades_.begin(), cascades_.end(), push.cascades);
    lightViews_.dispatchItems(cmd, points, buffers, push);
    // What cannot move, into `target`: all of its views, or the directional lights' alone; true where
    // it drew any.
    auto drawStill = [&](const vk::Buffer& target) {
      if (!staticDrawn_) {
        still_->record(cmd, frame, views_, views, size, target);
        return true;
      }
      if (!directionalMoved) return false;
      const uint64_t viewBytes = uint64_t(size.x) * size.y * sizeof(uint32_t);
      for (const auto& [first, count] : directionalViewRanges()) {
        vk::fillBuffer(cmd, target, 0xFFFFFFFFu, first * viewBytes, count * viewBytes);  // empty
        still_->record(cmd, frame, views_, uint32_t(count), size, target, false, uint32_t(first));
      }
      return true;
    };
    // Where only moving objects are drawn again over still maps, under the same lights, the surfels
    // they cannot shade keep their light.
    litChangedOnly_ = false;
    if (all_) {
      all_->record(cmd, frame, views_, views, size, depth_);
    } else if (moving_->meshes.exactCount() == 0) {  // nothing moves: the maps are drawn once
      drawStill(depth_);
    } else {
      litChangedOnly_ = staticDrawn_ && !lightsMoved_ && lightsSphere_ && movingSphere_ && drawnSphere_;
      restoreStill(cmd, drawStill(staticDepth_));
      moving_->record(cmd, frame, views_, views, size, depth_, false);
      movingDrawn_ = true;
    }
    staticDrawn_ = true;
    gpu::DirectLightPush lit{.count = surfelCount_,
                             .sampleCount = sampleCount(),
                             .resolution = settings_.resolution,
                             .punctualLights = settings_.punctualLights,
                             .surfelStride = surfelStride()};
    if (litChangedOnly_) {
      lit.lights = *lightsSphere_, lit.moved[0] = *movingSphere_, lit.moved[1] = *drawnSphere_, lit.changed = 1;
      vk::fillBuffer(cmd, surfelsLit_, 0u);
    }
    if (surfelsRelit_)
      directSurfels_.dispatchItems(cmd, surfelCount_, buffers.with({{"surfelsLit", surfelsLit_}}), lit);
    drawnSphere_ = movingSphere_;
  });
  lit_ = true;
  lightsMoved_ = cascadesMoved_ = false;
}

}  // namespace ivgi::gi

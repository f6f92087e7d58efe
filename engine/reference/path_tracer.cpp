#include "engine/reference/path_tracer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "engine/core/errors.h"
#include "engine/core/parallel.h"
#include "engine/scene/lights.h"
#include "engine/scene/reflectance.h"
#include "engine/scene/texture_sampling.h"
#include "engine/scene/triangle_rays.h"

namespace ivgi::reference {

namespace {

using gpu::kPi;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

// PCG32 (O'Neill): small, fast and good enough for Monte Carlo; seeded per pixel.
struct Rng {
  uint64_t state, increment;
  Rng(uint64_t seed, uint64_t stream) : state(0), increment(stream << 1u | 1u) {
    next();
    state += seed;
    next();
  }
  uint32_t next() {
    uint64_t old = state;
    state = old * 6364136223846793005ull + increment;
    uint32_t shifted = uint32_t(((old >> 18u) ^ old) >> 27u), rot = uint32_t(old >> 59u);
    return (shifted >> rot) | (shifted << ((32u - rot) & 31u));
  }
  float uniform() { return float(next() >> 8) * 0x1p-24f; }  // [0, 1)
};

uint64_t mix64(uint64_t z) {  // splitmix64's finaliser
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }
float maxComponent(glm::vec3 c) { return std::max(c.r, std::max(c.g, c.b)); }

// An orthonormal frame whose z is the unit normal n: where the BRDF's directions are expressed.
struct ShadingFrame {
  glm::vec3 b1, b2, n;
  explicit ShadingFrame(glm::vec3 normal) : n(normal) {
    glm::vec3 t = std::abs(n.x) > 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    b1 = glm::normalize(glm::cross(t, n)), b2 = glm::cross(n, b1);
  }
  glm::vec3 toLocal(glm::vec3 d) const { return {glm::dot(d, b1), glm::dot(d, b2), glm::dot(d, n)}; }
  glm::vec3 toWorld(glm::vec3 d) const { return d.x * b1 + d.y * b2 + d.z * n; }
  // A cosine-weighted direction.
  glm::vec3 cosineDirection(float u1, float u2) const {
    float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
    return r * std::cos(phi) * b1 + r * std::sin(phi) * b2 + std::sqrt(std::max(0.0f, 1.0f - u1)) * n;
  }
};

// How a surface reflects light arriving from wi toward wo (world directions, unit), and how its
// sampling picks wi: the diffuse base by cosine, the specular lobe by its visible normals, one or
// the other by gpu::specularChance.
struct Reflection {
  const gpu::SurfaceBrdf& m;
  ShadingFrame frame;
  glm::vec3 localWo;
  bool lambertian;
  scene::LayerAlbedo layer;
  float specularChance = 0.0f;

  Reflection(const gpu::SurfaceBrdf& material, glm::vec3 normal, glm::vec3 out)
      : m(material), frame(normal), localWo(frame.toLocal(out)), lambertian(gpu::isLambertian(material)) {
    if (lambertian) return;
    layer = scene::LayerAlbedo(m, localWo.z);
    specularChance = gpu::specularChance(m, localWo.z, layer.towardView);
  }

  glm::vec3 f(glm::vec3 wi) const {
    if (lambertian) return glm::vec3(m.base) / kPi;
    const glm::vec3 l = frame.toLocal(wi);
    return gpu::evalBrdf(m, l, localWo, layer.baseWeight(m, l.z));
  }
  float pdf(glm::vec3 wi) const {
    const float cosine = std::max(glm::dot(frame.n, wi), 0.0f) / kPi;
    if (lambertian) return cosine;
    return (1.0f - specularChance) * cosine +
           specularChance * gpu::visibleNormalPdf(frame.toLocal(wi), localWo, m.alpha);
  }
  glm::vec3 sample(Rng& rng) const {
    const bool specular = specularChance >= 1.0f || (specularChance > 0.0f && rng.uniform() < specularChance);
    const float u2 = rng.uniform(), u1 = rng.uniform();
    if (!specular) return frame.cosineDirection(u1, u2);
    const glm::vec3 h = gpu::sampleVisibleNormal(localWo, m.alpha, u1, u2);
    return frame.toWorld(glm::reflect(-localWo, h));
  }
};

// Power heuristic (β = 2) weight of a strategy with density a against one with density b.
float powerHeuristic(float a, float b) { return a * a / (a * a + b * b); }

}  // namespace

struct PathTracer::Impl {
  PathScene s;
  const scene::Geometry& g;
  scene::TriangleRays rays;
  std::vector<glm::vec3> front;     // per triangle: unit geometric normal on the side its vertex normals face
  std::vector<float> lightPdfArea;  // per triangle: density per unit area of choosing a point on it (0: no emission)
  std::vector<uint32_t> emitters;
  std::vector<float> emitterCdf;
  float epsilon = 1e-5f;  // ray-origin offset, relative to the scene's size

  struct Surface {
    uint32_t triangle;
    float t;
    glm::vec3 position, shadingNormal, geometricNormal;  // normals unit, not oriented
    gpu::SurfaceBrdf brdf;
    glm::vec3 emission;
    float roughness;  // as the file gives it (brdf.alpha is its square, clamped)
  };

  explicit Impl(PathScene scene)
      : s(std::move(scene)),
        g(*s.geometry),
        // Every face once: this tracer lights both sides of a face itself, so the backs the
        // solvers' one-sided surfels need (Geometry::backTriangles, the last) are left out.
        rays(s.world, g.triangles, g.triangles.size() - g.backTriangles, false, scene::cutAwayOf(g)) {
    const scene::Bounds bounds = scene::worldBounds(s.world);
    if (!bounds.empty()) epsilon = 1e-5f * std::max(glm::length(bounds.max - bounds.min), 1e-30f);

    // Emitters, chosen in proportion to their power (area × luminance of the emissive factor).
    front.resize(g.triangles.size());
    lightPdfArea.assign(g.triangles.size(), 0.0f);
    double total = 0;
    std::vector<float> power;
    for (uint32_t i = 0; i < g.triangles.size(); ++i) {
      const auto& t = g.triangles[i];
      const glm::vec3 n = gpu::faceFront(
          pos(t.v0), pos(t.v1), pos(t.v2),
          glm::vec3(s.world[t.v0].normal) + glm::vec3(s.world[t.v1].normal) + glm::vec3(s.world[t.v2].normal),
          (t.material & gpu::kFlatShaded) != 0u);
      const float area = 0.5f * glm::length(n);
      front[i] = area > 0.0f ? n / (2.0f * area) : glm::vec3(0.0f);
      float p = area * luminance(glm::vec3(g.materials[t.material & ~gpu::kTriangleFlags].emission));
      if (!(p > 0.0f) || !std::isfinite(p)) continue;
      emitters.push_back(i);
      power.push_back(p);
      total += p;
    }
    double running = 0;
    for (size_t k = 0; k < emitters.size(); ++k) {
      running += power[k];
      emitterCdf.push_back(float(running / total));
      const auto& t = g.triangles[emitters[k]];
      float area = 0.5f * glm::length(glm::cross(pos(t.v1) - pos(t.v0), pos(t.v2) - pos(t.v0)));
      lightPdfArea[emitters[k]] = float(power[k] / total) / area;
    }
    if (!emitterCdf.empty()) emitterCdf.back() = 1.0f;
  }

  glm::vec3 pos(uint32_t v) const { return glm::vec3(s.world[v].position); }

  std::optional<Surface> intersect(glm::vec3 o, glm::vec3 d, float tnear, float tfar) const {
    const std::optional<scene::TriangleRays::Hit> hit = rays.nearest(o, d, tnear, tfar);
    if (!hit) return std::nullopt;
    return surface(hit->triangle, hit->t, glm::vec3(1.0f - hit->uv.x - hit->uv.y, hit->uv.x, hit->uv.y));
  }

  bool occluded(glm::vec3 o, glm::vec3 d, float tfar) const { return rays.occluded(o, d, tfar); }

  // Everything shading needs at barycentric w of a triangle, as shaders/frame/resolve.comp computes it.
  Surface surface(uint32_t tri, float t, glm::vec3 w) const {
    const auto& tr = g.triangles[tri];
    Surface x{tri, t, w.x * pos(tr.v0) + w.y * pos(tr.v1) + w.z * pos(tr.v2), {}, {}, {}, {}};
    glm::vec3 ng = glm::cross(pos(tr.v1) - pos(tr.v0), pos(tr.v2) - pos(tr.v0));
    x.geometricNormal = glm::length(ng) > 0.0f ? glm::normalize(ng) : glm::vec3(0, 0, 1);
    x.shadingNormal = x.geometricNormal;
    if (!(tr.material & gpu::kFlatShaded)) {
      glm::vec3 ns = w.x * glm::vec3(s.world[tr.v0].normal) + w.y * glm::vec3(s.world[tr.v1].normal) +
                     w.z * glm::vec3(s.world[tr.v2].normal);
      if (glm::length(ns) > 0.0f) x.shadingNormal = glm::normalize(ns);
    }
    x.shadingNormal = scene::mappedNormalAt(g, s.world, tr, w, x.shadingNormal);
    const gpu::Material& m = g.materials[tr.material & ~gpu::kTriangleFlags];
    const glm::vec4 uv = w.x * g.uvs[tr.v0] + w.y * g.uvs[tr.v1] + w.z * g.uvs[tr.v2];
    const glm::vec4 color = w.x * g.colors[tr.v0] + w.y * g.colors[tr.v1] + w.z * g.colors[tr.v2];
    const glm::vec3 base =
        glm::vec3(m.baseColor) * glm::vec3(color) * glm::vec3(scene::sampleTexture(g, m.baseColorTexture, uv));
    const glm::vec4 metallicRoughness = scene::sampleTexture(g, m.metallicRoughnessTexture, uv);
    x.brdf = scene::surfaceBrdf(m, base, metallicRoughness);
    x.roughness = m.roughness * metallicRoughness.g;
    x.emission = glm::vec3(m.emission) * glm::vec3(scene::sampleTexture(g, m.emissiveTexture, uv));
    return x;
  }

  // Emitted radiance of x towards direction `out` (unit): emitters radiate from their front side.
  glm::vec3 emitted(const Surface& x, glm::vec3 out) const {
    return glm::dot(front[x.triangle], out) > 0.0f ? x.emission : glm::vec3(0.0f);
  }

  // Radiance reflected at x towards `out` (unit): the path from x on.
  glm::vec3 reflected(Surface x, glm::vec3 out, Rng& rng, const PathSettings& settings) const {
    glm::vec3 radiance(0.0f), throughput(1.0f);
    for (int vertex = 0;; ++vertex) {
      // Orient both normals to the side the path arrives from: surfaces reflect on both sides.
      glm::vec3 ng = x.geometricNormal, ns = x.shadingNormal;
      if (glm::dot(ng, out) < 0.0f) ng = -ng, ns = -ns;
      if (glm::dot(ns, ng) <= 0.0f) ns = ng;
      // Turned so that the view's mirror image stays above the surface, as Cycles turns it: the
      // specular lobe then has the view above its normal too.
      ns = gpu::liftedShadingNormal(ng, out, ns);
      const bool lambertian = gpu::isLambertian(x.brdf);
      if (lambertian && maxComponent(glm::vec3(x.brdf.base)) <= 0.0f) break;
      const Reflection reflection(x.brdf, ns, out);
      glm::vec3 origin = x.position + epsilon * ng;

      // Next-event estimation: one point on the emitters, every punctual light.
      if (!emitters.empty()) {
        size_t k =
            std::min(size_t(std::upper_bound(emitterCdf.begin(), emitterCdf.end(), rng.uniform()) - emitterCdf.begin()),
                     emitters.size() - 1);
        uint32_t tri = emitters[k];
        float r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
        glm::vec3 w(1.0f - r1, r1 * (1.0f - r2), r1 * r2);
        Surface y = surface(tri, 0.0f, w);
        // What the material's alpha takes away emits nothing: a blended emitter its alpha's share.
        if (g.cutouts) y.emission *= scene::presenceAt(g, g.triangles[tri], w);
        glm::vec3 toY = y.position - origin;
        float d2 = glm::dot(toY, toY), dist = std::sqrt(d2);
        if (dist > 0.0f) {
          glm::vec3 wi = toY / dist;
          float cosX = glm::dot(ns, wi), cosY = glm::dot(front[tri], -wi);
          if (cosX > 0.0f && cosY > 0.0f && glm::dot(ng, wi) > 0.0f && !occluded(origin, wi, dist * (1.0f - 1e-4f))) {
            float pdfLight = lightPdfArea[tri] * d2 / cosY, pdfBsdf = reflection.pdf(wi);
            radiance +=
                throughput * reflection.f(wi) * y.emission * (cosX / pdfLight * powerHeuristic(pdfLight, pdfBsdf));
          }
        }
      }
      for (const gpu::PunctualLight& light : s.lights) {
        glm::vec3 toLight;
        float dist2, falloff = gpu::lightFalloff(light, origin, toLight, dist2);
        if (!(falloff > 0.0f)) continue;
        glm::vec3 wi = glm::normalize(toLight);
        float cosX = glm::dot(ns, wi);
        if (cosX <= 0.0f || glm::dot(ng, wi) <= 0.0f) continue;
        float tfar = light.position.w == 0.0f ? kInfinity : std::sqrt(dist2) * (1.0f - 1e-4f);
        if (!occluded(origin, wi, tfar))
          radiance += throughput * reflection.f(wi) * glm::vec3(light.intensity) * (cosX * falloff);
      }

      // BSDF sampling: the next vertex, and emission or environment found on the way (MIS weighted).
      glm::vec3 wi = reflection.sample(rng);
      float cosX = glm::dot(ns, wi), pdfBsdf = reflection.pdf(wi);
      if (cosX <= 0.0f || glm::dot(ng, wi) <= 0.0f || !(pdfBsdf > 0.0f)) break;
      // f · cos / pdf: for a Lambertian surface (pdf = cos / π) the base colour itself.
      throughput *= lambertian ? glm::vec3(x.brdf.base) : reflection.f(wi) * (cosX / pdfBsdf);
      auto next = intersect(origin, wi, 0.0f, kInfinity);
      if (!next) {
        if (s.environment) radiance += throughput * s.environment->radiance(wi);
        break;
      }
      glm::vec3 le = emitted(*next, -wi);
      if (maxComponent(le) > 0.0f) {
        float cosY = std::abs(glm::dot(front[next->triangle], wi));
        float pdfLight = cosY > 0.0f ? lightPdfArea[next->triangle] * next->t * next->t / cosY : 0.0f;
        radiance += throughput * le * (pdfLight > 0.0f ? powerHeuristic(pdfBsdf, pdfLight) : 1.0f);
      }
      if (settings.bounces >= 0 && vertex >= settings.bounces) break;
      if (vertex >= 2) {  // Russian roulette, unbiased: survivors carry 1/q
        float q = std::min(0.95f, maxComponent(throughput));
        if (rng.uniform() >= q) break;
        throughput /= q;
      }
      x = *next;
      out = -wi;
    }
    return radiance;
  }
};

void validate(const PathSettings& s) {
  if (s.spp < 1 || s.spp > 1u << 20) throw SettingsError("--spp " + std::to_string(s.spp) + ": must be 1 to 1048576");
  if (s.threads > 1024)
    throw SettingsError("--threads " + std::to_string(s.threads) + ": must be 0 (every core) to 1024");
  constexpr int kMaxBounces = 10000;  // a guard against typing errors
  if (s.bounces < -1 || s.bounces > kMaxBounces)
    throw SettingsError("--bounces must be 0 to " + std::to_string(kMaxBounces));
}

PathScene PathScene::at(const scene::Scene& s, const scene::Geometry& g, const scene::Pose& pose,
                        std::optional<scene::Environment> env) {
  return {&g, scene::animateOnHost(g, g.frameInputs(s, pose)), scene::worldLights(s, pose), std::move(env)};
}

PathTracer::PathTracer(PathScene scene) : impl_(std::make_unique<Impl>(std::move(scene))) {}
PathTracer::~PathTracer() = default;

image::FrameChannels PathTracer::render(const scene::CameraView& view, uint32_t width, uint32_t height, uint32_t frame,
                                        const PathSettings& settings, std::atomic<uint32_t>* rowsDone) const {
  const Impl& im = *impl_;
  image::FrameChannels out;
  out.width = width, out.height = height;
  size_t pixels = size_t(width) * height;
  out.radiance.assign(pixels, glm::vec4(0.0f));
  out.albedo.assign(pixels, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  out.normalDepth.assign(pixels, glm::vec4(0.0f));
  out.emission.assign(pixels, glm::vec4(0.0f));
  out.roughnessMetallic.assign(pixels, glm::vec4(0.0f));
  const gpu::Camera cam = scene::gpuCamera(view, float(width) / float(height));
  const float zfar = cam.forward.w > 0.0f ? cam.forward.w : kInfinity;
  const uint64_t frameSeed = mix64(uint64_t(settings.seed) << 32 | frame);

  auto renderRow = [&](uint32_t y) {
    for (uint32_t x = 0; x < width; ++x) {
      size_t at = size_t(y) * width + x;
      Rng rng(mix64(frameSeed ^ at), at);
      glm::vec3 radiance(0.0f), albedo(0.0f), normal(0.0f), emission(0.0f);
      glm::vec2 roughnessMetallic(0.0f);
      float depth = 0.0f, hits = 0.0f;
      for (uint32_t i = 0; i < settings.spp; ++i) {
        // Drawn in sequence, y first: a call's arguments are evaluated in whatever order the
        // compiler chooses, and the image must not depend on the compiler.
        const float jitterY = rng.uniform(), jitterX = rng.uniform();
        glm::vec2 s = glm::vec2(float(x) + jitterX, float(y) + jitterY);
        if (settings.spp == 1)
          s = glm::vec2(float(x), float(y)) + 0.5f;             // one sample: the pixel centre, as the rasteriser
        glm::vec3 d = gpu::cameraRay(cam, s, {width, height});  // t along d is the depth along the view axis
        auto hit = im.intersect(gpu::cameraRayOrigin(cam, s, {width, height}), d, cam.origin.w, zfar);
        if (!hit) continue;
        glm::vec3 out = -glm::normalize(d);
        radiance += im.emitted(*hit, out) + im.reflected(*hit, out, rng, settings);
        albedo += glm::vec3(hit->brdf.base), roughnessMetallic += glm::vec2(hit->roughness, hit->brdf.metallic);
        normal += hit->shadingNormal, emission += hit->emission;
        depth += hit->t, hits += 1.0f;
      }
      float n = float(settings.spp);
      out.radiance[at] = glm::vec4(radiance / n, hits / n);
      out.albedo[at] = glm::vec4(albedo / n, 1.0f);
      float len = glm::length(normal);
      out.normalDepth[at] = glm::vec4(len > 0.0f ? normal / len : glm::vec3(0.0f), hits > 0.0f ? depth / hits : 0.0f);
      out.emission[at] = glm::vec4(emission / n, 0.0f);
      out.roughnessMetallic[at] = glm::vec4(roughnessMetallic / n, 0.0f, 0.0f);
    }
    if (rowsDone) rowsDone->fetch_add(1);
  };

  parallelFor(
      height, [&](size_t y) { renderRow(uint32_t(y)); }, settings.threads);
  return out;
}

glm::vec3 PathTracer::irradiance(glm::vec3 p, glm::vec3 n, uint32_t samples, const PathSettings& settings) const {
  const Impl& im = *impl_;
  Rng rng(mix64(uint64_t(settings.seed) << 32 ^ 0x9e3779b97f4a7c15ull), 7);
  // A white Lambertian point reflects E/π: estimate that and scale back.
  const gpu::SurfaceBrdf white{glm::vec4(1.0f), glm::vec4(0.0f), 0.0f, 1.0f, 0.0f, 0.0f};
  Impl::Surface x{0, 0.0f, p, glm::normalize(n), glm::normalize(n), white, glm::vec3(0.0f), 1.0f};
  glm::vec3 sum(0.0f);
  for (uint32_t i = 0; i < samples; ++i) sum += im.reflected(x, x.geometricNormal, rng, settings);
  return kPi * sum / float(samples);
}

}  // namespace ivgi::reference

// glTF's metallic-roughness BRDF (shaders/interface/brdf.h) against the specification's formulas
// written out here independently, the specular albedo table against its own integration, the
// BRDF's reciprocity and energy, and the path tracer's glossy reflection against numerically
// integrated directional albedos (white furnaces per roughness).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/reference/path_tracer.h"
#include "engine/scene/gltf.h"
#include "engine/scene/reflectance.h"
#include "scenes/gltf_builder.h"
#include "shaders/interface.h"

using namespace ivgi;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Params {
  glm::dvec3 base{1.0};
  double metallic = 0.0, roughness = 1.0;
  glm::dvec3 f0{0.04};  // the dielectric's Fresnel at normal incidence
  double f90 = 1.0;     // and at grazing
};

gpu::SurfaceBrdf brdfOf(const Params& p) {
  return {glm::vec4(glm::vec3(p.base), 0.0f),
          glm::vec4(glm::vec3(p.f0), float(p.f90)),
          float(p.metallic),
          gpu::alphaOf(float(p.roughness)),
          0.0f,
          0.0f};
}

// The specification's Appendix B in double precision: the specular lobe (rgb), and the diffuse base
// (rgb) as brdf.h layers it under the lobe (the table's albedo weighing it), split so that each
// can be integrated where it lives.
struct Reference {
  Params p;
  double alpha() const { return std::max(p.roughness * p.roughness, double(gpu::kMinAlpha)); }
  static double schlick(double vh) { return std::pow(1.0 - std::abs(vh), 5.0); }
  glm::dvec3 dielectricFresnel(double vh) const { return p.f0 + (glm::dvec3(p.f90) - p.f0) * schlick(vh); }
  glm::dvec3 specular(glm::dvec3 l, glm::dvec3 v) const {
    if (l.z <= 0 || v.z <= 0) return glm::dvec3(0.0);
    const glm::dvec3 h = glm::normalize(l + v);
    const double a2 = alpha() * alpha(), vh = glm::dot(v, h);
    const double D = a2 / (kPi * std::pow(h.z * h.z * (a2 - 1.0) + 1.0, 2.0));
    const double G1l = 2.0 * l.z / (l.z + std::sqrt(a2 + (1.0 - a2) * l.z * l.z));
    const double G1v = 2.0 * v.z / (v.z + std::sqrt(a2 + (1.0 - a2) * v.z * v.z));
    // Height-correlated: G2 = 1 / (1 + Λ(l) + Λ(v)), with Λ = 1/G1 − 1.
    const double G2 = 1.0 / (1.0 / G1l + 1.0 / G1v - 1.0);
    const double V = G2 / (4.0 * l.z * v.z);
    const glm::dvec3 metal = p.base + (glm::dvec3(1.0) - p.base) * schlick(vh);
    return D * V * ((1.0 - p.metallic) * dielectricFresnel(vh) + p.metallic * metal);
  }
  glm::dvec3 diffuse(glm::dvec3 l, glm::dvec3 v) const {
    if (l.z <= 0 || v.z <= 0) return glm::dvec3(0.0);
    const scene::LayerAlbedo layer(brdfOf(p), float(v.z));
    return (1.0 - p.metallic) * double(layer.baseWeight(brdfOf(p), float(l.z))) * p.base / kPi;
  }

  // ∫ f(l, v) cos θ_l dω_l: the diffuse base by a cosine-mapped midpoint rule over l, the specular
  // lobe by a midpoint rule over half vectors mapped through the distribution's inverse CDF in θ_h
  // (so that even a sharp lobe gets its share of the points).
  glm::dvec3 directionalAlbedo(double cosView) const {
    const glm::dvec3 v(std::sqrt(1.0 - cosView * cosView), 0.0, cosView);
    glm::dvec3 sum(0.0);
    constexpr int nu = 200, nphi = 100;
    for (int i = 0; i < nu; ++i)
      for (int k = 0; k < nphi; ++k) {
        const double u = (i + 0.5) / nu, phi = 2.0 * kPi * (k + 0.5) / nphi, r = std::sqrt(u);
        const glm::dvec3 l(r * std::cos(phi), r * std::sin(phi), std::sqrt(1.0 - u));
        sum += diffuse(l, v) * kPi / double(nu * nphi);  // f cos / (cos / π)
      }
    return sum + specularAlbedo(cosView);
  }
  // The specular lobe's part of it, over nxi × nh half vectors.
  glm::dvec3 specularAlbedo(double cosView, int nxi = 1000, int nh = 200) const {
    const glm::dvec3 v(std::sqrt(1.0 - cosView * cosView), 0.0, cosView);
    glm::dvec3 sum(0.0);
    const double a = alpha(), a2 = a * a;
    for (int i = 0; i < nxi; ++i)
      for (int k = 0; k < nh; ++k) {
        const double xi = (i + 0.5) / nxi, phi = 2.0 * kPi * (k + 0.5) / nh;
        const double theta = std::atan(a * std::sqrt(xi / (1.0 - xi)));
        const glm::dvec3 h(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
        const double vh = glm::dot(v, h);
        if (vh <= 0) continue;
        const glm::dvec3 l = 2.0 * vh * h - v;
        if (l.z <= 0) continue;
        const double pdfH = a2 / (kPi * std::pow(h.z * h.z * (a2 - 1.0) + 1.0, 2.0)) * h.z;  // D cos θ_h
        sum += specular(l, v) * l.z * (4.0 * vh) / pdfH / double(nxi * nh);
      }
    return sum;
  }
};

glm::dvec3 randomHemisphere(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = u(rng), phi = 2.0 * kPi * u(rng), r = std::sqrt(1.0 - z * z);
  return {r * std::cos(phi), r * std::sin(phi), std::max(z, 1e-3)};
}

glm::vec3 randomDirectionAbove(std::mt19937& rng) { return glm::normalize(glm::vec3(randomHemisphere(rng))); }

const std::vector<Params> kMaterials = {
    {.base = glm::dvec3(1.0), .metallic = 1.0, .roughness = 0.2},
    {.base = glm::dvec3(0.9, 0.6, 0.3), .metallic = 0.5, .roughness = 0.45},
    {.base = glm::dvec3(0.5), .metallic = 0.0, .roughness = 0.7},
    {.base = glm::dvec3(0.8, 0.1, 0.1),
     .metallic = 0.0,
     .roughness = 0.1,
     .f0 = glm::dvec3(0.02, 0.08, 0.04),
     .f90 = 0.6},
    {.base = glm::dvec3(1.0), .metallic = 1.0, .roughness = 1.0},
};

}  // namespace

// The table of the specular layer's albedo (A, B) against the lobe integrated here over half
// vectors, between its nodes as well as at them.
TEST(Brdf, SpecularAlbedoTableMatchesItsIntegral) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 20; ++i) {
    const double mu = 0.02 + 0.98 * u(rng), roughness = 0.05 + 0.95 * u(rng);
    // A: the lobe with F0 = 1, F90 = 0; B: with F0 = 0, F90 = 1 (a dielectric, no base).
    const double a = Reference{{.base = glm::dvec3(0.0), .roughness = roughness, .f0 = glm::dvec3(1.0), .f90 = 0.0}}
                         .directionalAlbedo(mu)
                         .x;
    const double b = Reference{{.base = glm::dvec3(0.0), .roughness = roughness, .f0 = glm::dvec3(0.0), .f90 = 1.0}}
                         .directionalAlbedo(mu)
                         .x;
    const glm::vec2 table = scene::SpecularAlbedo::table().at(float(mu), float(roughness));
    EXPECT_NEAR(table.x, a, 4e-3) << "cos " << mu << " roughness " << roughness;
    EXPECT_NEAR(table.y, b, 4e-3) << "cos " << mu << " roughness " << roughness;
  }
}

// brdf.h evaluates what the specification's formulas give.
TEST(Brdf, MatchesTheSpecificationsFormulas) {
  std::mt19937 rng(7);
  for (const Params& p : kMaterials) {
    const Reference ref{p};
    for (int i = 0; i < 200; ++i) {
      const glm::dvec3 l = glm::normalize(randomHemisphere(rng)), v = glm::normalize(randomHemisphere(rng));
      const glm::dvec3 expected = ref.diffuse(l, v) + ref.specular(l, v);
      const scene::LayerAlbedo layer(brdfOf(p), float(v.z));
      const glm::vec3 got =
          gpu::evalBrdf(brdfOf(p), glm::vec3(l), glm::vec3(v), layer.baseWeight(brdfOf(p), float(l.z)));
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(got[c], expected[c], 1e-4 * expected[c] + 1e-6)
            << "roughness " << p.roughness << " metallic " << p.metallic << " l.z " << l.z << " v.z " << v.z;
    }
  }
}

// f(l, v) = f(v, l), and nothing below the surface.
TEST(Brdf, IsReciprocal) {
  std::mt19937 rng(11);
  for (const Params& p : kMaterials)
    for (int i = 0; i < 500; ++i) {
      const glm::vec3 l = randomDirectionAbove(rng), v = randomDirectionAbove(rng);
      auto f = [&](glm::vec3 from, glm::vec3 to) {
        return gpu::evalBrdf(brdfOf(p), from, to, scene::LayerAlbedo(brdfOf(p), to.z).baseWeight(brdfOf(p), from.z));
      };
      const glm::vec3 a = f(l, v), b = f(v, l);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-5f * std::max(a[c], 1.0f));
      EXPECT_EQ(f(glm::vec3(l.x, l.y, -l.z), v), glm::vec3(0.0f));
    }
}

// A white surface reflects at most what reaches it, from every direction and at every roughness;
// a white metal at α → 0 reflects all of it (single scattering loses only what the rougher
// microsurfaces mask).
TEST(Brdf, ReflectsNoMoreEnergyThanItReceives) {
  for (double metallic : {0.0, 1.0})
    for (double roughness : {0.05, 0.25, 0.5, 0.75, 1.0})
      for (double cosView : {1.0, 0.7, 0.3, 0.1, 0.02}) {
        const Reference ref{{.base = glm::dvec3(1.0), .metallic = metallic, .roughness = roughness}};
        const glm::dvec3 albedo = ref.directionalAlbedo(cosView);
        EXPECT_LE(albedo.x, 1.0 + 2e-3) << "metallic " << metallic << " roughness " << roughness << " cos " << cosView;
        EXPECT_GT(albedo.x, 0.3) << "metallic " << metallic << " roughness " << roughness << " cos " << cosView;
      }
  // The integration itself: a Lambertian white reflects exactly 1, a smooth white metal nearly so.
  const Reference lambertian{{.f0 = glm::dvec3(0.0), .f90 = 0.0}}, mirror{{.metallic = 1.0, .roughness = 0.05}};
  EXPECT_NEAR(lambertian.directionalAlbedo(0.6).x, 1.0, 1e-4);
  EXPECT_NEAR(mirror.directionalAlbedo(0.8).x, 1.0, 2e-3);
}

// What a diffuse solver takes of a glossy surface: the fraction of uniform light it reflects toward
// a direction (per pixel) and over the hemisphere (per surfel), against the integrated lobe.
TEST(Brdf, ReflectanceIsTheIntegratedAlbedo) {
  const scene::SpecularAlbedo& table = scene::SpecularAlbedo::table();
  for (const Params& p : kMaterials) {
    const Reference ref{p};
    glm::dvec3 mean(0.0);  // 2 ∫ E(μ) μ dμ, midpoints
    constexpr int n = 16;
    for (int i = 0; i < n; ++i) {
      const double mu = (i + 0.5) / n;
      const glm::dvec3 albedo = ref.directionalAlbedo(mu);
      mean += 2.0 * albedo * mu / double(n);
      const glm::vec3 got = table.reflectance(brdfOf(p), float(mu));
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], albedo[c], 0.01 * albedo[c] + 1e-3) << "roughness " << p.roughness << " cos " << mu;
    }
    const glm::vec3 got = table.meanReflectance(brdfOf(p));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], mean[c], 0.01 * mean[c]) << "roughness " << p.roughness;
  }
}

// White furnaces: a plane of one material under a uniform sky of radiance 1, seen at a few angles
// through a narrow camera. Each pixel sees the directional albedo toward the camera, which the
// path tracer's sampling (visible normals and cosine, one-sample MIS between them) must reproduce
// within 1 % of the integrated table, at every roughness.
TEST(Brdf, PathTracedFurnaceMatchesTheIntegratedAlbedo) {
  struct Case {
    Params p;
    double viewDegrees;
  };
  std::vector<Case> cases;
  for (double roughness : {0.1, 0.3, 0.6, 1.0})
    for (double view : {0.0, 45.0, 75.0}) {
      cases.push_back({{.base = glm::dvec3(1.0), .metallic = 1.0, .roughness = roughness}, view});
      cases.push_back({{.base = glm::dvec3(1.0), .metallic = 0.0, .roughness = roughness}, view});
    }
  cases.push_back({{.base = glm::dvec3(0.9, 0.6, 0.3), .metallic = 0.5, .roughness = 0.45}, 30.0});

  for (const Case& c : cases) {
    scenes::GltfBuilder b;
    const int material = b.glossyMaterial("plane", glm::vec3(c.p.base), float(c.p.metallic), float(c.p.roughness));
    scenes::MeshData plane;
    scenes::addQuad(plane, {-50, 0, -50}, {50, 0, -50}, {50, 0, 50}, {-50, 0, 50}, 1, 1, {0, 1, 0});
    b.node("plane", b.mesh("plane", {{plane, material}}));
    const double theta = c.viewDegrees * kPi / 180.0;
    b.camera("camera", 0.01f, 0.01f, glm::vec3(0.0f, float(std::cos(theta)), float(std::sin(theta))),
             glm::angleAxis(float(theta - kPi / 2), glm::vec3(1, 0, 0)));
    const scene::Scene s = scene::sceneFromModel(b.finish(), "furnace plane");
    const scene::Geometry g = scene::buildGeometry(s);
    const auto pose = scene::evaluatePose(s, -1, 0.0f);
    const reference::PathTracer tracer(reference::PathScene::at(s, g, pose, scene::Environment::parse("1,1,1")));
    const image::FrameChannels f =
        tracer.render(scene::cameraView(s, pose, s.cameraNodes().at(0)), 8, 8, 0, {.spp = 2048, .threads = 2});
    glm::dvec3 mean(0.0);
    for (const auto& r : f.radiance) mean += glm::dvec3(glm::vec3(r)) / double(f.radiance.size());
    const glm::dvec3 expected = Reference{c.p}.directionalAlbedo(std::cos(theta));
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(mean[k], expected[k], 0.01 * expected[k])
          << "metallic " << c.p.metallic << " roughness " << c.p.roughness << " view " << c.viewDegrees << "°";
    EXPECT_NEAR(f.roughnessMetallic[0].r, c.p.roughness, 1e-4);  // a mean of float sums
    EXPECT_NEAR(f.roughnessMetallic[0].g, c.p.metallic, 1e-4);
  }
}

// A shading normal lifted toward the face (scene.h's liftedShadingNormal): where the view's mirror
// image about it lies below the threshold, the lifted normal is unit, lies between it and the face's
// normal in their plane, and mirrors the view to the threshold's height exactly; elsewhere it is
// the normal as given.
TEST(Brdf, ALiftedNormalMirrorsTheViewJustAboveTheFace) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const glm::vec3 face(0, 0, 1);
  int lifted = 0;
  for (int i = 0; i < 2000; ++i) {
    const float elevation = 0.02f + 1.5f * u(rng), tilt = 1.2f * u(rng), azimuth = 6.2832f * u(rng);
    const glm::vec3 toEye(std::cos(elevation), 0.0f, std::sin(elevation));
    const glm::vec3 n(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
    const float threshold = std::min(0.9f * toEye.z, 0.01f);
    const auto height = [&](glm::vec3 m) { return glm::dot(face, m * (2.0f * glm::dot(m, toEye)) - toEye); };
    const glm::vec3 m = gpu::liftedShadingNormal(face, toEye, n);
    if (height(n) >= threshold) {
      EXPECT_EQ(m, n) << i;
      continue;
    }
    ++lifted;
    EXPECT_NEAR(glm::length(m), 1.0f, 1e-5f) << i;
    EXPECT_NEAR(height(m), threshold, 2e-4f) << i;
    EXPECT_NEAR(glm::dot(glm::cross(n, face), m), 0.0f, 1e-4f) << i << ": in the plane of n and the face's normal";
    EXPECT_GE(glm::dot(m, face), glm::dot(n, face) - 1e-5f) << i << ": turned toward the face's normal";
  }
  EXPECT_GT(lifted, 200);
}

// The share of an even sky a lobe keeps above a face's plane (brdf.h's lobeShareAbove) against a
// Monte Carlo integral of the same lobe: 1 where the plane is the lobe's own horizon, within 0.05
// elsewhere, and continuous as the normal turns.
TEST(Brdf, ALobesShareAboveAPlaneMatchesItsIntegral) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const auto integral = [&](float alpha, glm::vec3 v, glm::vec3 plane) {
    const float a2 = alpha * alpha;
    double above = 0.0, all = 0.0;
    for (int k = 0; k < 200000; ++k) {
      const glm::vec3 h = gpu::sampleVisibleNormal(v, alpha, u(rng), u(rng));
      const glm::vec3 l = h * (2.0f * glm::dot(h, v)) - v;
      if (!(l.z > 0.0f)) continue;
      // G2 / G1(v): the estimator of the lobe's albedo under these samples.
      const double w = gpu::smithVisibility(l.z, v.z, a2) * 4.0 * l.z * v.z / gpu::smithG1(v.z, a2);
      all += w;
      if (glm::dot(l, plane) > 0.0f) above += w;
    }
    return above / all;
  };
  const glm::vec3 v = glm::normalize(glm::vec3(0.6f, 0.2f, 0.5f));
  for (float alpha : {0.05f, 0.1225f, 0.4f, 1.0f}) {
    EXPECT_EQ(gpu::lobeShareAbove(alpha, v, glm::vec3(0, 0, 1)), 1.0f) << alpha;
    for (float lean : {0.3f, 0.6f, 0.9f}) {
      const glm::vec3 plane(std::sin(lean), 0.0f, std::cos(lean));
      const float share = gpu::lobeShareAbove(alpha, v, plane), exact = float(integral(alpha, v, plane));
      std::printf("[ brdf ] α %.4f, plane leaning %.1f: share %.4f, integral %.4f\n", alpha, lean, share, exact);
      EXPECT_NEAR(share, exact, 0.05f) << "α " << alpha << ", lean " << lean;
      const glm::vec3 nudged(std::sin(lean + 1e-3f), 0.0f, std::cos(lean + 1e-3f));
      EXPECT_NEAR(gpu::lobeShareAbove(alpha, v, nudged), share, 0.01f) << "α " << alpha << ", lean " << lean;
    }
  }
}

// How far from even a lobe sends its light (scene::lobeDeviation) against the specification's lobe
// integrated here otherwise: over light and exit directions by uniform midpoints in (cos θ, φ),
// weighed by their cosines, in double precision. Rough dielectrics lie below the share the solvers
// send evenly (the Blender room's walls: F0 0 under KHR_materials_specular; the glTF default's
// F0 0.04 at roughness 1), polished and metallic lobes above it.
TEST(Brdf, ALobesDeviationFromEvenMatchesItsIntegral) {
  const auto integrated = [](const Params& p) {
    const Reference ref{p};
    constexpr int nl = 24, nmu = 96, nphi = 96;
    double sum = 0.0, weights = 0.0;
    for (int i = 0; i < nl; ++i) {
      const double cl = (i + 0.5) / nl;
      const glm::dvec3 l(std::sqrt(1.0 - cl * cl), 0.0, cl);
      std::vector<glm::dvec3> sent;
      std::vector<double> cosines;
      glm::dvec3 albedo(0.0);
      double cosineSum = 0.0;
      for (int j = 0; j < nmu; ++j)
        for (int k = 0; k < nphi; ++k) {
          const double c = (j + 0.5) / nmu, phi = 2.0 * kPi * (k + 0.5) / nphi, s = std::sqrt(1.0 - c * c);
          sent.push_back(kPi * ref.specular(l, glm::dvec3(s * std::cos(phi), s * std::sin(phi), c)));
          cosines.push_back(c);
          albedo += sent.back() * c;
          cosineSum += c;
        }
      albedo /= cosineSum;  // π ∫ f cos dω / ∫ cos dω = ∫ f cos dω, the lobe's albedo toward l
      glm::dvec3 deviation(0.0);
      for (size_t n = 0; n < sent.size(); ++n) deviation += glm::abs(sent[n] - albedo) * cosines[n];
      sum += std::max(deviation.x, std::max(deviation.y, deviation.z)) / cosineSum * cl;
      weights += cl;
    }
    return sum / weights;
  };
  const std::vector<std::pair<Params, bool>> cases = {
      {{.base = glm::dvec3(0.7), .roughness = 1.0, .f0 = glm::dvec3(0.0)}, false},
      {{.base = glm::dvec3(0.85), .roughness = 1.0}, false},
      {{.base = glm::dvec3(0.8), .roughness = 0.8}, true},
      {{.base = glm::dvec3(0.8), .roughness = 0.5}, true},
      {{.base = glm::dvec3(0.91), .metallic = 1.0, .roughness = 0.3}, true},
      {{.base = glm::dvec3(0.9), .metallic = 1.0, .roughness = 1.0}, true},
  };
  for (const auto& [p, directional] : cases) {
    const double expected = integrated(p), got = scene::lobeDeviation(brdfOf(p));
    std::printf("[ brdf ] roughness %.1f, metallic %.0f, F0 %.2f: deviation %.4f, integrated %.4f\n", p.roughness,
                p.metallic, p.f0.x, got, expected);
    EXPECT_NEAR(got, expected, 0.03 * expected + 1e-4) << "roughness " << p.roughness << " metallic " << p.metallic;
    EXPECT_EQ(got >= scene::kEvenLobeDeviation, directional) << "roughness " << p.roughness;
  }
  EXPECT_EQ(scene::lobeDeviation(brdfOf({.base = glm::dvec3(0.8), .f0 = glm::dvec3(0.0), .f90 = 0.0})), 0.0f);
}

// How far from even a dielectric's base sends its light (scene::baseDeviation) against the base
// weight integrated here: the layer's albedo E(μ) by the lobe's own quadrature at cosine-weighted
// exit strata, Ē their mean, the base's share ρ(1 − Ē) · mean |(1 − E)/(1 − Ē) − 1|. The solvers send
// bases evenly below kEvenLobeDeviation, as the glTF default material (F0 0.04, roughness 1) and the
// engine's; polished and satin bases above it; a metal and a base without a layer send none.
TEST(Brdf, ABasesDeviationFromEvenMatchesItsIntegral) {
  const auto integrated = [](const Params& p) {
    const Reference ref{p};
    constexpr int nmu = 48;
    std::vector<double> layer(nmu);
    double mean = 0.0;
    for (int j = 0; j < nmu; ++j) {
      const glm::dvec3 e = ref.specularAlbedo(std::sqrt((j + 0.5) / nmu), 200, 50);
      layer[j] = std::max(e.x, std::max(e.y, e.z));
      mean += layer[j] / nmu;
    }
    double deviation = 0.0;
    for (double e : layer) deviation += std::abs((1.0 - e) / (1.0 - mean) - 1.0) / nmu;
    return std::max(p.base.x, std::max(p.base.y, p.base.z)) * (1.0 - p.metallic) * (1.0 - mean) * deviation;
  };
  const std::vector<std::pair<Params, bool>> cases = {
      {{.base = glm::dvec3(0.85), .roughness = 1.0}, false},
      {{.base = glm::dvec3(0.8), .roughness = 0.5}, true},
      {{.base = glm::dvec3(0.8), .roughness = 0.2}, true},
      {{.base = glm::dvec3(0.2), .roughness = 0.2}, true},
  };
  for (const auto& [p, directional] : cases) {
    const double expected = integrated(p), got = scene::baseDeviation(brdfOf(p));
    std::printf("[ brdf ] base %.2f, roughness %.1f: base deviation %.4f, integrated %.4f\n", p.base.x, p.roughness,
                got, expected);
    EXPECT_NEAR(got, expected, 0.05 * expected + 2e-4) << "roughness " << p.roughness;
    EXPECT_EQ(scene::sendsBaseByDirection(brdfOf(p)), directional) << "roughness " << p.roughness;
  }
  EXPECT_EQ(scene::baseDeviation(brdfOf({.base = glm::dvec3(0.9), .metallic = 1.0, .roughness = 0.3})), 0.0f);
  EXPECT_EQ(scene::baseDeviation(brdfOf({.base = glm::dvec3(0.8), .f0 = glm::dvec3(0.0), .f90 = 0.0})), 0.0f);
}

// Without a spread the widened lobe is the lobe itself, anisotropic code path and all.
TEST(Brdf, AWidenedLobeWithoutSpreadIsTheLobe) {
  std::mt19937 rng(13);
  for (const Params& p : kMaterials)
    for (int i = 0; i < 300; ++i) {
      const glm::vec3 l = randomDirectionAbove(rng), v = randomDirectionAbove(rng);
      const glm::vec3 lobe = gpu::evalBrdf(brdfOf(p), l, v, 0.0f),
                      widened = gpu::widenedSpecular(brdfOf(p), l, v, 0.0f);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(widened[c], lobe[c], 1e-4f * lobe[c] + 1e-6f) << "l.z " << l.z << " v.z " << v.z;
    }
}

namespace {

// A white mirror-like metal of roughness α (its Fresnel 1), seen from cos θ = mu, and the view's
// mirror image `centre`.
struct Spot {
  gpu::SurfaceBrdf brdf;
  glm::dvec3 v, centre;
};
Spot spotOf(double alpha, double mu) {
  const gpu::SurfaceBrdf brdf{glm::vec4(1.0f), glm::vec4(1.0f), 1.0f, float(alpha), 0.0f, 0.0f};
  const glm::dvec3 v(std::sqrt(1.0 - mu * mu), 0.0, mu);
  return {brdf, v, glm::dvec3(-v.x, 0.0, mu)};
}

// The lobe's f·cos θ_l averaged over the cap of solid angle `omega` around the spot's centre, by a
// midpoint rule in the cap's own (cos, φ).
double capMean(const Spot& s, double omega) {
  const glm::dvec3 c = s.centre, t = glm::normalize(glm::cross(c, glm::dvec3(0.0, 1.0, 0.0))), b = glm::cross(c, t);
  const double lowest = 1.0 - omega / (2.0 * kPi);
  constexpr int nz = 400, nphi = 200;
  double sum = 0.0;
  for (int i = 0; i < nz; ++i)
    for (int k = 0; k < nphi; ++k) {
      const double z = lowest + (1.0 - lowest) * (i + 0.5) / nz, phi = 2.0 * kPi * (k + 0.5) / nphi;
      const double r = std::sqrt(1.0 - z * z);
      const glm::dvec3 l = r * std::cos(phi) * t + r * std::sin(phi) * b + z * c;
      if (l.z > 0.0) sum += gpu::evalBrdf(s.brdf, glm::vec3(l), glm::vec3(s.v), 0.0f).x * l.z;
    }
  return sum / (nz * nphi);
}

}  // namespace

// What iv reflects of a sender (lobe_links.glsl): the lobe widened by the sender's spread, at the
// sender's centre, standing for the lobe's mean over the sender's disk. Toward grazing the half
// vector spreads across the plane of incidence 1/μ times as far as within it, which an isotropic
// widening (widenedLobe: 2.6 times the mean at μ 0.28, α 0.09, a disk of 16 bins) leaves out.
TEST(Brdf, AWidenedLobeAtADisksCentreIsTheLobesMeanOverIt) {
  const double bin = 4.0 * kPi / 1536.0;  // a bin of iv's defaults, 6·16²
  for (double mu : {0.9, 0.5, 0.28})
    for (double alpha : {0.04, 0.09, 0.25})
      for (double bins : {1.0, 4.0, 16.0}) {
        const Spot s = spotOf(alpha, mu);
        const double omega = bins * bin, mean = capMean(s, omega);
        const double widened =
            gpu::widenedSpecular(s.brdf, glm::vec3(s.centre), glm::vec3(s.v), float(omega / (4.0 * kPi))).x *
            s.centre.z;
        EXPECT_NEAR(widened / mean, 1.0, 0.07) << "mu " << mu << " alpha " << alpha << " bins " << bins;
      }
}

// Away from the lobe's peak the mean over a disk is the narrow lobe's value at its centre, where a
// lobe widened by the disk (α'² = α² + spread) has a tail heavier by α'²/α² (2.3 times at α 0.09
// and a disk of 16 bins, more across the plane of incidence at grazing). With widenedTailFactor the
// widened lobe stays within 20 % of the disk's mean, for disks three and six of their radii from
// the peak, along the plane of incidence and across it.
TEST(Brdf, AWidenedLobeAwayFromItsPeakIsTheLobesMeanOverTheDisk) {
  const double bin = 4.0 * kPi / 1536.0;
  double worst = 0.0;
  for (double mu : {0.9, 0.5, 0.28})
    for (double alpha : {0.09, 0.25})
      for (double bins : {1.0, 4.0, 16.0})
        for (double radii : {3.0, 6.0})
          for (bool across : {false, true}) {
            Spot s = spotOf(alpha, mu);
            const double omega = bins * bin, radius = std::acos(1.0 - omega / (2.0 * kPi));
            // Turned about the axis that keeps it in the plane of incidence (along) or takes it out
            // of it (across).
            const glm::dvec3 c = s.centre;
            const glm::dvec3 axis =
                glm::normalize(glm::cross(c, across ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0)));
            const double angle = radii * radius;
            s.centre = glm::normalize(std::cos(angle) * c + std::sin(angle) * glm::cross(axis, c));
            if (s.centre.z - radius < 0.05) continue;  // the disk must lie wholly above the surface
            const double mean = capMean(s, omega);
            const double widened =
                gpu::widenedSpecular(s.brdf, glm::vec3(s.centre), glm::vec3(s.v), float(omega / (4.0 * kPi))).x *
                s.centre.z;
            EXPECT_NEAR(widened / mean, 1.0, 0.2) << "mu " << mu << " alpha " << alpha << " bins " << bins << ", "
                                                  << radii << " radii " << (across ? "across" : "along");
            worst = std::max(worst, std::abs(widened / mean - 1.0));
          }
  std::printf("[ brdf ] a widened lobe away from its peak: at most %.3f off the disk's mean\n", worst);
}

// Senders tiling the sphere (a Fibonacci lattice of iv's 1,536 bins, each a disk of a bin's solid
// angle) reflect, each through the lobe widened by its disk at its centre, what the lobe does of
// even light: its albedo.
TEST(Brdf, WidenedLobesOverSendersTilingTheSphereSumToTheAlbedo) {
  constexpr int kSenders = 1536;
  const double omega = 4.0 * kPi / kSenders;
  for (double mu : {0.9, 0.5, 0.28})
    for (double alpha : {0.04, 0.09, 0.25}) {
      if (alpha < 0.05 && mu < 0.3) continue;  // a lobe this narrow at grazing falls between the senders
      const Spot s = spotOf(alpha, mu);
      double sum = 0.0;
      for (int i = 0; i < kSenders; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / kSenders, phi = kPi * (1.0 + std::sqrt(5.0)) * (i + 0.5),
                     r = std::sqrt(1.0 - z * z);
        const glm::vec3 l(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
        sum += gpu::widenedSpecular(s.brdf, l, glm::vec3(s.v), float(omega / (4.0 * kPi))).x * std::max(z, 0.0) * omega;
      }
      const Reference white{{.base = glm::dvec3(1.0), .metallic = 1.0, .roughness = std::sqrt(alpha)}};
      EXPECT_NEAR(sum / white.directionalAlbedo(mu).x, 1.0, 0.05) << "mu " << mu << " alpha " << alpha;
    }
}

// The path tracer against closed forms: the furnace, direct light under a square emitter, the
// configuration factor of two parallel squares (also from iv's form-factor code), the 1/√spp
// convergence, independence of the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "engine/image/metrics.h"
#include "engine/reference/path_tracer.h"
#include "engine/scene/gltf.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "shaders/interface.h"
#include "tests/test_support.h"

using namespace ivgi;

namespace {

constexpr double kPi = 3.14159265358979;

// A scene ready for the tracer at time 0.
struct Traced {
  scene::Scene scene;
  scene::Geometry geometry;
  std::unique_ptr<reference::PathTracer> tracer;
  explicit Traced(const tinygltf::Model& model)
      : scene(scene::sceneFromModel(model, "test")), geometry(scene::buildGeometry(scene)) {
    auto pose = scene::evaluatePose(scene, -1, 0.0f);
    tracer = std::make_unique<reference::PathTracer>(reference::PathScene::at(scene, geometry, pose));
  }
  image::FrameChannels render(uint32_t w, uint32_t h, const reference::PathSettings& settings) const {
    auto pose = scene::evaluatePose(scene, -1, 0.0f);
    return tracer->render(scene::cameraView(scene, pose, scene.cameraNodes().at(0)), w, h, 0, settings);
  }
};

double meanRadiance(const image::FrameChannels& f, int channel = 0) {
  double sum = 0;
  for (const auto& r : f.radiance) sum += r[channel];
  return sum / double(f.radiance.size());
}

// Form factor from a point to a parallel a × b rectangle at height c whose corner lies straight above it.
double cornerFormFactor(double a, double b, double c) {
  double x = a / c, y = b / c, sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPi);
}

// Emitter square [x0,x1]×[z0,z1] at height h facing down with radiance `radiance`, black floor.
tinygltf::Model squareOverFloor(float x0, float x1, float z0, float z1, float h, float radiance) {
  scenes::GltfBuilder b;
  int lamp = b.material("lamp", glm::vec3(0.0f), glm::vec3(radiance));
  int floor = b.material("floor", glm::vec3(0.0f));
  scenes::MeshData emitter, ground;
  scenes::addQuad(emitter, {x0, h, z0}, {x1, h, z0}, {x1, h, z1}, {x0, h, z1}, 2, 2, {0, -1, 0});
  scenes::addQuad(ground, {-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}, 1, 1, {0, 1, 0});
  b.node("scene", b.mesh("scene", {{emitter, lamp}, {ground, floor}}));
  return b.finish();
}

}  // namespace

// Closed furnace, every face emitting Le = 1 with albedo ρ = 0.5: radiance Le/(1−ρ) = 2 with
// unlimited bounces, and Le·Σ_{i≤K+1} ρ^i with K indirect bounces (K = 0: emission plus direct light).
// Tolerance 1.5 %: about five standard errors of the image mean at this sample count (measured
// spread of the per-run means ≈ 0.2 %).
TEST(PtFurnace, RadianceIsEmissionOverOneMinusAlbedo) {
  Traced t(scenes::furnace({.cells = 4, .albedo = 0.5f, .emission = 1.0f}));
  double unlimited = meanRadiance(t.render(32, 32, {.spp = 32}));
  std::printf("[ pt furnace ] unlimited: %.4f (exact 2)\n", unlimited);
  EXPECT_NEAR(unlimited, 2.0, 0.03);
  for (int k : {0, 1, 3}) {
    double exact = 0;
    for (int i = 0; i <= k + 1; ++i) exact += std::pow(0.5, i);
    double got = meanRadiance(t.render(32, 32, {.spp = 16, .bounces = k}));
    std::printf("[ pt furnace ] --bounces %d: %.4f (exact %.4f)\n", k, got, exact);
    EXPECT_NEAR(got, exact, 0.015 * exact) << "bounces " << k;
  }
}

// The Cornell box's room closed, with its blocks, every face the furnace's: corners, contacts and
// shadows change nothing, the radiance is still Le/(1−ρ) = 2 (the scene the solvers' furnace tests
// with occluders rest on; a gap in its walls would let paths escape and darken it).
TEST(PtFurnace, BlocksInsideChangeNothing) {
  Traced t(scenes::furnace({.cells = 4, .albedo = 0.5f, .emission = 1.0f, .blocks = true}));
  double got = meanRadiance(t.render(32, 32, {.spp = 32}));
  std::printf("[ pt furnace ] with blocks: %.4f (exact 2)\n", got);
  EXPECT_NEAR(got, 2.0, 0.03);
}

// High albedo: long paths, ended only by roulette, still converge to Le/(1−ρ) = 10.
TEST(PtFurnace, HighAlbedoConvergesThroughRoulette) {
  Traced t(scenes::furnace({.cells = 4, .albedo = 0.9f, .emission = 1.0f}));
  double got = meanRadiance(t.render(32, 32, {.spp = 32}));
  std::printf("[ pt furnace ] rho 0.9: %.4f (exact 10)\n", got);
  EXPECT_NEAR(got, 10.0, 0.3);
}

// Direct irradiance on the floor under a 0.4 × 0.3 emitter at height 0.5, at its centre's foot and
// off-centre, against the closed-form point-to-rectangle form factor (sum of four corner
// rectangles): E = π·L·F. 20,000 samples per point; tolerance 1 %.
TEST(PtDirectLight, IrradianceUnderASquareEmitterMatchesTheClosedForm) {
  const float x0 = -0.2f, x1 = 0.2f, z0 = -0.15f, z1 = 0.15f, h = 0.5f, L = 4.0f;
  Traced t(squareOverFloor(x0, x1, z0, z1, h, L));
  for (glm::vec2 p : {glm::vec2(0.0f, 0.0f), glm::vec2(0.12f, -0.05f)}) {
    double f = cornerFormFactor(x1 - p.x, z1 - p.y, h) + cornerFormFactor(p.x - x0, z1 - p.y, h) +
               cornerFormFactor(x1 - p.x, p.y - z0, h) + cornerFormFactor(p.x - x0, p.y - z0, h);
    double exact = kPi * L * f;
    double got = t.tracer->irradiance({p.x, 0.0f, p.y}, {0, 1, 0}, 20000, {.bounces = 0}).x;
    std::printf("[ pt direct ] floor (%.2f, %.2f): E %.5f, exact %.5f (%+.2f %%)\n", p.x, p.y, got, exact,
                100 * (got - exact) / exact);
    EXPECT_NEAR(got, exact, 0.01 * exact);
  }
}

// The same check in the Cornell room (the value iv's IvDirectLight test measures against): direct
// irradiance at the floor centre of the empty room from the ceiling light, exact by quadrature.
TEST(PtDirectLight, CornellFloorCentre) {
  const glm::dvec3 p(0.278, 0.0, 0.2795);
  const double exact = test::cornellLightIrradiance(p, {0, 1, 0}, 400);
  Traced t(scenes::cornellBox({.cells = 4, .animated = false, .blocks = false}));
  double got = t.tracer->irradiance(glm::vec3(p) + glm::vec3(0, 1e-4f, 0), {0, 1, 0}, 20000, {.bounces = 0}).x;
  std::printf("[ pt direct ] Cornell floor centre: E %.4f, exact %.4f (%+.2f %%)\n", got, exact,
              100 * (got - exact) / exact);
  EXPECT_NEAR(got, exact, 0.01 * exact);
}

// Two parallel unit squares one unit apart: configuration factor 0.19982 (closed form below).
// iv's form factor (the clamped disk of docs/design.md §2.1), summed over 32×32 patches of each, and pt's
// irradiance averaged over an 8×8 grid of the receiver (midpoint rule) must both give it within 1 %.
TEST(ConfigurationFactor, ParallelUnitSquares) {
  const double X = 1, Y = 1;
  const double exact =
      2 / (kPi * X * Y) *
      (std::log(std::sqrt((1 + X * X) * (1 + Y * Y) / (1 + X * X + Y * Y))) +
       X * std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y)) +
       Y * std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) - X * std::atan(X) - Y * std::atan(Y));
  EXPECT_NEAR(exact, 0.1998, 1e-4);

  const int n = 32;
  const float a = 1.0f / float(n * n);
  double iv = 0;
  for (int i = 0; i < n * n; ++i)
    for (int j = 0; j < n * n; ++j) {
      glm::vec3 r((i % n + 0.5f) / n, 0.0f, (i / n + 0.5f) / n), s((j % n + 0.5f) / n, 1.0f, (j / n + 0.5f) / n);
      glm::vec3 d = s - r;
      float d2 = glm::dot(d, d), c = d.y / std::sqrt(d2);
      iv += a * gpu::formFactor(a, c, c, d2);  // area-weighted: F = (1/A_r) Σ A_i F_ij with A_r = 1
    }

  Traced t(squareOverFloor(0, 1, 0, 1, 1, 1.0f));
  double pt = 0;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      pt += t.tracer->irradiance({(i + 0.5f) / 8, 0.0f, (j + 0.5f) / 8}, {0, 1, 0}, 4000, {.bounces = 0}).x / kPi / 64;
  std::printf("[ configuration factor ] exact %.5f, iv form factors %.5f (%+.2f %%), pt %.5f (%+.2f %%)\n", exact, iv,
              100 * (iv - exact) / exact, pt, 100 * (pt - exact) / exact);
  EXPECT_NEAR(iv, exact, 0.01 * exact);
  EXPECT_NEAR(pt, exact, 0.01 * exact);
}

// Monte Carlo error falls like 1/√spp: the RMSE against a 2048-spp render of the Cornell box (an
// independent seed) halves, within 20 %, each time spp grows fourfold. Pixels that see the light are
// left out: their error is the light's coverage of the pixel (radiance 17 or nothing per sample),
// so a handful of them would decide the RMSE of a small image.
TEST(PtConvergence, ErrorFallsLikeOneOverSqrtSpp) {
  Traced t(scenes::cornellBox({.cells = 2, .animated = false}));
  auto refFrame = t.render(32, 32, {.spp = 2048, .seed = 0});
  auto ref = image::radianceOf(refFrame);
  std::vector<uint8_t> light(ref.pixels.size());
  for (size_t i = 0; i < light.size(); ++i) light[i] = refFrame.emission[i].r > 0.0f;
  std::vector<double> rmse;
  for (uint32_t spp : {4u, 16u, 64u}) {
    rmse.push_back(image::measureError(image::radianceOf(t.render(32, 32, {.spp = spp, .seed = 1})), ref, light).rmse);
    std::printf("[ pt convergence ] spp %3u: RMSE %.5f\n", spp, rmse.back());
  }
  for (size_t i = 1; i < rmse.size(); ++i) {
    double ratio = rmse[i - 1] / rmse[i];
    EXPECT_GT(ratio, 1.6) << "spp step " << i;
    EXPECT_LT(ratio, 2.4) << "spp step " << i;
  }
}

// Seeds are per pixel: one thread and three threads give the same image, bit for bit; another seed
// gives another.
TEST(PtDeterminism, SameImageForAnyThreadCount) {
  Traced t(scenes::cornellBox({.cells = 2}));
  auto one = t.render(20, 16, {.spp = 4, .threads = 1}), three = t.render(20, 16, {.spp = 4, .threads = 3});
  auto other = t.render(20, 16, {.spp = 4, .seed = 5, .threads = 3});
  size_t same = 0;
  for (size_t i = 0; i < one.radiance.size(); ++i) {
    EXPECT_EQ(one.radiance[i], three.radiance[i]) << i;
    same += one.radiance[i] == other.radiance[i];
  }
  EXPECT_LT(same, one.radiance.size() / 2);
}

// The rendered image, not only the estimator: direct light only (--bounces 0) in the empty Cornell
// room, the mean radiance of floor regions (pixels whose normal is up, their world position from the
// depth layer) against ρ/π·E with E the light's rectangle integrated by quadrature at each pixel's
// centre. Whole floor and its four quadrants, within 1.5 % (256 spp; pixel-area averaging of a
// smooth E adds < 0.1 %).
TEST(PtDirectLight, FloorRegionMeansOfTheRenderedImage) {
  Traced t(scenes::cornellBox({.cells = 4, .animated = false, .blocks = false}));
  const uint32_t w = 64, h = 64;
  auto frame = t.render(w, h, {.spp = 256, .bounces = 0});
  auto pose = scene::evaluatePose(t.scene, -1, 0.0f);
  const gpu::Camera cam = scene::gpuCamera(scene::cameraView(t.scene, pose, t.scene.cameraNodes().at(0)), 1.0f);
  auto exactRadiance = [](glm::dvec3 p) {
    return 0.725 * test::cornellLightIrradiance(p, {0, 1, 0}, 48) / kPi;
  };  // white floor, red channel
  double got[5] = {}, exact[5] = {};
  int count[5] = {};
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      size_t i = size_t(y) * w + x;
      glm::vec4 nd = frame.normalDepth[i];
      if (nd.y < 0.99f || nd.w <= 0.0f || frame.radiance[i].a < 1.0f) continue;  // floor pixels, fully covered
      glm::dvec3 p = glm::dvec3(glm::vec3(cam.origin) + nd.w * gpu::cameraRay(cam, glm::vec2(x, y) + 0.5f, {w, h}));
      if (p.x < 0.02 || p.x > 0.53 || p.z < 0.02 || p.z > 0.54) continue;  // away from the walls' pixels
      int quadrant = 1 + (p.x > 0.278) + 2 * (p.z > 0.2795);
      for (int k : {0, quadrant}) got[k] += frame.radiance[i].r, exact[k] += exactRadiance(p), ++count[k];
    }
  ASSERT_GT(count[0], 200);
  for (int k = 0; k < 5; ++k) {
    ASSERT_GT(count[k], 20) << "region " << k;
    std::printf("[ pt direct ] floor region %d (%d px): mean %.5f, exact %.5f (%+.2f %%)\n", k, count[k],
                got[k] / count[k], exact[k] / count[k], 100 * (got[k] - exact[k]) / exact[k]);
    EXPECT_NEAR(got[k] / exact[k], 1.0, 0.015) << "region " << k;
  }
}

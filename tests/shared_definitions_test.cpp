// The functions of shaders/interface.h give on the GPU what they give on the host, where both sides
// use their results: key packing and ordering, texel addressing, camera rays, bins, form factors,
// tangent frames and lights; and the definitions have the properties the solver relies on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>

#include "engine/scene/camera.h"
#include "engine/vk/program.h"
#include "shaders/interface.h"
#include "tests/test_support.h"

namespace ivgi {
std::span<const uint32_t> testShaderCode(const std::string& name);
}

using namespace ivgi;

namespace {

struct Case {
  float value;
  uint32_t id, size, mode;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  const float values[] = {0.0f, 1e-30f, 1e-6f,  0.25f, 0.5f, 0.999999f, 1.0f,
                          1.5f, 2.75f,  -0.25f, -3.6f, 1e6f, 123.456f,  7.0f};
  const uint32_t modes[] = {10497u, 33071u, 33648u};
  const uint32_t sizes[] = {1u, 2u, 7u, 64u};
  uint32_t id = 0;
  for (float v : values)
    for (uint32_t m : modes)
      for (uint32_t s : sizes) out.push_back({v, id++ * 2654435761u, s, m});
  return out;
}

}  // namespace

TEST(SharedDefinitions, GlslAndCppAgree) {
  auto& ctx = test::gpu();
  auto cs = cases();
  vk::Program program(ctx, "common_cases", testShaderCode("common_cases"));
  vk::Buffer in = vk::makeBuffer(ctx, cs);
  vk::Buffer keys(ctx, cs.size() * 8, vk::Memory::Host), pairs(ctx, cs.size() * 16, vk::Memory::Host),
      rays(ctx, cs.size() * 16, vk::Memory::Host);
  vk::Buffer staticBins(ctx, cs.size() * 16, vk::Memory::Host);
  scene::CameraView view;
  view.origin = {1, 2, 3};
  view.forward = glm::normalize(glm::vec3(0.2f, -0.1f, -1.0f));
  view.right = glm::normalize(glm::cross(view.forward, glm::vec3(0, 1, 0)));
  view.up = glm::cross(view.right, view.forward);
  view.yfov = 0.6f;
  const gpu::ResolvePush push{.camera = scene::gpuCamera(view, 1.5f), .size = {48, 32}, .samples = uint32_t(cs.size())};
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    program.dispatchItems(cmd, cs.size(),
                          {{"cases", in}, {"keys", keys}, {"pairs", pairs}, {"rays", rays}, {"staticBins", staticBins}},
                          push);
  });
  auto gotKeys = keys.read<uint64_t>(cs.size());
  auto gotPairs = pairs.read<glm::vec4>(cs.size());
  auto gotRays = rays.read<glm::vec4>(cs.size());
  auto gotStaticBins = staticBins.read<glm::uvec4>(cs.size());

  for (size_t i = 0; i < cs.size(); ++i) {
    const Case& c = cs[i];
    if (c.value >= 0.0f) {  // keys are defined for depths >= 0
      EXPECT_EQ(gotKeys[i], gpu::packDepthKey(c.value, c.id)) << i;
      EXPECT_EQ(gotPairs[i].w, 1.0f) << "keyDepth/keyId round trip, case " << i;
    }
    float weight;
    glm::ivec2 pair = gpu::texelPair(c.value, int(c.size), c.mode, weight);
    EXPECT_EQ(glm::ivec2(gotPairs[i]), pair) << "u " << c.value << " size " << c.size << " mode " << c.mode;
    EXPECT_NEAR(gotPairs[i].z, weight, 1e-3f) << "u " << c.value << " size " << c.size << " mode " << c.mode;
    EXPECT_GE(pair.x, 0);
    EXPECT_LT(pair.y, int(c.size));
    glm::vec3 ray = gpu::cameraRay(push.camera, glm::vec2(c.value, float(c.id % 7u)) * float(push.size.x), push.size);
    EXPECT_LT(glm::length(glm::vec3(gotRays[i]) - ray), 1e-4f * std::max(1.0f, glm::length(ray))) << i;
    // A static leaf link's bin (any of 6·64² bins) and its coverage, capped at the whole bin.
    const uint32_t bin = c.id % 24576u, covered = c.id >> 13, packed = gpu::packStaticBin(bin, covered);
    EXPECT_EQ(gotStaticBins[i], glm::uvec4(packed, bin, std::min(covered, gpu::kCoverageUnit), 0u))
        << "covered " << covered;
    EXPECT_EQ(gpu::staticBinOf(packed), bin);
    EXPECT_EQ(gpu::staticCoverageOf(packed), std::min(covered, gpu::kCoverageUnit));
  }
}

TEST(SharedDefinitions, KeysOrderByDepthThenId) {
  // atomicMin on the key must keep the nearest hit, ties broken by the lower id.
  std::vector<std::pair<float, uint32_t>> hits = {{2.0f, 1}, {0.5f, 9}, {0.5f, 3}, {1e-20f, 7}, {1e20f, 0}, {0.0f, 4}};
  std::vector<uint64_t> keys;
  for (auto [d, id] : hits) keys.push_back(gpu::packDepthKey(d, id));
  auto sortedHits = hits;
  std::sort(sortedHits.begin(), sortedHits.end());
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i < keys.size(); ++i) {
    EXPECT_EQ(gpu::keyDepth(keys[i]), sortedHits[i].first);
    EXPECT_EQ(gpu::keyId(keys[i]), sortedHits[i].second);
  }
  EXPECT_LT(gpu::packDepthKey(1e30f, ~0u - 1), gpu::kEmptyVisibility) << "any hit beats an empty sample";
}

TEST(SharedDefinitions, LinkKeysRankCoresBeforeFringes) {
  // A bin goes to the nearest sender centred in it; a sender that only brushes it wins it only
  // where no core reached it, and then the nearest such.
  EXPECT_LT(gpu::packLinkKey(1e20f, 9, false), gpu::packLinkKey(1e-20f, 1, true)) << "a far core beats a near fringe";
  EXPECT_LT(gpu::packLinkKey(0.5f, 9, true), gpu::packLinkKey(2.0f, 1, true)) << "among fringes the nearest";
  EXPECT_LT(gpu::packLinkKey(0.5f, 3, false), gpu::packLinkKey(0.5f, 9, false)) << "ties by id";
  EXPECT_LT(gpu::packLinkKey(3.4e38f, ~0u - 1, true), gpu::kEmptyVisibility) << "any sender beats an empty bin";
  EXPECT_EQ(gpu::linkKeyDepth(gpu::packLinkKey(0.25f, 5, true)), 0.25f);
  EXPECT_EQ(gpu::keyId(gpu::packLinkKey(0.25f, 5, true)), 5u);
}

TEST(SharedDefinitions, TexelPairsFollowTheWrapModes) {
  float w;
  EXPECT_EQ(gpu::texelPair(0.0f, 4, 10497u, w), glm::ivec2(3, 0)) << "repeat wraps left of the first texel centre";
  EXPECT_FLOAT_EQ(w, 0.5f);
  EXPECT_EQ(gpu::texelPair(0.0f, 4, 33071u, w), glm::ivec2(0, 0)) << "clamp";
  EXPECT_EQ(gpu::texelPair(1.25f, 4, 10497u, w), glm::ivec2(0, 1)) << "repeat: 1.25 is 0.25";
  EXPECT_FLOAT_EQ(w, 0.5f);
  EXPECT_EQ(gpu::texelPair(1.25f, 4, 33648u, w), glm::ivec2(2, 3)) << "mirrored: 1.25 is 0.75";
  EXPECT_FLOAT_EQ(w, 0.5f);
}

namespace {

struct BinCase {
  glm::vec4 direction;  // w: cosine of the sender
  uint32_t n, bin;
  float area, distance2;
};
struct BinResult {
  uint32_t bin;
  float solidAngle, formFactor;
  uint32_t roundTrip;
  glm::vec4 centre;
  uint64_t key, fringeKey;
  float fringeDepth;
  uint32_t beyond;
  uint32_t pad[2];
  glm::vec4 tangent;
};

}  // namespace

TEST(SharedDefinitions, BinsAndFormFactorsAgree) {
  auto& ctx = test::gpu();
  std::vector<BinCase> cs;
  uint32_t seed = 12345;
  auto rnd = [&] {
    seed = seed * 1664525u + 1013904223u;
    return float(seed >> 8) / float(1 << 24) * 2.0f - 1.0f;
  };
  for (uint32_t n : {1u, 2u, 3u, 8u, 12u, 16u, 33u, 64u})
    for (int k = 0; k < 40; ++k) {
      glm::vec3 d(rnd(), rnd(), rnd());
      if (k < 6) d = glm::vec3(0.0f), d[k / 2] = (k % 2) ? -1.0f : 1.0f;  // the axes themselves
      if (k == 6) d = glm::vec3(1.0f, 1.0f, 1.0f);                        // a cube corner: ties between axes
      cs.push_back({glm::vec4(d, rnd()), n, uint32_t(std::abs(rnd()) * 6 * n * n) % (6 * n * n), std::abs(rnd()) * 3.0f,
                    k == 7 ? 0.0f : std::abs(rnd()) * 10.0f});
    }
  vk::Program program(ctx, "bin_cases", testShaderCode("bin_cases"));
  vk::Buffer in = vk::makeBuffer(ctx, cs);
  vk::Buffer out(ctx, cs.size() * sizeof(BinResult), vk::Memory::Host);
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    program.dispatchItems(cmd, cs.size(), {{"cases", in}, {"results", out}},
                          gpu::CountPush{.count = uint32_t(cs.size())});
  });
  auto got = out.read<BinResult>(cs.size());
  for (size_t i = 0; i < cs.size(); ++i) {
    const BinCase& c = cs[i];
    glm::vec3 d(c.direction);
    EXPECT_EQ(got[i].bin, gpu::binOf(d, c.n)) << "case " << i;
    // GLSL atan is an approximation (lavapipe's is within about 3e-6 of libm), and the solid angle
    // is a difference of four such terms: the solver builds its bin table on the host for that reason.
    EXPECT_NEAR(got[i].solidAngle, gpu::binSolidAngle(c.bin, c.n), 1.5e-5f) << "case " << i;
    float ff = gpu::formFactor(c.area, c.direction.w, c.direction.x, c.distance2);
    EXPECT_NEAR(got[i].formFactor, ff, 1e-6f * std::max(1.0f, ff)) << "case " << i;
    EXPECT_EQ(got[i].roundTrip, c.bin) << "a bin's centre falls in the bin, case " << i;
    EXPECT_EQ(glm::vec3(got[i].centre), gpu::binDirection(c.bin, c.n));
    EXPECT_EQ(got[i].key, gpu::packLinkKey(c.distance2, c.bin, false)) << "case " << i;
    EXPECT_EQ(got[i].fringeKey, gpu::packLinkKey(c.distance2, c.bin, true)) << "case " << i;
    EXPECT_EQ(got[i].fringeDepth, c.distance2) << "a fringe key keeps its depth, case " << i;
    uint32_t r = c.bin % (c.n * c.n);
    EXPECT_EQ(got[i].beyond, gpu::binOfCell(c.bin / (c.n * c.n), glm::ivec2(int(r % c.n), -1 - int(r / c.n)), c.n))
        << "case " << i;
    if (glm::length(d) > 0.0f) {
      glm::vec3 t1, t2;
      gpu::tangentFrame(glm::normalize(d), t1, t2);
      EXPECT_LT(glm::length(glm::vec3(got[i].tangent) - t1), 1e-5f) << "tangent frame, case " << i;
      EXPECT_NEAR(glm::dot(t1, glm::normalize(d)), 0.0f, 1e-5f);
    }
  }
}

TEST(SharedDefinitions, BinSolidAnglesCoverTheSphere) {
  for (uint32_t n : {1u, 2u, 4u, 8u, 12u, 16u, 32u, 64u}) {
    double sum = 0;
    float smallest = 1e9f, largest = 0;
    for (uint32_t b = 0; b < 6 * n * n; ++b) {
      float w = gpu::binSolidAngle(b, n);
      sum += w;
      smallest = std::min(smallest, w), largest = std::max(largest, w);
      ASSERT_EQ(gpu::binOf(gpu::binDirection(b, n), n), b);
      ASSERT_EQ(gpu::oppositeBin(b, n), gpu::binOf(-gpu::binDirection(b, n), n)) << "bin " << b << " of n " << n;
    }
    EXPECT_NEAR(sum, 4.0 * 3.14159265358979, 1e-4) << n;
    if (n >= 16) {
      EXPECT_GT(largest / smallest, 4.0f) << "corner bins are several times smaller than centre bins";
    }
  }
  EXPECT_NEAR(gpu::binSolidAngle(0, 1), 4.0f * 3.14159265f / 6.0f, 1e-6f) << "one bin per face: a sixth of the sphere";
}

// The prune files a footprint across a cube edge on both sides: a cell just past a face's edge is
// a bin of the neighbouring face that touches the edge, beside the face's own edge bin.
TEST(SharedDefinitions, CellsPastAFaceEdgeFallOnItsNeighbour) {
  for (uint32_t n : {1u, 2u, 8u, 16u, 33u}) {
    const float binWidth = 2.0f / float(n);  // on the unit cube, at the edge
    for (uint32_t face = 0; face < 6; ++face)
      for (int along = 0; along < int(n); ++along)
        for (glm::ivec2 step : {glm::ivec2(0, -1), glm::ivec2(0, 1), glm::ivec2(-1, 0), glm::ivec2(1, 0)}) {
          // The face's own edge bin, and the cell one step past it.
          glm::ivec2 inside = step.x != 0 ? glm::ivec2(step.x < 0 ? 0 : int(n) - 1, along)
                                          : glm::ivec2(along, step.y < 0 ? 0 : int(n) - 1);
          uint32_t own = gpu::binOfCell(face, inside, n), past = gpu::binOfCell(face, inside + step, n);
          ASSERT_EQ(own, face * n * n + uint32_t(inside.y) * n + uint32_t(inside.x));
          EXPECT_NE(past / (n * n), face) << "n " << n << " face " << face;
          // Centres on the unit cube: the two bins are neighbours across the edge.
          glm::vec3 a = gpu::binDirection(own, n), b = gpu::binDirection(past, n);
          EXPECT_LT(glm::length(a - b), 1.5f * binWidth) << "n " << n << " face " << face << " along " << along;
        }
  }
}

TEST(SharedDefinitions, FormFactorIsBoundedAndFinite) {
  EXPECT_EQ(gpu::formFactor(1.0f, 1.0f, 1.0f, 0.0f), 1.0f) << "d → 0 gives 1, not infinity";
  EXPECT_EQ(gpu::formFactor(1.0f, -0.5f, 1.0f, 1.0f), 0.0f) << "back faces send nothing";
  EXPECT_NEAR(gpu::formFactor(1e-4f, 1.0f, 1.0f, 1.0f), 1e-4f / 3.14159265f, 1e-4f * 1e-4f / 3.14159265f)
      << "far away: A cos cos / (π d²)";
  // Scale invariance: scaling areas by s² and distances by s leaves it unchanged.
  for (float s : {1e-3f, 1.0f, 1e3f})
    EXPECT_NEAR(gpu::formFactor(0.3f * s * s, 0.8f, 0.6f, 2.0f * s * s), gpu::formFactor(0.3f, 0.8f, 0.6f, 2.0f),
                1e-6f);
}

// lightFalloff() on the GPU (prune_bins' punctual lights) against the host (the path tracer's), for
// directional, point (with and without range) and spot
// lights (smooth cone and a hard one whose inner and outer cones coincide).
TEST(SharedDefinitions, LightFalloffMatchesOnTheGpu) {
  vk::Context& ctx = test::gpu();
  const glm::vec3 down(0, -1, 0);
  std::vector<gpu::PunctualLight> lights = {
      {glm::vec4(0, 0, 0, 0), glm::vec4(glm::normalize(glm::vec3(0.3f, -1, 0.2f)), 0), glm::vec4(1), glm::vec4(0)},
      {glm::vec4(0, 2, 0, 1), glm::vec4(down, 0), glm::vec4(1), glm::vec4(0)},
      {glm::vec4(0, 2, 0, 1), glm::vec4(down, 2.5f), glm::vec4(1), glm::vec4(0)},
      {glm::vec4(0, 2, 0, 2), glm::vec4(down, 0), glm::vec4(1), glm::vec4(std::cos(0.6f), std::cos(0.3f), 0, 0)},
      {glm::vec4(0, 2, 0, 2), glm::vec4(down, 0), glm::vec4(1), glm::vec4(std::cos(0.5f), std::cos(0.5f), 0, 0)},
  };
  std::vector<glm::vec4> points;
  for (int i = 0; i < 40; ++i) points.emplace_back(-2.0f + 0.1f * float(i), 0.0f, 0.05f * float(i % 5), 0.0f);
  points.emplace_back(0, 2, 0, 0);  // at a point light's position
  const uint32_t n = uint32_t(lights.size() * points.size());
  vk::Program program(ctx, "light_cases", testShaderCode("light_cases"));
  vk::Buffer lightBuffer = vk::makeBuffer(ctx, lights), pointBuffer = vk::makeBuffer(ctx, points);
  vk::Buffer results(ctx, n * 16, vk::Memory::Host), distances(ctx, n * 4, vk::Memory::Host);
  struct {
    uint32_t lightCount, pointCount;
  } push{uint32_t(lights.size()), uint32_t(points.size())};
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    program.dispatchItems(
        cmd, n, {{"lights", lightBuffer}, {"points", pointBuffer}, {"results", results}, {"distances", distances}},
        push);
  });
  auto got = results.read<glm::vec4>(n);
  auto gotDist = distances.read<float>(n);
  int lit = 0;
  for (uint32_t i = 0; i < n; ++i) {
    glm::vec3 toLight;
    float dist2,
        falloff = gpu::lightFalloff(lights[i / points.size()], glm::vec3(points[i % points.size()]), toLight, dist2);
    EXPECT_NEAR(got[i].w, falloff, 1e-4f * std::max(1.0f, falloff))
        << "light " << i / points.size() << " point " << i % points.size();
    EXPECT_LT(glm::length(glm::vec3(got[i]) - toLight), 1e-5f) << i;
    EXPECT_NEAR(gotDist[i], dist2, 1e-5f * std::max(1.0f, dist2)) << i;
    lit += falloff > 0.0f;
  }
  EXPECT_GT(lit, int(n / 3));  // the cases light something
  EXPECT_LT(lit, int(n));      // and the range, cones and the light's own position cut some off
}

// The range window and the spot cone of KHR_lights_punctual's reference code: 1 − (d/range)⁴ on
// the inverse square, and (t)² where t is the cosine's place between the outer cone (0) and the
// inner (1). The cone's square falls steeply past the inner cone and levels off toward the outer,
// as the extension asks of a conforming renderer (a smoothstep starts flat instead).
TEST(SharedDefinitions, LightFalloffFollowsKhrLightsPunctual) {
  const glm::vec3 down(0, -1, 0);
  glm::vec3 toLight;
  float dist2 = 0;
  const gpu::PunctualLight ranged{glm::vec4(0, 2, 0, gpu::kLightPoint), glm::vec4(down, 4.0f), glm::vec4(1),
                                  glm::vec4(0)};
  EXPECT_NEAR(gpu::lightFalloff(ranged, {0, 0, 0}, toLight, dist2), (1.0f - 0.0625f) / 4.0f, 1e-6f);  // d/range ½
  EXPECT_NEAR(gpu::lightFalloff(ranged, {0, -1, 0}, toLight, dist2), (1.0f - 0.75f * 0.75f * 0.75f * 0.75f) / 9.0f,
              1e-6f);
  EXPECT_EQ(gpu::lightFalloff(ranged, {0, -2, 0}, toLight, dist2), 0.0f) << "at the range";
  EXPECT_EQ(gpu::lightFalloff(ranged, {0, -3, 0}, toLight, dist2), 0.0f) << "past it";
  const float inner = 0.3f, outer = 0.6f;
  const gpu::PunctualLight spot{glm::vec4(0, 2, 0, gpu::kLightSpot), glm::vec4(down, 0.0f), glm::vec4(1),
                                glm::vec4(std::cos(outer), std::cos(inner), 0, 0)};
  // A point on the floor θ from the spot's axis, and what the extension's reference code gives there.
  auto at = [&](float theta) { return glm::vec3(2.0f * std::tan(theta), 0, 0); };
  auto reference = [&](float theta) {
    const float scale = 1.0f / std::max(0.001f, std::cos(inner) - std::cos(outer));
    const float t = std::clamp(std::cos(theta) * scale - std::cos(outer) * scale, 0.0f, 1.0f);
    return t * t * std::cos(theta) * std::cos(theta) / 4.0f;
  };
  for (float theta : {0.0f, 0.2f, 0.3f, 0.35f, 0.45f, 0.55f, 0.59f, 0.6f, 0.7f})
    EXPECT_NEAR(gpu::lightFalloff(spot, at(theta), toLight, dist2), reference(theta), 1e-6f) << "θ " << theta;
  // Halfway between the cones' cosines a quarter of the light, where a smoothstep would give half.
  const float half = std::acos(0.5f * (std::cos(inner) + std::cos(outer)));
  EXPECT_NEAR(gpu::lightFalloff(spot, at(half), toLight, dist2) / (1.0f / dist2), 0.25f, 1e-4f);
}

// lavapipe ends every loop of a subgroup, silently, once its loops together ran 65,535 rounds
// (common.glsl); loopBudgetSpent() must tell exactly when a loop was cut short, here and on any
// device (where nothing is cut, it must say nothing was). On lavapipe the budget is shared by all
// loops: two loops of 40,000 rounds each get cut, as does one of 70,000, but not one of 60,000.
TEST(SharedDefinitions, LoopBudgetSpentTellsWhenLoopsWereCutShort) {
  auto& ctx = test::gpu();
  const std::vector<glm::uvec2> cs = {{10, 0},        {60000, 0},  {40000, 20000}, {70000, 0},
                                      {40000, 40000}, {200000, 5}, {0, 0}};
  vk::Program program(ctx, "loop_budget_cases", testShaderCode("loop_budget_cases"));
  vk::Buffer in = vk::makeBuffer(ctx, cs);
  vk::Buffer out(ctx, cs.size() * sizeof(glm::uvec4), vk::Memory::Host);
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    program.dispatch(cmd, program.groupsFor(cs.size(), 1), {{"cases", in}, {"results", out}},
                     gpu::CountPush{.count = uint32_t(cs.size())});
  });
  const auto got = out.read<glm::uvec4>(cs.size());
  const bool lavapipe = ctx.info().name.find("llvmpipe") != std::string::npos;
  for (size_t i = 0; i < cs.size(); ++i) {
    const bool cut = got[i].x != cs[i].x || got[i].y != cs[i].y;
    std::printf("loops of %u and %u rounds ran %u and %u; spent: %u\n", cs[i].x, cs[i].y, got[i].x, got[i].y, got[i].z);
    EXPECT_EQ(got[i].z != 0, cut) << "case " << i;
    if (lavapipe) {
      EXPECT_EQ(cut, cs[i].x + cs[i].y > 65535) << "case " << i;
    }
  }
}

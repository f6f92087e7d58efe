// The iv method through the ivgi command: scale invariance, determinism, and every setting at its
// extremes finishing with finite, sensible images.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

#include "engine/gi/pass.h"
#include "engine/image/compare.h"
#include "engine/image/metrics.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "shaders/registry.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

struct Stats {
  double mean = 0, max = 0;
  size_t nonFinite = 0;
};

Stats radianceStats(const fs::path& exr) {
  OIIO_NAMESPACE::ImageBuf buf(exr.string());
  Stats st;
  if (!buf.read(0, 0, true, OIIO_NAMESPACE::TypeDesc::FLOAT)) {
    ADD_FAILURE() << exr << " unreadable";
    return st;
  }
  const float* p = static_cast<const float*>(buf.localpixels());
  size_t values = size_t(buf.spec().image_pixels()) * buf.spec().nchannels;
  for (size_t i = 0; i < values; ++i)
    if (!std::isfinite(p[i])) ++st.nonFinite;
  int r = buf.spec().channelindex("R");
  size_t pixels = size_t(buf.spec().image_pixels());
  for (size_t i = 0; i < pixels; ++i) {
    float v = p[i * buf.spec().nchannels + r];
    if (std::isfinite(v)) st.mean += v / double(pixels), st.max = std::max(st.max, double(v));
  }
  return st;
}

// The Cornell box with everything (camera and its near plane too) scaled by `s`.
std::string scaledCornell(float s) {
  tinygltf::Model m = test::scaled(scenes::cornellBox({.cells = 6, .animated = false}), s);
  for (auto& c : m.cameras) c.perspective.znear *= s;
  auto path = test::scratchDir("model-" + std::to_string(s)) / "cornell.gltf";
  scenes::writeModel(m, path.string());
  return path.string();
}

}  // namespace

// The mesh as modelled (--tessellate 0): tessellated, a few surfels at the hard edges of the short
// block's top differ by up to 3 % between the scales (docs/notes/receivers.md), so that 0.5 % of the
// pixels fail this rule.
TEST(IvScale, ImageIsTheSameFromMillimetresToKilometres) {
  fs::path unit = test::renderExr("unit", {scaledCornell(1.0f), "--size", "96x72", "--tessellate", "0"});
  for (float s : {1e-3f, 1e3f}) {
    fs::path scaled =
        test::renderExr("render-" + std::to_string(s), {scaledCornell(s), "--size", "96x72", "--tessellate", "0"});
    // Per pixel within 0.5 % of its own value (radiance) or of the range (normals), on all but 0.1 % of the pixels.
    for (const auto& d :
         image::compareLayers(scaled.string(), unit.string(), {{"", 0.005f, 0.001f, true}, {"N", 0.005f, 0.001f}}))
      EXPECT_TRUE(d.passed) << "scale " << s << " layer " << d.layer << ": " << 100 * d.failingFraction
                            << " % of pixels beyond " << d.threshold << ", max error " << d.maxError;
  }
}

TEST(IvDeterminism, TwoRunsGiveIdenticalFiles) {
  fs::path a = test::renderExr("a", {"cornell", "--cells", "6", "--size", "96x72", "--frames", "12"});
  fs::path b = test::renderExr("b", {"cornell", "--cells", "6", "--size", "96x72", "--frames", "12"});
  a.replace_filename("f_0012.exr"), b.replace_filename("f_0012.exr");
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  std::string da((std::istreambuf_iterator<char>(fa)), {}), db((std::istreambuf_iterator<char>(fb)), {});
  ASSERT_FALSE(da.empty());
  EXPECT_TRUE(da == db) << "the two EXRs differ";
}

// `bench` prints every pass's median and p90, the frame rate, the device, and the solver's figures,
// its prune's work included; its JSON carries the same.
TEST(IvBench, PrintsEveryPassAndTheSolversFigures) {
  const fs::path json = test::scratchDir("bench") / "b.json";
  // In a process of its own: the host's peak is the process's, and in-process the shard's earlier
  // tests would count (under AddressSanitizer, gigabytes of them).
  auto r = test::runIvgiProcess(
      {"bench", "--cells", "4", "--size", "64x48", "--frames", "2", "--warmup", "1", "--json", json.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* row : {"\nrefit ", "\nlinks ", "\nprune ", "\nbounces ", "\nraster ", "\nresolve ", "\ntotal ",
                          "fps", "LP_NUM_THREADS", "leaf links after push-down and pruning",
                          "root-path senders walked in the last frame", "bytes allocated", "host peak"})
    EXPECT_NE(r.out.find(row), std::string::npos) << row << " in\n" << r.out;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  for (const char* pass : {"refit", "links", "prune", "bounces", "total"})
    EXPECT_GT(j["passes"][pass]["medianMs"].get<double>(), 0.0) << pass;
  EXPECT_EQ(j["frames"].size(), 2u);
  // The moving block's pairs are walked every frame, the static ones once, and those are most.
  const auto walked = j["solver"]["sendersWalked"].get<uint64_t>(),
             once = j["solver"]["staticSendersWalked"].get<uint64_t>();
  EXPECT_GT(walked, 0u);
  EXPECT_GT(once, walked);
  EXPECT_GT(j["solver"]["leafLinks"].get<uint64_t>(), 0u);
  EXPECT_GT(j["bytesAllocated"].get<uint64_t>(), 0u);
  // The host's peak resident memory: at least what the process's code and the scene took, and
  // within a small scene's (not a runaway allocation).
  EXPECT_GT(j["hostPeakMiB"].get<double>(), 10.0);
  EXPECT_LT(j["hostPeakMiB"].get<double>(), 4096.0);
}

// `bench --per-program` times every dispatch by its program: each a shader of the build, each
// frame's dispatches within its passes' time; without the flag nothing is timed that way.
TEST(IvBench, PerProgramTimesEveryDispatchByItsShader) {
  const fs::path json = test::scratchDir("bench") / "programs.json";
  auto r = test::runIvgi({"bench", "--cells", "4", "--size", "64x48", "--frames", "2", "--warmup", "1", "--per-program",
                          "--json", json.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\nprune_bins "), std::string::npos) << r.out;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  for (const char* program :
       {"animate", "refine_links", "prune_bins", "refine_receivers", "gather", "raster", "resolve"})
    ASSERT_TRUE(j["programs"].contains(program)) << program;
  for (const auto& [name, figures] : j["programs"].items()) {
    EXPECT_NO_THROW(shaderCode(name)) << name << " is no shader";
    EXPECT_GE(figures["dispatches"].get<double>(), 1.0) << name;
  }
  ASSERT_EQ(j["frames"].size(), 2u);
  for (const auto& frame : j["frames"]) {
    double dispatches = 0;
    for (const auto& [name, p] : frame["programs"].items()) {
      EXPECT_GE(p["ms"].get<double>(), 0.0) << name;
      dispatches += p["ms"].get<double>();
    }
    EXPECT_GT(dispatches, 0.0);
    EXPECT_LE(dispatches, frame["totalGpuMs"].get<double>()) << "each dispatch lies within its pass";
  }

  const fs::path plain = test::scratchDir("bench") / "plain.json";
  r = test::runIvgi(
      {"bench", "--cells", "2", "--size", "32x24", "--frames", "1", "--warmup", "0", "--json", plain.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.find("prune_bins"), std::string::npos) << r.out;
  std::ifstream plainIn(plain);
  EXPECT_TRUE(nlohmann::json::parse(plainIn)["programs"].empty());

  r = test::runIvgi({"bench", "--equal-error", "--per-program", "--cells", "2"});
  EXPECT_EQ(r.status, 1);
  ASSERT_EQ(r.errLines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("--per-program"), std::string::npos) << r.err;
}

TEST(IvExtremes, BinsFromOneToSixtyFour) {
  for (const char* bins : {"1", "64"}) {
    Stats st = radianceStats(
        test::renderExr(std::string("bins") + bins, {"cornell", "--cells", "3", "--size", "48x36", "--bins", bins}));
    EXPECT_EQ(st.nonFinite, 0u) << bins;
    EXPECT_GT(st.mean, 0.01) << "the box is lit, bins " << bins;
  }
}

TEST(IvExtremes, EpsilonFromOneToOneMillionth) {
  for (const char* eps : {"1", "1e-6"}) {
    Stats st = radianceStats(test::renderExr(
        std::string("eps"), {"cornell", "--cells", "2", "--size", "48x36", "--bins", "8", "--eps", eps}));
    EXPECT_EQ(st.nonFinite, 0u) << eps;
    EXPECT_GT(st.mean, 0.01) << "eps " << eps;
  }
}

TEST(IvExtremes, AlbedoZeroAndNearlyOne) {
  // Furnace, Le = 1: with ρ = 0 the image is exactly the emission; with ρ = 0.99 it is brighter,
  // finite, and below the exact 1/(1−ρ) = 100.
  auto dir = test::scratchDir("furnaces");
  for (float rho : {0.0f, 0.99f}) {
    std::string file = (dir / ("furnace_" + std::to_string(rho) + ".gltf")).string();
    scenes::writeModel(scenes::furnace({.cells = 4, .albedo = rho, .emission = 1.0f}), file);
    Stats st =
        radianceStats(test::renderExr("furnace-" + std::to_string(rho), {file, "--size", "32x32", "--bounces", "40"}));
    EXPECT_EQ(st.nonFinite, 0u);
    if (rho == 0.0f) {
      EXPECT_NEAR(st.mean, 1.0, 1e-5);
      EXPECT_NEAR(st.max, 1.0, 1e-5);
    } else {
      EXPECT_GT(st.mean, 5.0);
      EXPECT_LT(st.max, 100.0);
    }
  }
}

// The furnace as a user renders it (defaults: 6×16×16 bins, tessellated, bounces until converged):
// the mean radiance within 0.5 % of the exact 1/(1−ρ) at ρ = 0.5 and within 2 % at ρ = 0.9, and no
// pixel above it (a receiver's form factors never sum above one).
TEST(IvFurnace, AtDefaultsWithinHalfAPerCentAtHalfAlbedoAndTwoAtNineTenths) {
  auto dir = test::scratchDir("furnace-defaults");
  for (auto [rho, tolerance] : {std::pair{0.5f, 0.005}, std::pair{0.9f, 0.02}}) {
    std::string file = (dir / ("furnace_" + std::to_string(rho) + ".gltf")).string();
    scenes::writeModel(scenes::furnace({.cells = 12, .albedo = rho, .emission = 1.0f}), file);
    Stats st = radianceStats(test::renderExr("furnace-defaults-" + std::to_string(rho), {file, "--size", "64x48"}));
    const double exact = 1.0 / (1.0 - rho);
    std::printf("[ furnace ] rho %.1f at defaults: mean radiance %.4f, exact %.4f (%+.2f %%)\n", rho, st.mean, exact,
                100.0 * (st.mean / exact - 1.0));
    EXPECT_NEAR(st.mean, exact, tolerance * exact) << "rho " << rho;
    EXPECT_LE(st.max, exact * (1 + 1e-4)) << "rho " << rho;
  }
}

TEST(IvExtremes, SingleTriangleAndNoEmitter) {
  scenes::MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  auto dir = test::scratchDir("tiny");
  {
    scenes::GltfBuilder b;
    b.node("one", b.mesh("one", {{m, b.material("lamp", glm::vec3(0.5f), glm::vec3(2.0f))}}));
    std::string file = (dir / "one.gltf").string();
    scenes::writeModel(b.finish(), file);
    Stats st = radianceStats(test::renderExr("one", {file, "--size", "32x32"}));
    EXPECT_EQ(st.nonFinite, 0u);
    EXPECT_NEAR(st.max, 2.0, 1e-5) << "a lone emitter shows its emission and nothing else";
  }
  {
    scenes::GltfBuilder b;
    b.node("dark", b.mesh("dark", {{m, b.material("grey", glm::vec3(0.5f))}}));
    std::string file = (dir / "dark.gltf").string();
    scenes::writeModel(b.finish(), file);
    Stats st = radianceStats(test::renderExr("dark", {file, "--size", "32x32", "--env", "none"}));
    EXPECT_EQ(st.nonFinite, 0u);
    EXPECT_EQ(st.max, 0.0) << "no emitter, no light, --env none";
  }
}

// A scene with no emitter, no punctual light and no --env is lit by a uniform white sky, and one
// line on stderr says so; a scene with its own light gets no sky and no line.
TEST(IvDefaults, UnlitSceneGetsAWhiteSky) {
  auto path = test::assimpGltfDir() / "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is not installed";
  auto dir = test::scratchDir("sky");
  auto r = test::runIvgi(
      {"render", path.string(), "--size", "48x36", "--frames", "0", "--format", "exr", "--out", (dir / "f").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto lines = r.errLines();
  EXPECT_EQ(std::count_if(lines.begin(), lines.end(), [](const std::string& l) { return l.find("note:") != l.npos; }),
            1)
      << r.err;
  EXPECT_NE(r.err.find("white sky"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--env none"), std::string::npos) << r.err;
  Stats st = radianceStats(dir / "f_0000.exr");
  EXPECT_EQ(st.nonFinite, 0u);
  EXPECT_GT(st.mean, 0.05);
  EXPECT_LE(st.max, 1.0 + 1e-4) << "a white sky of radiance 1 lights nothing brighter than itself";

  r = test::runIvgi({"render", "cornell", "--cells", "2", "--size", "32x24", "--frames", "0", "--format", "exr",
                     "--out", (dir / "c").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("note:"), std::string::npos) << r.err;
}

namespace {

// Renders one frame of `args` into `dir` with a sidecar and returns the frame's solver figures.
nlohmann::json solverFigures(const fs::path& dir, std::vector<std::string> args) {
  args.insert(args.begin(), {"render", "--format", "exr", "--out", (dir / "f").string(), "--json",
                             (dir / "s.json").string(), "--frames", "0"});
  auto r = test::runIvgi(args);
  EXPECT_EQ(r.status, 0) << r.err;
  if (r.status != 0) return {};
  return nlohmann::json::parse(std::ifstream(dir / "s.json"))["frames"][0]["solver"];
}

}  // namespace

// --bounces K runs exactly K bounces; by default bounces run until the light with the tail of the
// bounces not run settles within --bounce-tol, and a tighter tolerance runs more of them.
TEST(IvBounces, ForcedCountOrUntilTheTolerance) {
  const std::vector<std::string> cornell = {"cornell", "--cells", "4", "--size", "48x36"};
  auto forced = cornell;
  forced.insert(forced.end(), {"--bounces", "3"});
  auto f = solverFigures(test::scratchDir("forced"), forced);
  EXPECT_EQ(f["bounces"].get<double>(), 3.0);

  auto loose = solverFigures(test::scratchDir("auto"), cornell);
  EXPECT_GE(loose["bounces"].get<double>(), 2.0);
  EXPECT_LE(loose["bounceRemaining"].get<double>(), 1e-3);
  auto tight = cornell;
  tight.insert(tight.end(), {"--bounce-tol", "1e-5"});
  auto t = solverFigures(test::scratchDir("tight"), tight);
  EXPECT_GT(t["bounces"].get<double>(), loose["bounces"].get<double>());
  EXPECT_LE(t["bounceRemaining"].get<double>(), 1e-5);
}

// By default the bounces stop once the light, with the geometric tail of the bounces not run,
// settles; the tail is added at every surfel. So the automatic count's image is far nearer the
// converged one than the same count forced (no tail); a count forced past the first submission's
// bounces runs exactly, through more submissions.
TEST(IvBounces, TheTailBringsTheAutomaticCountNearConvergence) {
  const std::vector<std::string> cornell = {"cornell", "--cells", "4", "--size", "48x36", "--receiver-tol", "0"};
  const auto autoDir = test::scratchDir("tail-auto"), forcedDir = test::scratchDir("tail-forced"),
             convergedDir = test::scratchDir("tail-converged");
  auto a = solverFigures(autoDir, cornell);
  const double bounces = a["bounces"].get<double>();
  EXPECT_GE(bounces, 3.0);
  auto forced = cornell;
  forced.insert(forced.end(), {"--bounces", std::to_string(int(bounces))});
  EXPECT_EQ(solverFigures(forcedDir, forced)["bounces"].get<double>(), bounces);
  auto converged = cornell;
  converged.insert(converged.end(), {"--bounces", "60"});
  EXPECT_EQ(solverFigures(convergedDir, converged)["bounces"].get<double>(), 60.0);

  const auto c = image::readLinearRgb((convergedDir / "f_0000.exr").string());
  const double withTail = image::measureError(image::readLinearRgb((autoDir / "f_0000.exr").string()), c).relMse;
  const double without = image::measureError(image::readLinearRgb((forcedDir / "f_0000.exr").string()), c).relMse;
  std::printf("[ tail ] %g bounces: relMSE against 60 bounces %g with the tail, %g without\n", bounces, withTail,
              without);
  EXPECT_GT(without, 0.0);
  EXPECT_LT(withTail, 0.1 * without);
}

namespace {

// bounce_check.comp fed one gather's area-weighted light and change at a time, as the
// interpolation leaves them: the state after each, until it is done (or after all of them).
std::vector<gpu::BounceState> checkBounces(const std::vector<gpu::BounceSum>& gathers, float tolerance) {
  vk::Context& ctx = test::gpu();
  const vk::Program check = gi::shaderProgram(ctx, "bounce_check");
  vk::Buffer sums(ctx, sizeof(gpu::BounceSum), vk::Memory::Host),
      state(ctx, sizeof(gpu::BounceState), vk::Memory::Host);
  const std::vector<glm::uvec4> full(3, glm::uvec4(1u));
  const vk::Buffer fullArgs = vk::makeBuffer(ctx, full), args(ctx, 4 * sizeof(glm::uvec4), vk::Memory::Device);
  state.upload(std::vector<gpu::BounceState>(1, gpu::BounceState{}));
  std::vector<gpu::BounceState> states;
  for (const gpu::BounceSum& gather : gathers) {
    sums.upload(std::vector<gpu::BounceSum>{gather});
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
      check.dispatch(cmd, {},
                     {{"bounceSums", sums}, {"bounceStates", state}, {"fullArgs", fullArgs}, {"bounceArgs", args}},
                     gpu::BounceCheckPush{.groups = 1u, .dispatches = 3u, .maxGathers = 1000u, .tolerance = tolerance});
    });
    states.push_back(state.read<gpu::BounceState>(1)[0]);
    if (states.back().done) break;
  }
  return states;
}

}  // namespace

// The bounces' changes shrink in a convergent transport (from the first bounce on), so a change
// past kDivergingGrowth times the least before it stops the bounces as diverging. A slow decay
// with the float sums' jitter, a first bounce that adds more than the direct light, and changes at
// the sums' noise (a count forced far past convergence, where the changes may double) do not.
TEST(IvBounces, GrowingChangesStopAsDiverging) {
  std::vector<gpu::BounceSum> growing, slow, early, noise;
  float total = 10.0f;
  for (int k = 0; k < 40; ++k) {
    const float grows = 0.5f * std::pow(1.3f, float(k)), jitter = 1.0f + 0.03f * float(k % 3 == 0 ? 1 : -1);
    growing.push_back({total += grows, grows});
    slow.push_back(
        {10.0f + 500.0f * (1.0f - std::pow(0.999f, float(k + 1))), 0.5f * std::pow(0.999f, float(k)) * jitter});
    early.push_back({10.0f + float(k), k == 0 ? 0.5f : 0.9f * std::pow(0.7f, float(k - 1))});
    noise.push_back({100.0f, k < 3 ? 1.0f / float(k + 1) : (k % 2 ? 3e-6f : 1e-6f)});
  }
  // Where the growing series must stop: the first gather past twice the least change since the second.
  uint32_t expected = 0;
  for (size_t k = 2, least = 1; k < growing.size() && !expected; ++k) {
    if (growing[k].change > gpu::kDivergingGrowth * growing[least].change) expected = uint32_t(k + 1);
    if (growing[k].change < growing[least].change) least = k;
  }
  // Counted bounces (no tolerance): only the divergence stops them early.
  const auto g = checkBounces(growing, -1.0f);
  ASSERT_FALSE(g.empty());
  EXPECT_EQ(g.back().done, 1u);
  EXPECT_EQ(g.back().diverged, 1u);
  EXPECT_EQ(g.back().gathers, expected);
  for (const auto& series : {slow, early, noise}) {
    const auto states = checkBounces(series, -1.0f);
    EXPECT_EQ(states.size(), series.size());
    for (const gpu::BounceState& state : states) EXPECT_EQ(state.diverged, 0u) << "gather " << state.gathers;
  }
  // No scene here diverges (the host's line is not reached); the sidecar's figure is 0 on one that
  // converges.
  auto f = solverFigures(test::scratchDir("converging"), {"cornell", "--cells", "4", "--size", "48x36"});
  EXPECT_EQ(f["diverged"].get<double>(), 0.0);
}

// Links the device's memory (here --max-memory) cannot hold are held in host memory, which the
// device reads across its bus: the frame renders, the same bit for bit, and one line says so.
TEST(IvMemory, LinksPastTheDeviceAreHeldInHostMemory) {
  test::expectTheSameFromHostMemory("links-in-host-memory",
                                    {"cornell", "--cells", "8", "--size", "32x24", "--frames", "0-1"}, "8", {0, 1});
}

// A scene whose buffers other than its links cannot fit the memory it is allowed gets one line
// naming what would need less, and nothing is written.
TEST(IvMemory, RefusalNamesWhatWouldNeedLess) {
  test::expectRefusedNaming("refused",
                            {"cornell", "--cells", "8", "--size", "32x24", "--frames", "0", "--max-memory", "1"},
                            {"--max-memory", "--tessellate"});
}

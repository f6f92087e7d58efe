// ivgi bench --equal-error: how much faster iv (or ar) is than the path tracer at the same error. Its time
// is the mean GPU time of an animated frame (ar's chains: restarts and chained frames in their
// proportion); its error the relMSE and the FLIP of one frame against a converged pt reference;
// pt's time the wall-clock time, on this machine's cores, of the spp that reaches the same relMSE,
// and the same FLIP (doubling spp with an independent seed, interpolated log-log between the two
// spp that bracket it).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "engine/cli/commands.h"
#include "engine/cli/frame_times.h"
#include "engine/cli/json_file.h"
#include "engine/cli/machine.h"
#include "engine/cli/options.h"
#include "engine/cli/report.h"
#include "engine/cli/statistics.h"
#include "engine/image/atomic_file.h"
#include "engine/reference/path_tracer.h"
#include "engine/scene/animation.h"
#include "engine/scene/lights.h"

namespace ivgi::cli {

namespace {

struct PtRender {
  image::RgbImage radiance;
  double ms = 0;
};

// One spp of pt's ladder: its time and errors.
struct Rung {
  uint32_t spp;
  double ms, relMse, flip;
};

// Where pt's ladder reaches `target` of `metric`: its time, log-log interpolated between the two
// rungs that bracket it (`bracketed`), or that of the first rung where it is already below; none
// where no rung reaches it.
struct Crossing {
  double ms;
  bool bracketed;
};
std::optional<Crossing> crossing(const std::vector<Rung>& ladder, double Rung::*metric, double target) {
  for (size_t k = 0; k < ladder.size(); ++k) {
    if (ladder[k].*metric > target) continue;
    if (k == 0) return Crossing{ladder[0].ms, false};
    const Rung &a = ladder[k - 1], &b = ladder[k];
    const double f = (std::log(target) - std::log(a.*metric)) / (std::log(b.*metric) - std::log(a.*metric));
    return Crossing{std::exp(std::log(a.ms) + f * (std::log(b.ms) - std::log(a.ms))), true};
  }
  return std::nullopt;
}

PtRender pathTrace(const scene::Scene& s, const scene::Geometry& g, const scene::Pose& pose,
                   const std::optional<scene::Environment>& environment, const scene::CameraView& view, uint32_t width,
                   uint32_t height, uint32_t frame, const reference::PathSettings& settings) {
  auto start = std::chrono::steady_clock::now();
  reference::PathTracer tracer(reference::PathScene::at(s, g, pose, environment));
  auto channels = tracer.render(view, width, height, frame, settings);
  image::sanitize(channels);
  return {image::radianceOf(channels),
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()};
}

}  // namespace

int runEqualError(const BenchOptions& o) {
  checkFrameCounts(o);
  if (o.referenceSpp < 1 || o.referenceSpp > 1u << 20) throw SettingsError("--reference-spp must be 1 to 1048576");
  if (o.maxSpp < 1 || o.maxSpp > 1u << 20) throw SettingsError("--max-spp must be 1 to 1048576");
  if (!o.solver.environment.empty())
    throw SettingsError("--equal-error compares the scene's own lights; leave out --env");
  gi::ImageSettings image{.samples = o.supersample};
  parseSize(o.size, image.width, image.height);
  scene::Scene s = loadScene(o.source);
  scene::Geometry g = renderableGeometry(s, o.solver, o.source.limits);
  const scene::Geometry modelled =
      renderableGeometry(s, {.method = "pt"}, o.source.limits);  // pt traces the mesh as modelled
  sayWarnings(s);
  if (!o.json.empty()) image::prepareToWrite(o.json);  // written at the end
  // The scene's own lights, or for a scene without any the default sky, for both methods.
  const SolverOptions solver = withSceneLight(o.solver, s, g);
  std::optional<scene::Environment> environment;
  if (!solver.environment.empty()) environment = scene::Environment::parse(solver.environment);
  const Timeline tl = timeline(s, "", o.fps);
  if (o.frame < 0 || o.frame > tl.lastFrame)
    throw SettingsError("--frame must be 0 to " + std::to_string(tl.lastFrame));
  const FrameCamera camera(s, g, tl, o.fps, "", {0}, float(image.width) / float(image.height));
  const auto pose = scene::evaluatePose(s, tl.animation, float(tl.time(o.frame, o.fps)));
  const auto view = camera.at(pose);
  // The renderer first: its settings are checked before the reference takes its time.
  const std::shared_ptr<vk::Context> device = openDevice(o.device);
  vk::Context& ctx = *device;
  gi::FrameRenderer renderer(ctx, g, image, makeSolver(solver, ctx, s, g, tl.animation),
                             directLightSettings(solver, s, g), scene::movingInstances(s, g, tl.animation));

  // The reference: given, or rendered now with seed 0 (the measured pt runs use seed 1).
  image::RgbImage ref;
  double referenceMs = 0;
  if (!o.reference.empty()) {
    ref = image::readLinearRgb(o.reference);
    if (ref.width != image.width || ref.height != image.height)
      throw SettingsError(o.reference + ": the reference is not " + o.size);
  } else {
    std::fprintf(stderr, "equal-error: rendering the reference, pt at %u spp...\n", o.referenceSpp);
    auto r = pathTrace(s, modelled, pose, environment, view, image.width, image.height, uint32_t(o.frame),
                       {.spp = o.referenceSpp, .seed = 0, .threads = o.threads});
    ref = std::move(r.radiance);
    referenceMs = r.ms;
  }

  // The solver (iv or ar): the mean GPU time over animated frames, and the error of the compared frame
  // (solved from the emission, as a restart of ar's chains is). A scene that does not move keeps the
  // solution its timed frames solved, from the emission: solving it again would give it bit for bit.
  FrameTimes times = timeFrames(renderer, s, g, tl, camera, o.fps, o.warmup, o.frames);
  const std::vector<double>& totals = times.perPass["total"];
  const double ivMs = mean(totals);
  const char* method = solver.method.c_str();
  const bool moving = scene::animationMovesGeometry(s, tl.animation);
  auto ivFrame = renderer.render(g.frameInputs(s, pose), view, scene::worldLights(s, pose), moving);
  image::sanitize(ivFrame.channels);
  const image::ErrorMetrics ivError = image::measureError(image::radianceOf(ivFrame.channels), ref);

  std::printf("ivgi bench --equal-error: %s, frame %d, %ux%u\n", s.source.c_str(), o.frame, image.width, image.height);
  const nlohmann::json settings = settingsJson(solver.method, solver.iv, sampledTessellation(solver),
                                               arSettings(solver), directLightSettings(solver, s, g));
  std::printf("%s:  %s; %s\n", method, deviceLine(ctx).c_str(), settings.dump().c_str());
  std::printf("pt:  %s, unlimited bounces (roulette)\n", cpuLine(o.threads).c_str());
  std::printf("reference: %s\n\n", o.reference.empty() ? ("pt " + std::to_string(o.referenceSpp) + " spp, seed 0, " +
                                                          std::to_string(int(std::lround(referenceMs / 1000))) + " s")
                                                             .c_str()
                                                       : o.reference.c_str());
  std::printf("%s   %8.2f ms per frame (mean GPU over %d frames)   relMSE %.5g   FLIP %.4f\n\n", method, ivMs, o.frames,
              ivError.relMse, ivError.flip);
  std::printf("%8s %12s %12s %10s\n", "pt spp", "ms", "relMSE", "FLIP");

  std::vector<Rung> ladder;
  nlohmann::json ladderJson = nlohmann::json::array();
  for (uint32_t spp = 1; spp <= o.maxSpp; spp *= 2) {
    auto r = pathTrace(s, modelled, pose, environment, view, image.width, image.height, uint32_t(o.frame),
                       {.spp = spp, .seed = 1, .threads = o.threads});
    auto e = image::measureError(r.radiance, ref);
    std::printf("%8u %12.1f %12.5g %10.4f\n", spp, r.ms, e.relMse, e.flip);
    ladder.push_back({spp, r.ms, e.relMse, e.flip});
    ladderJson.push_back({{"spp", spp}, {"ms", r.ms}, {"relMSE", e.relMse}, {"FLIP", e.flip}});
    if (e.relMse <= ivError.relMse && e.flip <= ivError.flip) break;  // both reached
  }
  nlohmann::json result = {
      {"scene", s.source},
      {"surfels", g.surfels.size()},
      {"frame", o.frame},
      {"width", image.width},
      {"height", image.height},
      {"supersample", image.samples},
      {"solver",
       {{"meanGpuMs", ivMs},
        {"medianGpuMs", percentile(totals, 0.5)},
        {"relMSE", ivError.relMse},
        {"FLIP", ivError.flip},
        {"settings", settings},
        {"device", deviceJson(ctx)}}},
      {"pt", {{"ladder", ladderJson}, {"device", cpuJson(o.threads)}}},
      {"reference", o.reference.empty() ? nlohmann::json({{"spp", o.referenceSpp}, {"ms", referenceMs}})
                                        : nlohmann::json(o.reference)}};
  std::printf("\n");
  // At equal relMSE (the keys "ratio", "ptMsAtEqualError", "ratioLowerBound"), then at equal FLIP.
  const struct {
    const char* name;
    double Rung::*metric;
    double target;
    std::string suffix;
  } measures[] = {{"relMSE", &Rung::relMse, ivError.relMse, ""}, {"FLIP", &Rung::flip, ivError.flip, "Flip"}};
  for (const auto& m : measures) {
    const std::string msKey = m.suffix.empty() ? "ptMsAtEqualError" : "ptMsAtEqualFlip";
    if (const auto c = crossing(ladder, m.metric, m.target)) {
      std::printf("pt reaches %s's %s in %.1f ms%s: %s is %.2fx %s at equal %s\n", method, m.name, c->ms,
                  c->bracketed ? " (interpolated)" : " (at 1 spp)", method, c->ms / ivMs,
                  c->ms >= ivMs ? "faster" : "slower (ratio < 1)", m.suffix.empty() ? "error" : "FLIP");
      result[msKey] = c->ms;
      result["ratio" + m.suffix] = c->ms / ivMs;
    } else {
      std::printf("pt did not reach %s's %s within %u spp: %s is more than %.0fx faster at equal %s\n", method, m.name,
                  o.maxSpp, method, ladder.back().ms / ivMs, m.suffix.empty() ? "error" : "FLIP");
      result["ratio" + m.suffix] = nullptr;
      result["ratio" + m.suffix + "LowerBound"] = ladder.back().ms / ivMs;
    }
  }
  if (!o.json.empty()) writeJson(o.json, result);
  return ctx.validationErrors() ? 3 : 0;
}

}  // namespace ivgi::cli

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "engine/cli/commands.h"
#include "engine/cli/frame_writer.h"
#include "engine/cli/json_file.h"
#include "engine/cli/machine.h"
#include "engine/cli/options.h"
#include "engine/cli/progress.h"
#include "engine/cli/report.h"
#include "engine/cli/sidecar.h"
#include "engine/cli/statistics.h"
#include "engine/cli/timeline.h"
#include "engine/gi/frame_renderer.h"
#include "engine/image/atomic_file.h"
#include "engine/image/frame_image.h"
#include "engine/reference/path_tracer.h"
#include "engine/scene/camera.h"
#include "engine/scene/environment.h"
#include "engine/scene/geometry.h"
#include "engine/scene/lights.h"
#include "engine/vk/context.h"

namespace ivgi::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// One path-traced frame: the host poses the geometry, Embree traces it; the progress line advances
// by rows while the threads work.
gi::FrameResult pathTraceFrame(const scene::Geometry& g, const scene::Scene& s, const scene::Pose& pose,
                               const std::optional<scene::Environment>& env, const scene::CameraView& view,
                               const gi::ImageSettings& image, uint32_t frame, const reference::PathSettings& settings,
                               Progress& progress) {
  auto start = std::chrono::steady_clock::now();
  reference::PathTracer tracer(reference::PathScene::at(s, g, pose, env));
  std::atomic<uint32_t> rows{0};
  auto job = std::async(std::launch::async,
                        [&] { return tracer.render(view, image.width, image.height, frame, settings, &rows); });
  uint32_t shown = 0;
  while (job.wait_for(std::chrono::milliseconds(200)) != std::future_status::ready) {
    uint32_t now = rows.load();
    for (; shown < now; ++shown) progress.advance();
  }
  gi::FrameResult result{job.get(), {}};
  for (; shown < image.height; ++shown) progress.advance();
  result.passTimes.push_back(
      {"pt", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
  return result;
}

}  // namespace

int runRender(const RenderOptions& o) {
  if (o.tonemap != "aces" && o.tonemap != "clamp") throw SettingsError("--tonemap must be aces or clamp");
  const bool pt = o.solver.method == "pt";
  if (!pt && o.pt.given) throw SettingsError("--spp, --seed and --threads apply to --method pt only");
  gi::ImageSettings image;
  parseSize(o.size, image.width, image.height);
  image.samples = o.supersample;
  auto formats = parseFormats(o.formats);
  OutputPattern pattern(o.out);
  const image::DisplaySettings display{o.tonemap == "aces" ? image::ToneMap::Aces : image::ToneMap::Clamp, o.exposure};
  image::validate(display);

  scene::Scene s = loadScene(o.source);
  Timeline tl = timeline(s, o.animation, o.fps);
  FrameRange range{0, tl.lastFrame, 1};
  if (!o.frames.empty()) range = parseFrameRange(o.frames);
  if (range.last > tl.lastFrame) {
    std::string what = tl.animation >= 0 ? "the animation '" + s.animations[tl.animation].name + "' (frames 0-" +
                                               std::to_string(tl.lastFrame) + " at " + json(o.fps).dump() + " fps)"
                                         : "a scene without animation (frame 0 only)";
    throw scene::LoadError(s.source + ": frames " + std::to_string(range.first) + "-" + std::to_string(range.last) +
                           " lie outside " + what);
  }
  scene::Geometry g = renderableGeometry(s, o.solver, o.source.limits);
  const SolverOptions solver = withSceneLight(o.solver, s, g);
  sayWarnings(s);

  // The frame source: the GPU pipeline (iv, none) or the Embree path tracer (pt, no Vulkan).
  std::shared_ptr<vk::Context> ctx;
  std::unique_ptr<gi::FrameRenderer> renderer;
  std::optional<scene::Environment> environment;
  const reference::PathSettings ptSettings = pathSettings(o.pt, solver);
  if (pt) {
    if (image.samples != 1)
      throw SettingsError("--supersample: pt spreads its --spp samples over each pixel; leave --supersample at 1");
    if (!solver.environment.empty()) environment = scene::Environment::parse(solver.environment);
  } else {
    ctx = openDevice(o.device);
    renderer = std::make_unique<gi::FrameRenderer>(*ctx, g, image, makeSolver(solver, *ctx, s, g, tl.animation),
                                                   directLightSettings(solver, s, g),
                                                   scene::movingInstances(s, g, tl.animation));
  }
  const bool geometryAnimated = scene::animationMovesGeometry(s, tl.animation);

  const Shard shard = o.shard.empty() ? Shard{} : parseShard(o.shard);
  const auto chainStart = [&](int frame) {
    return renderer && renderer->solver() ? renderer->solver()->chainStart(frame) : frame;
  };
  const auto frames = shardFrames(range.frames(), shard, chainStart);
  const FrameCamera camera(s, g, tl, o.fps, o.camera, range.frames(), float(image.width) / float(image.height));

  // The frames' folder, and the sidecar written at the end, checked before the first frame renders.
  const std::string sidecarPath = Sidecar::forShard(o.json.empty() ? pattern.sidecar() : o.json, shard);
  image::prepareToWrite(sidecarPath);
  image::prepareToWrite(pattern.path(frames.empty() ? range.first : frames.front(), formats.front()));
  image::installInterruptCleanup();
  // While this run lives, its temporaries are its own; with --resume, those of runs that ended are removed.
  const image::RunLock lock(pattern.directory());
  if (o.resume)
    if (size_t removed = image::removeDeadTemporaries(pattern.directory()))
      std::fprintf(stderr, "ivgi: removed %zu temporary files left by runs that ended\n", removed);
  json settings = settingsJson(solver.method, solver.iv, sampledTessellation(solver), arSettings(solver),
                               directLightSettings(solver, s, g));
  settings.update({{"frames", {range.first, range.last, range.step}},
                   {"shard", {shard.index, shard.count}},
                   {"fps", o.fps},
                   {"width", image.width},
                   {"height", image.height},
                   {"supersample", image.samples},
                   {"formats", formats},
                   {"tonemap", o.tonemap},
                   {"exposure", o.exposure},
                   {"animation", tl.animation >= 0 ? json(s.animations[tl.animation].name) : json(nullptr)},
                   {"environment", solver.environment},
                   {"spp", o.pt.spp},
                   {"seed", o.pt.seed},
                   {"unbounded", pt && !solver.iv.bounces},
                   {"camera", camera.name()}});
  Sidecar sidecar(
      sidecarPath,
      {{"ivgi", IVGI_VERSION},
       {"scene", s.source},
       {"settings", settings},
       {"device", ctx ? deviceJson(*ctx) : cpuJson(ptSettings.threads)},
       {"counts", {{"triangles", g.triangles.size()}, {"vertices", g.vertices.size()}, {"surfels", g.surfels.size()}}},
       {"bytesAllocated", renderer ? renderer->bytesAllocated() : 0}},
      pt);
  auto pathsOf = [&](int frame) {
    std::vector<std::string> paths;
    for (const auto& f : formats) paths.push_back(pattern.path(frame, f));
    return paths;
  };
  auto done = [&](int frame) {
    const auto paths = pathsOf(frame);
    return std::all_of(paths.begin(), paths.end(), [](auto& p) { return fs::exists(p); });
  };
  if (o.resume) {
    std::vector<int> skipped;
    std::copy_if(frames.begin(), frames.end(), std::back_inserter(skipped), done);
    sidecar.keepEarlierRecords(skipped);
  }

  const image::Provenance provenance{solver.method, pt ? o.pt.spp : image.samples * image.samples};
  // pt frames take long: its progress counts rows.
  Progress progress("render", pt ? frames.size() * image.height : frames.size(), pt ? "row" : "frame");
  int lastSolved = -1;  // by the renderer
  // Solved on the GPU; relinked in the first frame this run solves, whatever frame that is: an image
  // never depends on the frames solved before it (but those of its chain, the same in every run).
  auto solve = [&](int frame, const scene::Pose& pose, const scene::CameraView& view) {
    gi::FrameResult result = renderer->render(g.frameInputs(s, pose), view, scene::worldLights(s, pose),
                                              lastSolved < 0 || geometryAnimated, frame);
    lastSolved = frame;
    return result;
  };
  // By default a frame's images are written while the next frames render on a GPU only: where the
  // frames come from the CPU (lavapipe, pt) writing alongside would take its cores.
  FrameWriter writer(
      sidecar, o.writeAhead.value_or(ctx && ctx->info().type != "cpu" ? 3 : 0),
      [&](const std::vector<std::string>& paths, const image::FrameChannels& channels) {
        for (size_t i = 0; i < formats.size(); ++i) {
          if (formats[i] == "exr")
            image::writeExr(paths[i], channels, provenance);
          else
            image::writePng(paths[i], channels, display);
        }
      },
      [&] {
        if (!renderer) return;
        sidecar.set("solver", solverJson(renderer->solver()));
        sidecar.set("bytesAllocated", renderer->bytesAllocated());
      });
  for (int frame : frames) {
    if (o.resume && done(frame)) {
      progress.advance(pt ? image.height : 1, true);
      continue;
    }
    const auto started = std::chrono::steady_clock::now();
    const double t = tl.time(frame, o.fps);
    const auto pose = scene::evaluatePose(s, tl.animation, float(t));
    const auto view = camera.at(pose);
    gi::FrameResult result;
    if (pt) {
      result = pathTraceFrame(g, s, pose, environment, view, image, uint32_t(frame), ptSettings, progress);
    } else {
      // A frame that starts from the solution of the frame before: the frames of its chain before it
      // that this run has not just solved are solved first, and not written.
      const int start = chainStart(frame);
      for (int before = lastSolved >= start && lastSolved < frame ? lastSolved + 1 : start; before < frame; ++before) {
        const auto posed = scene::evaluatePose(s, tl.animation, float(tl.time(before, o.fps)));
        solve(before, posed, camera.at(posed));
      }
      result = solve(frame, pose, view);
      progress.advance();
    }
    if (size_t bad = image::sanitize(result.channels))
      std::fprintf(stderr, "ivgi: warning: frame %d: %zu non-finite values replaced by 0 (a bug: please report it)\n",
                   frame, bad);
    writer.add(frame, t, pathsOf(frame), std::move(result), started);
  }
  writer.finish();
  progress.finish();
  sidecar.write();
  std::fprintf(stderr, "ivgi: %zu frames to %s, timings in %s (median %s %.2f ms per frame)\n", frames.size(),
               pattern.directory().c_str(), sidecar.path().c_str(), pt ? "CPU" : "GPU", sidecar.medianTotalMs());
  if (ctx && ctx->validationErrors()) {
    std::fprintf(stderr, "ivgi: %u Vulkan validation errors\n", ctx->validationErrors());
    return 3;
  }
  return 0;
}

}  // namespace ivgi::cli

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>

#include "engine/cli/commands.h"
#include "engine/cli/frame_times.h"
#include "engine/cli/json_file.h"
#include "engine/cli/machine.h"
#include "engine/cli/options.h"
#include "engine/cli/report.h"
#include "engine/cli/statistics.h"
#include "engine/cli/timeline.h"
#include "engine/gi/frame_renderer.h"
#include "engine/image/atomic_file.h"
#include "engine/scene/camera.h"
#include "engine/scene/lights.h"
#include "engine/vk/context.h"

namespace ivgi::cli {

FrameTimes timeFrames(gi::FrameRenderer& renderer, const scene::Scene& s, const scene::Geometry& g, const Timeline& tl,
                      const FrameCamera& camera, double fps, int warmup, int count) {
  const bool moving = scene::animationMovesGeometry(s, tl.animation);
  FrameTimes out;
  std::vector<std::vector<vk::PassTime>> programs;  // per measured frame
  for (int i = 0; i < warmup + count; ++i) {
    int frame = i % (tl.lastFrame + 1);
    auto pose = scene::evaluatePose(s, tl.animation, float(tl.time(frame, fps)));
    auto result =
        renderer.render(g.frameInputs(s, pose), camera.at(pose), scene::worldLights(s, pose), i == 0 || moving, frame);
    if (i < warmup) continue;
    programs.push_back(result.programTimes);
    double total = 0;
    nlohmann::json passes = nlohmann::json::object();
    for (const auto& p : result.passTimes) {
      if (!out.perPass.count(p.pass)) out.order.push_back(p.pass);
      out.perPass[p.pass].push_back(p.ms);
      passes[p.pass] = p.ms;
      total += p.ms;
    }
    out.perPass["total"].push_back(total);
    nlohmann::json figures = nlohmann::json::object();
    for (const auto& [figure, value] : result.solverFigures)
      out.solverFigures[figure].push_back(value), figures[figure] = value;
    out.frames.push_back({{"frame", frame}, {"gpuMs", passes}, {"totalGpuMs", total}, {"solver", figures}});
    if (!result.programTimes.empty()) {
      nlohmann::json perProgram = nlohmann::json::object();
      for (const vk::PassTime& p : result.programTimes) perProgram[p.pass] = {{"ms", p.ms}, {"dispatches", p.count}};
      out.frames.back()["programs"] = perProgram;
    }
  }
  // Every program any measured frame ran, with a value for each frame (0 where it did not run).
  for (const auto& frame : programs)
    for (const vk::PassTime& p : frame) out.perProgram.try_emplace(p.pass), out.programDispatches.try_emplace(p.pass);
  for (const auto& frame : programs)
    for (auto& [program, times] : out.perProgram) {
      const std::string& name = program;  // a lambda captures no structured binding before clang 16
      auto it = std::find_if(frame.begin(), frame.end(), [&](const vk::PassTime& p) { return p.pass == name; });
      times.push_back(it == frame.end() ? 0.0 : it->ms);
      out.programDispatches[name].push_back(it == frame.end() ? 0.0 : double(it->count));
    }
  return out;
}

namespace {

// With --per-program: each program's median time a frame, its p90 and its dispatches a frame, the
// slowest first (printed and as JSON; empty without it).
nlohmann::json printPrograms(const FrameTimes& times) {
  nlohmann::json out = nlohmann::json::object();
  if (times.perProgram.empty()) return out;
  std::vector<std::pair<double, std::string>> byTime;
  for (const auto& [name, ms] : times.perProgram) byTime.emplace_back(percentile(ms, 0.5), name);
  std::sort(byTime.begin(), byTime.end(), std::greater<>());
  std::printf("\n%-24s %10s %10s %10s\n", "program", "median ms", "p90 ms", "dispatches");
  double sum = 0;
  for (const auto& [median, name] : byTime) {
    const double p90 = percentile(times.perProgram.at(name), 0.9),
                 dispatches = percentile(times.programDispatches.at(name), 0.5);
    std::printf("%-24s %10.3f %10.3f %10.0f\n", name.c_str(), median, p90, dispatches);
    out[name] = {{"medianMs", median}, {"p90Ms", p90}, {"dispatches", dispatches}};
    sum += median;
  }
  std::printf("%-24s %10.3f  (the dispatches' own times: the barriers, fills and copies between them are not in it)\n",
              "sum of medians", sum);
  return out;
}

}  // namespace

void checkFrameCounts(const BenchOptions& o) {
  if (o.frames < 1 || o.frames > 100000) throw SettingsError("--frames must be 1 to 100000");
  if (o.warmup < 0 || o.warmup > 1000) throw SettingsError("--warmup must be 0 to 1000");
}

int runBench(const BenchOptions& o) {
  if (o.equalError && o.perProgram)
    throw SettingsError("--per-program times bench's own frames; --equal-error does not take it");
  if (o.equalError) return runEqualError(o);
  checkFrameCounts(o);
  gi::ImageSettings image{.samples = o.supersample};
  parseSize(o.size, image.width, image.height);
  scene::Scene s = loadScene(o.source);
  scene::Geometry g = renderableGeometry(s, o.solver, o.source.limits);
  sayWarnings(s);
  if (!o.json.empty()) image::prepareToWrite(o.json);  // written at the end
  const SolverOptions solver = withSceneLight(o.solver, s, g);
  const Timeline tl = timeline(s, "", o.fps);
  const int animation = tl.animation;

  const std::shared_ptr<vk::Context> device = openDevice(o.device);
  vk::Context& ctx = *device;
  gi::FrameRenderer renderer(ctx, g, image, makeSolver(solver, ctx, s, g, animation), directLightSettings(solver, s, g),
                             scene::movingInstances(s, g, animation));
  if (o.perProgram) renderer.timePrograms();
  const FrameCamera camera(s, g, tl, o.fps, "", {0}, float(image.width) / float(image.height));

  const bool moving = scene::animationMovesGeometry(s, animation);
  FrameTimes times = timeFrames(renderer, s, g, tl, camera, o.fps, o.warmup, o.frames);
  auto& perPass = times.perPass;
  auto& order = times.order;
  auto& frames = times.frames;

  std::printf("ivgi bench: %s, %ux%u", s.source.c_str(), image.width, image.height);
  if (image.samples > 1) std::printf(" (%ux%u samples a pixel)", image.samples, image.samples);
  std::printf(", method %s", solver.method.c_str());
  const gi::IvSettings& iv = solver.iv;
  if (const auto* ivSolver = dynamic_cast<const gi::IvSolver*>(renderer.solver())) {
    std::printf(", bins 6x%ux%u, eps %g, bounces %s, receiver-tol %g%s", iv.bins, iv.bins, iv.epsilon,
                bouncesText(iv).c_str(), *ivSolver->settings().receiverTolerance,
                iv.receiverTolerance ? "" : " (the device's default)");
    if (ivSolver->guidedByView()) std::printf(", unseen-tol %g", iv.unseenTolerance);
  }
  if (solver.method == "ar")
    std::printf(", dirs 6x%ux%u, eps %g, iterations %s, %s, restart every %u", solver.ar.dirs, solver.ar.dirs,
                iv.epsilon, solver.ar.iterations ? std::to_string(*solver.ar.iterations).c_str() : "auto",
                solver.arScheme.c_str(), solver.ar.restartEvery);
  std::printf("\ndevice: %s\n", deviceLine(ctx).c_str());
  std::printf(
      "frames: %d measured after %d warm-up%s\n\n", o.frames, o.warmup,
      moving ? ""
             : " (nothing moves: the scene was posed and solved once, in the first warm-up frame or the first frame; "
               "the frames after it redo what depends on the view)");
  std::printf("%-10s %10s %10s\n", "pass", "median ms", "p90 ms");
  nlohmann::json summary = nlohmann::json::object();
  order.push_back("total");
  for (const auto& p : order) {
    // Passes that did not run every frame (static geometry) are reported over the frames they ran.
    double med = percentile(perPass[p], 0.5), p90 = percentile(perPass[p], 0.9);
    std::printf(
        "%-10s %10.3f %10.3f%s\n", p.c_str(), med, p90,
        perPass[p].size() < size_t(o.frames) ? ("  (" + std::to_string(perPass[p].size()) + " frames)").c_str() : "");
    summary[p] = {{"medianMs", med}, {"p90Ms", p90}, {"frames", perPass[p].size()}};
  }
  double totalMs = percentile(perPass["total"], 0.5);
  const double meanMs = mean(perPass["total"]);
  summary["total"]["meanMs"] = meanMs;
  std::printf("\nframe: %.3f ms median GPU, %.2f fps; mean %.3f ms, %.2f fps over the measured frames\n", totalMs,
              totalMs > 0 ? 1000.0 / totalMs : 0.0, meanMs, meanMs > 0 ? 1000.0 / meanMs : 0.0);
  const nlohmann::json programs = printPrograms(times);
  std::printf("surfels %zu, triangles %zu", g.surfels.size(), g.triangles.size());
  nlohmann::json counts = {
      {"surfels", g.surfels.size()}, {"triangles", g.triangles.size()}, {"vertices", g.vertices.size()}};
  const uint64_t bytes = renderer.bytesAllocated();
  uint64_t linksInHostMemory = 0;
  if (const auto* solver = dynamic_cast<const gi::IvSolver*>(renderer.solver())) {
    const gi::IvStats st = solver->stats();
    std::printf(", nodes %u, links %u created, %u leaf links after push-down and pruning", st.nodes, st.links,
                st.leafLinks);
    if (st.staticLinks)
      std::printf(" (of which %u and %u between static objects or within a rigid one, made once)", st.staticLinks,
                  st.staticLeafLinks);
    // A redone frame's timings are the sum of its runs: say so where it happened.
    if (st.framesRedone) std::printf("; %u frame(s) redone with more room for links or loop rounds", st.framesRedone);
    std::printf("; prune workgroups of %u invocations", st.pruneGroupSize);
    linksInHostMemory = st.hostBytes;
    // The prune's work, and its rate where it ran in the measured frames.
    // A still scene's measured frames keep the first frame's solution: its counts are that frame's.
    std::printf(
        "\nprune work: %llu root-path senders walked in the last frame%s", (unsigned long long)st.sendersWalked,
        perPass["prune"].empty() ? " that pruned (a warm-up frame: the measured frames kept its solution)" : "");
    if (st.receivers > 0)  // against the bins a receiver resolves them into (docs/notes/prune-bound.md)
      std::printf(" (%.0f a receiver, against %u bins)", double(st.sendersWalked) / st.receivers,
                  6 * o.solver.iv.bins * o.solver.iv.bins);
    if (!perPass["prune"].empty() && percentile(perPass["prune"], 0.5) > 0)
      std::printf(" (%.1f M/s at the median prune time)",
                  double(st.sendersWalked) / percentile(perPass["prune"], 0.5) / 1e3);
    if (st.staticSendersWalked) {
      std::printf(
          ", %llu of them by the leaves that merge them with what the static pass kept (static leaves, and "
          "rigid ones), against the senders that move apart from them alone",
          (unsigned long long)st.mergedSendersWalked);
      if (st.rigidLeaves > 0)
        std::printf(" (%llu by %u leaves of rigid objects, %.0f each: their objects' links to the rest)",
                    (unsigned long long)st.rigidSendersWalked, st.rigidLeaves,
                    double(st.rigidSendersWalked) / st.rigidLeaves);
      std::printf("; %llu in the static pass (once a leaf, so far)", (unsigned long long)st.staticSendersWalked);
    }
    if (const auto& b = times.solverFigures["bounces"]; !b.empty())
      std::printf("\nbounces: median %.0f a frame (%.0f to %.0f)%s", percentile(b, 0.5),
                  *std::min_element(b.begin(), b.end()), *std::max_element(b.begin(), b.end()),
                  solver->stats().bounceRemaining > 0
                      ? ", and the tail of those not run, until the light with it settles within --bounce-tol"
                      : "");
    const auto& diverged = times.solverFigures["diverged"];
    if (const auto stopped = std::count(diverged.begin(), diverged.end(), 1.0))
      std::printf("\ndivergence: %td frame(s) stopped with their bounces diverging", stopped);
  }
  if (const auto* ar = dynamic_cast<const gi::ArSolver*>(renderer.solver())) {
    const gi::ArStats st = ar->stats();
    std::printf(", nodes %u, links %u (both sides, unpruned", st.nodes, st.links);
    if (st.staticLinks) std::printf("; %u between static objects or within a rigid one, made once", st.staticLinks);
    std::printf("); directional tables %.1f MiB", double(st.tableBytes) / (1 << 20));
    if (st.framesRedone) std::printf("; %u frame(s) redone (link room, or a diverging iteration)", st.framesRedone);
    if (const auto& it = times.solverFigures["iterations"]; !it.empty())
      std::printf("\niterations: median %.0f a frame (%.0f to %.0f); the last frame's residuals:", percentile(it, 0.5),
                  *std::min_element(it.begin(), it.end()), *std::max_element(it.begin(), it.end()));
    for (float r : st.residuals) std::printf(" %.2g", double(r));
    if (const auto& warm = times.solverFigures["warm"]; !warm.empty())
      std::printf("\nchains: %td of %zu frames started from the frame before's solution",
                  std::count(warm.begin(), warm.end(), 1.0), warm.size());
    const auto& damping = times.solverFigures["damping"];
    const auto& diverged = times.solverFigures["diverged"];
    const auto damped = std::count_if(damping.begin(), damping.end(), [](double w) { return w < 1.0; });
    if (damped)
      std::printf("\ndivergence: %td frame(s) solved damped (down to %.3g of a step), %td of them stopped diverged",
                  damped, *std::min_element(damping.begin(), damping.end()),
                  std::count(diverged.begin(), diverged.end(), 1.0));
  }
  if (const gi::DirectLight* direct = renderer.directLight()) {
    // Where only moving objects were drawn again, the surfels whose light they can have changed.
    const auto [drawn, views] = direct->movingViewsDrawn();
    std::printf("\ndirect light: the last frame lit %u of %zu surfels", direct->surfelsLit(), g.surfels.size());
    if (drawn > 0) std::printf(" and drew the moving objects into %u of the maps' %u views", drawn, views);
  }
  const double hostPeak = hostPeakMiB();
  std::printf("\nbytes allocated: %llu (%.1f MiB)", (unsigned long long)bytes, double(bytes) / (1 << 20));
  if (linksInHostMemory)  // where the device's memory (or --max-memory) could not hold them
    std::printf(": %.1f MiB on the device, %.1f MiB of links in host memory",
                double(bytes - linksInHostMemory) / (1 << 20), double(linksInHostMemory) / (1 << 20));
  else
    std::printf(" on the device");
  std::printf("; host peak %.1f MiB resident\n", hostPeak);
  if (!o.json.empty()) {
    nlohmann::json settings =
        settingsJson(solver.method, iv, solver.tessellation, arSettings(solver), directLightSettings(solver, s, g));
    settings.update({{"width", image.width},
                     {"height", image.height},
                     {"supersample", image.samples},
                     {"frames", o.frames},
                     {"warmup", o.warmup}});
    nlohmann::json j = {{"scene", s.source},
                        {"settings", settings},
                        {"device", deviceJson(ctx)},
                        {"passes", summary},
                        {"programs", programs},
                        {"fps", totalMs > 0 ? 1000.0 / totalMs : 0.0},
                        {"meanFps", meanMs > 0 ? 1000.0 / meanMs : 0.0},
                        {"counts", counts},
                        {"solver", solverJson(renderer.solver())},
                        {"bytesAllocated", bytes},
                        {"hostPeakMiB", hostPeak},
                        {"frames", frames}};
    writeJson(o.json, j);
  }
  return ctx.validationErrors() ? 3 : 0;
}

}  // namespace ivgi::cli

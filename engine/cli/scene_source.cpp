#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "engine/cli/commands.h"
#include "engine/cli/options.h"
#include "engine/cli/progress.h"
#include "engine/scene/animation.h"
#include "engine/scene/gltf.h"
#include "engine/scene/lights.h"
#include "scenes/builtin.h"

namespace ivgi::cli {

std::shared_ptr<vk::Context> openDevice(const DeviceChoice& choice) {
  if (choice.lent && choice.name.empty()) return {std::shared_ptr<vk::Context>{}, choice.lent};  // not owned
  return std::make_shared<vk::Context>(vk::ContextOptions{.device = choice.name});
}

scene::Scene loadScene(const SceneChoice& choice) {
  const std::string& name = choice.scene.empty() ? "cornell" : choice.scene;
  auto builtins = scenes::builtinSceneNames();
  bool builtin = std::find(builtins.begin(), builtins.end(), name) != builtins.end() && !std::filesystem::exists(name);
  if (choice.glossy && (!builtin || name != "cornell"))
    throw SettingsError("--glossy: only the built-in cornell has a glossy variant, not " + name);
  if (!builtin) return scene::loadGltf(name, choice.limits);
  if (name == "cornell")
    return scene::sceneFromModel(scenes::cornellBox({.cells = choice.cells, .glossy = choice.glossy}),
                                 choice.glossy ? "built-in glossy cornell" : "built-in cornell");
  return scene::sceneFromModel(scenes::furnace({.cells = choice.cells}), "built-in furnace");
}

std::optional<gi::DirectLightSettings> directLightSettings(const SolverOptions& o, const scene::Scene& s,
                                                           const scene::Geometry& g) {
  const uint32_t pointLights = scene::punctualLightCount(s);
  if (o.direct.empty()) {  // the default: the pixels' own, where the maps suit the scene's lights
    const bool suits =
        (o.method == "iv" || o.method == "ar") &&
        (pointLights > 0 || gi::emits(g) || (!o.environment.empty() && o.maps.environmentDirections > 0)) &&
        (gi::emissiveAreaShare(g) <= gi::kMapsEmitterShare || gi::emitterPowerShare(s, g) <= gi::kBinsEmitterPower);
    if (!suits) return std::nullopt;
  }
  if (o.direct == "bins") return std::nullopt;
  if (!o.direct.empty() && o.direct != "maps" && o.direct != "pixels")
    throw SettingsError("--direct " + o.direct + ": must be bins, maps or pixels");
  if (o.method != "iv" && o.method != "ar")
    throw SettingsError("--direct " + o.direct + ": only iv and ar take the direct light from depth maps (" + o.method +
                        " computes its own)");
  gi::DirectLightSettings maps = o.maps;
  maps.perPixel = o.direct.empty() || o.direct == "pixels";
  maps.punctualLights = pointLights;
  if (!o.environment.empty() && maps.environmentDirections > 0)
    maps.environment = scene::Environment::parse(o.environment);
  return maps;
}

uint32_t sampledTessellation(const SolverOptions& solver) {
  return solver.method == "iv" || solver.method == "ar" ? solver.tessellation : 0;
}

scene::BuildProgress buildProgress() {
  struct Line {
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    std::optional<Progress> progress;
  };
  auto line = std::make_shared<Line>();
  return [line](size_t built, size_t nodes) {
    if (!line->progress) {
      if (std::chrono::steady_clock::now() - line->start < std::chrono::seconds(2)) return;
      line->progress.emplace("scene", nodes, "node");
      line->progress->advance(built - 1, true);  // before the line: not counted for the rate
    }
    line->progress->advance();
    if (built == nodes) line->progress->finish();
  };
}

scene::OpenSpace openSpaceOf(const SolverOptions& solver, const scene::Scene& s) {
  if (solver.environment == "none") return scene::OpenSpace::Dark;
  if (!solver.environment.empty()) return scene::OpenSpace::Lit;
  bool emits = false, lit = false;
  for (const scene::Node& n : s.nodes) {
    lit = lit || n.light >= 0;
    if (n.mesh < 0) continue;
    for (const scene::Primitive& p : s.meshes[size_t(n.mesh)].primitives)
      if (p.material >= 0) {
        const scene::Material& m = s.materials[size_t(p.material)];
        emits = emits || (m.emissiveStrength > 0.0f && glm::any(glm::greaterThan(m.emissive, glm::vec3(0.0f))));
      }
  }
  return emits || lit ? scene::OpenSpace::Dark : scene::OpenSpace::Lit;
}

scene::Geometry renderableGeometry(const scene::Scene& s, const SolverOptions& solver, const scene::Limits& limits) {
  if (solver.tessellation > 100000) throw SettingsError("--tessellate must be 0 to 100000");
  scene::Geometry g =
      scene::buildGeometry(s, sampledTessellation(solver), buildProgress(), limits, openSpaceOf(solver, s));
  if (g.triangles.empty()) {
    // What the loader skipped is often why (a file of points or lines): said in the one line.
    std::string why;
    if (!s.warnings.empty())
      why = " (" + s.warnings.front() +
            (s.warnings.size() > 1 ? ", and " + std::to_string(s.warnings.size() - 1) + " warnings more" : "") + ")";
    throw scene::LoadError(s.source + ": the scene has no triangles to render" + why);
  }
  return g;
}

void sayWarnings(const scene::Scene& s) {
  for (const auto& w : s.warnings) std::fprintf(stderr, "ivgi: warning: %s: %s\n", s.source.c_str(), w.c_str());
}

SolverOptions withSceneLight(SolverOptions o, const scene::Scene& s, const scene::Geometry& g) {
  if (o.environment == "none") {
    o.environment.clear();
    return o;
  }
  if (!o.environment.empty()) return o;
  const bool emits = std::any_of(g.surfelEmission.begin(), g.surfelEmission.end(),
                                 [](const glm::vec4& e) { return e.r > 0.0f || e.g > 0.0f || e.b > 0.0f; });
  const bool lit = std::any_of(s.nodes.begin(), s.nodes.end(), [](const scene::Node& n) { return n.light >= 0; });
  if (emits || lit) return o;
  o.environment = "1,1,1";
  std::fprintf(stderr,
               "ivgi: note: %s has no light: lit by a uniform white sky (--env 1,1,1); --env none keeps it dark\n",
               s.source.c_str());
  return o;
}

gi::ArSettings arSettings(const SolverOptions& o) {
  gi::ArSettings settings = o.ar;
  settings.epsilon = o.iv.epsilon, settings.kappa = o.iv.kappa;
  settings.scheme = gi::parseScheme(o.arScheme);
  settings.memoryBudget = o.maxMemoryMiB << 20;
  if (!o.environment.empty()) settings.environment = scene::Environment::parse(o.environment);
  return settings;
}

std::unique_ptr<gi::Solver> makeSolver(const SolverOptions& o, const vk::Context& ctx, const scene::Scene& s,
                                       const scene::Geometry& g, int animation, const gi::Hierarchy* hierarchy) {
  if (o.method == "none") return nullptr;
  if (o.method == "pt")
    throw SettingsError(
        "--method pt: the path tracer runs on the CPU; use `ivgi render --method pt` (bench and info measure iv, "
        "ar and none)");
  if (o.method == "ar") {
    gi::Hierarchy h = hierarchy ? *hierarchy : gi::restPoseHierarchy(s, g);
    const std::vector<bool> moves = gi::movingRoots(h, s, g, animation);
    return std::make_unique<gi::ArSolver>(ctx, g, std::move(h), arSettings(o), moves);
  }
  if (o.method != "iv") throw SettingsError("--method '" + o.method + "': methods are iv, ar, pt and none");
  gi::IvSettings settings = o.iv;
  settings.memoryBudget = o.maxMemoryMiB << 20;
  if (o.rigid != "auto") settings.rigidOnce = o.rigid == "once";
  if (!o.environment.empty()) settings.environment = scene::Environment::parse(o.environment);
  // A still scene is solved once, for every frame: where a camera moves, for every view.
  settings.viewGuided = scene::animationMovesGeometry(s, animation) || !scene::animationMovesCameras(s, animation);
  gi::IvSetup setup = hierarchy ? gi::IvSetup{*hierarchy, settings, {}} : gi::makeIvSetup(s, g, settings);
  gi::markMovingObjects(setup, s, g, animation);
  return std::make_unique<gi::IvSolver>(ctx, g, std::move(setup));
}

reference::PathSettings pathSettings(const PathOptions& o, const SolverOptions& solver) {
  reference::PathSettings settings{
      .spp = o.spp, .bounces = solver.iv.bounces ? int(*solver.iv.bounces) : -1, .seed = o.seed, .threads = o.threads};
  reference::validate(settings);
  return settings;
}

}  // namespace ivgi::cli

#include <algorithm>
#include <filesystem>

#include "engine/cli/commands.h"
#include "engine/cli/options.h"
#include "engine/scene/gltf.h"
#include "scenes/builtin.h"

namespace ivgi::cli {

scene::Scene loadScene(const SceneChoice& choice) {
  const std::string& name = choice.scene.empty() ? "cornell" : choice.scene;
  auto builtins = scenes::builtinSceneNames();
  bool builtin = std::find(builtins.begin(), builtins.end(), name) != builtins.end() && !std::filesystem::exists(name);
  if (!builtin) return scene::loadGltf(name);
  if (name == "cornell") return scene::sceneFromModel(scenes::cornellBox({.cells = choice.cells}), "built-in cornell");
  return scene::sceneFromModel(scenes::furnace({.cells = choice.cells}), "built-in furnace");
}

scene::Geometry renderableGeometry(const scene::Scene& s) {
  scene::Geometry g = scene::buildGeometry(s);
  if (g.triangles.empty()) throw scene::LoadError(s.source + ": the scene has no triangles to render");
  return g;
}

std::unique_ptr<gi::Solver> makeSolver(const SolverOptions& o, const vk::Context& ctx, const scene::Scene& s,
                                       const scene::Geometry& g, int animation, const gi::Hierarchy* hierarchy) {
  if (o.method == "none") return nullptr;
  if (o.method == "pt")
    throw SettingsError(
        "--method pt: the path tracer runs on the CPU; use `ivgi render --method pt` (bench and info measure iv and "
        "none)");
  if (o.method != "iv") throw SettingsError("--method '" + o.method + "': methods are iv, pt and none");
  gi::IvSettings settings = o.iv;
  if (!o.environment.empty()) settings.environment = scene::Environment::parse(o.environment);
  gi::IvSetup setup = hierarchy ? gi::IvSetup{*hierarchy, settings, {}} : gi::makeIvSetup(s, g, settings);
  gi::markMovingObjects(setup, s, g, animation);
  return std::make_unique<gi::IvSolver>(ctx, g, std::move(setup));
}

reference::PathSettings pathSettings(const PathOptions& o, const SolverOptions& solver) {
  reference::PathSettings settings{
      .spp = o.spp, .bounces = o.bouncesGiven ? int(solver.iv.bounces) : -1, .seed = o.seed, .threads = o.threads};
  reference::validate(settings);
  return settings;
}

}  // namespace ivgi::cli

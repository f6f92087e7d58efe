#include <algorithm>
#include <filesystem>

#include "engine/cli/commands.h"
#include "engine/cli/options.h"
#include "engine/gi/environment.h"
#include "engine/scene/gltf.h"
#include "scenes/builtin.h"

namespace ivgi::cli {

scene::Scene loadScene(const SceneChoice& choice) {
  if (choice.cells < 1 || choice.cells > 512) throw UsageError("--cells " + std::to_string(choice.cells) + ": must be 1 to 512");
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

std::optional<gi::IvSetup> solverSetup(const SolverOptions& o, const scene::Scene& s, const scene::Geometry& g, int animation,
                                       const gi::Hierarchy* hierarchy) {
  if (o.method == "none") return std::nullopt;
  if (o.method == "pt") throw UsageError("--method pt: the path tracer runs on the CPU; use `ivgi render --method pt` (bench and info measure iv and none)");
  if (o.method != "iv") throw UsageError("--method '" + o.method + "': methods are iv, pt and none");
  if (o.bins < 1 || o.bins > 64) throw UsageError("--bins " + std::to_string(o.bins) + ": must be 1 to 64");
  if (!(o.epsilon > 0.0f && o.epsilon <= 1.0f)) throw UsageError("--eps must lie in (0, 1]");
  if (o.bounces < 0 || o.bounces > 64) throw UsageError("--bounces must be 0 to 64");
  if (!(o.kappa >= 0.01f && o.kappa <= 1000.0f)) throw UsageError("--kappa must lie in [0.01, 1000]");
  gi::IvSettings settings;
  settings.bins = o.bins;
  settings.epsilon = o.epsilon;
  settings.bounces = uint32_t(o.bounces);
  settings.kappa = o.kappa;
  if (!o.environment.empty()) settings.environment = gi::environmentBins(o.environment, o.bins);
  if (!hierarchy) return gi::makeIvSetup(s, g, settings, animation);
  gi::IvSetup setup{*hierarchy, settings, {}};
  gi::markMovingObjects(setup, s, g, animation);
  return setup;
}

reference::PathSettings pathSettings(const PathOptions& o, const SolverOptions& solver) {
  if (o.spp < 1 || o.spp > 1u << 20) throw UsageError("--spp " + std::to_string(o.spp) + ": must be 1 to 1048576");
  if (o.threads > 1024) throw UsageError("--threads " + std::to_string(o.threads) + ": must be 0 (every core) to 1024");
  if (o.bouncesGiven && (solver.bounces < 0 || solver.bounces > 64)) throw UsageError("--bounces must be 0 to 64");
  return {.spp = o.spp, .bounces = o.bouncesGiven ? solver.bounces : -1, .seed = o.seed, .threads = o.threads};
}

}  // namespace ivgi::cli

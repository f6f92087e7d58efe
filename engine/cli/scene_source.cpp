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

std::optional<gi::IvSetup> solverSetup(const SolverOptions& o, const scene::Scene& s, const scene::Geometry& g) {
  if (o.method == "none") return std::nullopt;
  if (o.method != "iv") throw UsageError("--method '" + o.method + "': methods are iv and none");
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
  return gi::makeIvSetup(s, g, settings);
}

}  // namespace ivgi::cli

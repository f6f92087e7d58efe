#include <algorithm>
#include <filesystem>

#include "engine/cli/commands.h"
#include "engine/cli/options.h"
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

}  // namespace ivgi::cli

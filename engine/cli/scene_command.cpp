#include <cmath>
#include <cstdio>
#include <filesystem>

#include "engine/cli/commands.h"
#include "engine/cli/options.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"

namespace ivgi::cli {

int runScene(const SceneOptions& o) {
  auto ext = std::filesystem::path(o.out).extension();
  if (ext != ".gltf" && ext != ".glb") throw SettingsError("--out '" + o.out + "': the file must end in .gltf or .glb");
  tinygltf::Model model;
  if (o.glossy && o.name != "cornell") throw SettingsError("--glossy: only the built-in cornell has a glossy variant");
  if (o.name == "cornell")
    model = scenes::cornellBox({.cells = o.cells, .animated = !o.still, .glossy = o.glossy});
  else if (o.name == "furnace")
    model = scenes::furnace({.cells = o.cells, .albedo = o.albedo, .emission = o.emission, .blocks = o.blocks});
  else
    throw SettingsError("unknown built-in scene '" + o.name + "' (built-in: cornell, furnace)");
  auto dir = std::filesystem::path(o.out).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
  scenes::writeModel(model, o.out);
  std::printf("wrote %s\n", o.out.c_str());
  return 0;
}

}  // namespace ivgi::cli

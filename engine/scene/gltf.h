#pragma once
// glTF 2.0 (.gltf and .glb) to Scene, through tinygltf, with every accessor checked.
#include <string>

#include "engine/scene/scene.h"

namespace tinygltf {
class Model;
}

namespace ivgi::scene {

// Converts an already parsed model; `source` names it in messages.
Scene sceneFromModel(const tinygltf::Model& model, const std::string& source, const Limits& limits = {});

}  // namespace ivgi::scene

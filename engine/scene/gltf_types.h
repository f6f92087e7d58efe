#pragma once
// The JSON types of the glTF properties ivgi reads. tinygltf reads a property of the wrong type as
// if it were absent: a material's pbrMetallicRoughness given as an array left the glTF defaults (a
// white metal), a texture index of -1 no texture, a mesh's primitives given as an object no
// triangles. Such a file is refused instead, naming the property, so that nothing renders as
// something its file does not say. Properties that change nothing drawn (names, extras) are left to
// tinygltf.
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>

namespace ivgi::scene {

// The first property, among those ivgi reads, whose type or length the glTF 2.0 schema does not
// allow, as "materials[0].pbrMetallicRoughness is an array, not an object"; none where all are as
// the schema says. Expects the JSON tinygltf has parsed (gltfJson).
std::optional<std::string> gltfTypeProblem(const nlohmann::json& gltf);

// Where a file is not glTF 2.0, what it is, as "is glTF 1.0 (asset.version \"1.0\")", from a .glb's
// header and the file's JSON (gltfJson); none where a glTF 2.0 reader may read it, a later minor
// version included unless its asset.minVersion asks for more (the specification has such a reader
// ignore what the minor version added). A file without a version string whose collections are
// objects of named entries is glTF 1.0's form.
std::optional<std::string> gltfVersionProblem(std::span<const unsigned char> file, bool binary,
                                              const nlohmann::json& gltf);

// The JSON of a .gltf file's bytes, or of a .glb's JSON chunk; discarded (is_discarded()) where it
// cannot be read as JSON.
nlohmann::json gltfJson(std::span<const unsigned char> file, bool binary);

}  // namespace ivgi::scene

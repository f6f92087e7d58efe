#pragma once
// Builds glTF models in memory: the built-in scenes and the test scenes are made with it.
#include <tiny_gltf.h>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <string>
#include <vector>

namespace ivgi::scenes {

struct MeshData {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs, uvs1;  // TEXCOORD_0 and TEXCOORD_1, each written where not empty
  std::vector<glm::vec4> colors;     // COLOR_0, written where not empty
  std::vector<uint32_t> indices;
};

// Appends a bilinear patch p0 p1 p2 p3 (in order around it) split into nu × nv cells, with the flat
// normal turned toward `facing` (a point on the side the surface faces), winding to match.
void addQuad(MeshData& mesh, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, int nu, int nv, glm::vec3 facing);
// Appends the six faces of the box centre ± half, facing out, each split into cells × cells.
void addBox(MeshData& mesh, glm::vec3 centre, glm::vec3 half, int cells);
// Cells along an edge of `length` for `cellsPerMetre`, at least one.
int cellsFor(float length, float cellsPerMetre);

class GltfBuilder {
 public:
  GltfBuilder();
  // A Lambertian material (KHR_materials_specular with no specular layer) with linear base colour
  // and emitted radiance (split into factor and emissive strength).
  int material(const std::string& name, glm::vec3 baseColor, glm::vec3 radiance = glm::vec3(0.0f));
  // glTF's metallic-roughness material, its dielectric's specular layer as the core specification's.
  int glossyMaterial(const std::string& name, glm::vec3 baseColor, float metallic, float roughness);
  int mesh(const std::string& name, const std::vector<std::pair<MeshData, int>>& primitives);
  int node(const std::string& name, int mesh = -1, glm::vec3 translation = glm::vec3(0.0f),
           glm::quat rotation = glm::quat(1, 0, 0, 0), int parent = -1);
  int camera(const std::string& name, float yfov, float znear, glm::vec3 position, glm::quat rotation);
  // A KHR_lights_punctual light of white `intensity` ("point", "spot" or "directional", which
  // shines along its node's -z) on a node of its own; returns the node.
  int light(const std::string& name, const std::string& type, float intensity, glm::vec3 position,
            glm::quat rotation = glm::quat(1, 0, 0, 0));
  // One channel animating `path` ("translation", "rotation", "scale") of `node`; values per key.
  void animate(const std::string& animation, int node, const std::string& path, const std::vector<float>& times,
               const std::vector<float>& values, const std::string& interpolation = "LINEAR");
  int accessor(const void* data, size_t count, int componentType, int type, size_t elementBytes, int target = 0);
  tinygltf::Model& model() { return model_; }
  tinygltf::Model finish();

 private:
  tinygltf::Model model_;
  void useExtension(const std::string& name);
};

// Writes `model` to `path` (.gltf with embedded buffers, or .glb), through a temporary file.
void writeModel(const tinygltf::Model& model, const std::string& path);

}  // namespace ivgi::scenes

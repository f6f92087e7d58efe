#pragma once
// The scene as ivgi models it: what the glTF file says, decoded and validated, independent of
// Vulkan. Node transforms, skins and morph weights are animated by animation.h.
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "shaders/interface.h"

namespace ivgi::scene {

// Bad input: the message names the file and the problem.
struct LoadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Texture {
  std::string name;
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;         // 8-bit RGBA texels as stored (sRGB-encoded for colour textures)
  int wrapS = 10497, wrapT = 10497;  // glTF wrap enums: REPEAT, CLAMP_TO_EDGE 33071, MIRRORED_REPEAT 33648
  bool nearest = false;              // the sampler's magFilter is NEAREST: the nearest texel, not a blend
};

// How one texture reference maps a surface's coordinates to the texture's: the set it reads
// (`texCoord`, or KHR_texture_transform's in its place), whose coordinates are then scaled, rotated
// counter-clockwise by `rotation` radians about the origin and offset (KHR_texture_transform).
struct TextureTransform {
  glm::vec2 offset{0.0f};
  float rotation = 0.0f;
  glm::vec2 scale{1.0f};
  int texCoord = 0;  // 0: TEXCOORD_0, 1: TEXCOORD_1
  // TEXCOORD_0 as it is.
  bool identity() const {
    return offset == glm::vec2(0.0f) && rotation == 0.0f && scale == glm::vec2(1.0f) && texCoord == 0;
  }
  // The rows of the affine map (u, v, 1) → u', v'.
  glm::vec3 rowU() const;
  glm::vec3 rowV() const;
};

struct Material {
  std::string name;
  glm::vec4 baseColor{1.0f};
  int baseColorTexture = -1;
  TextureTransform baseColorTransform;
  glm::vec3 emissive{0.0f};
  float emissiveStrength = 1.0f;  // KHR_materials_emissive_strength
  int emissiveTexture = -1;
  TextureTransform emissiveTransform;
  float metallic = 1.0f, roughness = 1.0f;  // in [0, 1]
  int metallicRoughnessTexture = -1;        // linear: G roughness, B metallic
  TextureTransform metallicRoughnessTransform;
  int normalTexture = -1;  // linear: the tangent-space normal, gpu::mappedNormal
  TextureTransform normalTransform;
  float normalScale = 1.0f;
  // alphaMode: MASK's alphaCutoff (where the base colour's alpha, factor × texture × COLOR_0, is
  // below it the surface is not there), gpu::kAlphaOpaque or gpu::kAlphaBlended (gpu::presenceOf).
  float alphaCutoff = gpu::kAlphaOpaque;
  float specular = 1.0f;          // KHR_materials_specular: the dielectric's specular weight
  glm::vec3 specularColor{1.0f};  // and its reflectance's colour
  float ior = 1.5f;               // KHR_materials_ior (0: the reflectance is the colour itself)
  // The dielectric's Fresnel reflectance at normal incidence (rgb) and at grazing (a), as glTF's
  // KHR_materials_specular defines them.
  glm::vec4 dielectricReflectance() const;
  bool doubleSided = false;
};

struct MorphTarget {
  std::vector<glm::vec3> positions, normals;  // deltas; empty when the target leaves them unchanged
};

struct Primitive {
  std::vector<glm::vec3> positions, normals;  // normals empty: flat shading, surfel normals from faces
  std::vector<glm::vec2> uvs;                 // TEXCOORD_0, empty if absent
  std::vector<glm::vec2> uvs1;                // TEXCOORD_1, empty if absent
  std::vector<glm::vec4> colors;              // COLOR_0 (linear, multiplies the base colour), empty if absent
  std::vector<glm::uvec4> joints;             // JOINTS_0
  std::vector<glm::vec4> weights;             // WEIGHTS_0
  std::vector<uint32_t> indices;              // triangle list (strips and fans are converted)
  std::vector<MorphTarget> targets;
  int material = -1;  // -1: the glTF default material
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
  std::vector<float> weights;  // default morph weights
};

struct Node {
  std::string name;
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
  std::optional<glm::mat4> matrix;  // a node given by matrix is not animated
  std::vector<int> children;
  int parent = -1;
  int mesh = -1, skin = -1, camera = -1, light = -1;
  std::vector<float> weights;  // morph weights overriding the mesh's
};

struct Skin {
  std::string name;
  std::vector<int> joints;
  std::vector<glm::mat4> inverseBind;
};

struct Camera {
  std::string name;
  float yfov = 0.7f;  // radians
  float znear = 0.01f;
  float zfar = 0.0f;      // 0: infinite
  float aspectRatio = 0;  // 0: the image's
  // An orthographic camera: its view's half height (glTF's ymag; the half width follows from the
  // image's aspect, as a perspective camera's does from yfov), in place of yfov.
  bool orthographic = false;
  float ymag = 1.0f;
};

struct Light {  // KHR_lights_punctual
  enum class Type { Directional, Point, Spot } type = Type::Point;
  std::string name;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;  // 0: infinite
  float innerCone = 0.0f, outerCone = 0.7853982f;
};

enum class Interpolation { Step, Linear, CubicSpline };
enum class Path { Translation, Rotation, Scale, Weights };

struct Sampler {
  std::vector<float> input;   // key times, strictly increasing
  std::vector<float> output;  // components per key (×3 for CUBICSPLINE: in-tangent, value, out-tangent)
  int components = 0;
  Interpolation interpolation = Interpolation::Linear;
};

struct Channel {
  int node = -1;
  Path path = Path::Translation;
  int sampler = -1;
};

struct Animation {
  std::string name;
  std::vector<Sampler> samplers;
  std::vector<Channel> channels;
  float start = 0.0f, end = 0.0f;  // first and last key time over all samplers
};

struct Scene {
  std::string source;  // file name used in messages
  std::vector<Mesh> meshes;
  std::vector<Node> nodes;
  std::vector<int> roots;  // nodes of the default scene
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Camera> cameras;
  std::vector<Light> lights;
  std::vector<Skin> skins;
  std::vector<Animation> animations;
  std::vector<std::string> warnings;

  // Index of an animation, camera, … by name or number; nullopt when none matches.
  std::optional<int> findAnimation(const std::string& nameOrIndex) const;
  std::optional<int> findCameraNode(const std::string& nameOrIndex) const;  // returns a node index
  std::vector<int> cameraNodes() const;  // nodes carrying a camera, in traversal order
};

// What a scene may declare before it is refused (--max-triangles, --max-morph-deltas,
// --max-texels), checked before anything is sized by it: past these, memory and set-up time would
// take a render-farm node down before a frame.
struct Limits {
  uint64_t triangles = uint64_t(1) << 23;    // drawn, as modelled or as tessellated
  uint64_t morphDeltas = uint64_t(1) << 25;  // morph targets × their vertices, as read or as drawn
  uint64_t texels = uint64_t(1) << 26;       // of one image, as its header declares (8192²)
};

Scene loadGltf(const std::string& path, const Limits& limits = {});

// What the scene draws as modelled: each drawn instance's primitives, instanced nodes counted as
// often as they are drawn.
struct DrawnSize {
  uint64_t triangles = 0, morphDeltas = 0;
};
DrawnSize drawnSize(const Scene& scene);

}  // namespace ivgi::scene

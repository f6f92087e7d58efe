#pragma once
// The scene flattened for the GPU: one vertex array over every drawn (node, primitive) instance, the
// triangles, the materials and textures, and the surfels of design.md §1.2 with what the surfel pass
// needs to rebuild them each frame. Built once; per frame only FrameInputs change.
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "engine/scene/animation.h"
#include "engine/scene/scene.h"

namespace ivgi::scene {

// std430 layouts shared with shaders/common.glsl.
struct GpuVertex {
  glm::vec3 position;  // rest pose, primitive space
  uint32_t instance;
  glm::vec3 normal;
  uint32_t local;  // index inside its primitive, for morph deltas
  glm::uvec4 joints;
  glm::vec4 weights;
};
struct GpuInstance {
  uint32_t matrix;          // node world matrix, or first joint matrix when skinned
  uint32_t skinned;
  uint32_t morphTargets;
  uint32_t morphWeightBase;
  uint32_t morphDeltaBase;  // deltas of target k, vertex v at morphDeltaBase + k * vertexCount + v
  uint32_t vertexCount;
  uint32_t pad0, pad1;
};
struct GpuMorphDelta {
  glm::vec4 position, normal;
};
struct GpuTriangle {
  uint32_t v0, v1, v2;
  uint32_t material;  // material index | kFlatShaded when the primitive has no normals
};
constexpr uint32_t kFlatShaded = 0x80000000u;
struct GpuMaterial {
  glm::vec4 baseColor;
  glm::vec4 emission;  // rgb = emissive factor × strength (radiance), w unused
  int32_t baseColorTexture, emissiveTexture, pad0, pad1;
};
struct GpuTexture {
  uint32_t offset, width, height, wrap;  // offset in texels; wrap = wrapS | wrapT << 16 (glTF enums)
};
struct GpuSurfelSource {
  uint32_t firstVertex, vertexCount;      // welded vertices, in Geometry::surfelVertices
  uint32_t firstTriangle, triangleCount;  // adjacent non-degenerate triangles, in Geometry::surfelTriangles
};
struct WorldVertex {  // output of the animate pass
  glm::vec4 position, normal;
};
struct Surfel {  // output of the surfel pass
  glm::vec4 positionArea;  // xyz: centroid of the surfel's area (its vertex's third of each triangle), w: area
  glm::vec4 normal;
  glm::vec4 shape;  // x: radius of a disk of its area; zw: half-extents of its rectangle along tangentFrame(normal) (y: angle, 0)
};

struct FrameInputs {
  std::vector<glm::mat4> matrices;  // node world matrices, then joint matrices of every skin
  std::vector<float> morphWeights;
};

struct Bounds {
  glm::vec3 min{1e30f}, max{-1e30f};
  bool empty() const { return min.x > max.x; }
  void add(glm::vec3 p) { min = glm::min(min, p), max = glm::max(max, p); }
};

struct Geometry {
  std::vector<GpuVertex> vertices;
  std::vector<glm::vec2> uvs;
  std::vector<GpuInstance> instances;
  std::vector<GpuMorphDelta> morphDeltas;
  std::vector<GpuTriangle> triangles;
  std::vector<GpuMaterial> materials;  // last one: the glTF default material
  std::vector<GpuTexture> textures;
  std::vector<uint32_t> texels;  // linear RGBA as two packHalf2x16 words per texel
  std::vector<GpuSurfelSource> surfels;
  std::vector<uint32_t> surfelVertices, surfelTriangles;
  std::vector<glm::vec4> surfelAlbedo, surfelEmission;  // static: base colour × texture at the vertex UV

  uint32_t degenerateTriangles = 0;
  uint32_t nodeCount = 0;
  std::vector<uint32_t> skinJointBase;  // per skin: index of its first joint matrix
  std::vector<int> instanceNode;        // per instance
  uint32_t morphWeightCount = 0;

  FrameInputs frameInputs(const Scene& scene, const Pose& pose) const;
};

Geometry buildGeometry(const Scene& scene);

// tangentFrame() of common.glsl: the tangents of unit normal n, from n alone (so that neighbours on
// a flat face agree).
void tangentFrame(glm::vec3 n, glm::vec3& t1, glm::vec3& t2);

// The animate pass evaluated on the host: the reference the GPU is tested against.
std::vector<WorldVertex> animateOnHost(const Geometry& geometry, const FrameInputs& inputs);
// The surfel pass on the host, likewise.
std::vector<Surfel> surfelsOnHost(const Geometry& geometry, const std::vector<WorldVertex>& world);

Bounds worldBounds(const std::vector<WorldVertex>& world);

// Per instance: whether `animation` can move its world-space geometry (its node or an ancestor is
// animated, its morph weights are, or it is skinned and the animation moves anything). The solver
// links and prunes what cannot move once.
std::vector<bool> movingInstances(const Scene& scene, const Geometry& geometry, int animation);

}  // namespace ivgi::scene

#pragma once
// The scene flattened for the GPU: one vertex array over every drawn (node, primitive) instance, the
// triangles, the materials and textures, and the surfels of docs/design.md §2.1 with what the surfel pass
// needs to rebuild them each frame. Built once; per frame only FrameInputs change.
#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <vector>

#include "engine/scene/animation.h"
#include "engine/scene/back_faces.h"
#include "engine/scene/scene.h"
#include "shaders/interface.h"

namespace ivgi::scene {

// The GPU's layouts of scene data (shaders/interface.h); Material and Texture are gpu:: (scene.h
// has the glTF ones).
using gpu::Instance;
using gpu::MorphDelta;
using gpu::Surfel;
using gpu::SurfelSource;
using gpu::Triangle;
using gpu::Vertex;
using gpu::WorldVertex;

struct FrameInputs {
  std::vector<glm::mat4> matrices;  // node world matrices, then joint matrices of every skin
  std::vector<float> morphWeights;
};

struct Bounds {
  glm::vec3 min{1e30f}, max{-1e30f};
  bool empty() const { return min.x > max.x; }
  void add(glm::vec3 p) { min = glm::min(min, p), max = glm::max(max, p); }
};

// The least share of a surfel's area kept where its material's alpha takes it away: a surfel of no area
// at all would have no direction to send or receive along.
constexpr float kLeastCoverage = 1e-3f;

struct Geometry {
  std::vector<Vertex> vertices;
  std::vector<glm::vec4> uvs;     // TEXCOORD_0 (xy) and TEXCOORD_1 (zw), zero where a primitive has none
  std::vector<glm::vec4> colors;  // COLOR_0, white where a primitive has none
  bool vertexColors = false;      // some primitive has COLOR_0
  std::vector<Instance> instances;
  uint32_t backInstances = 0;  // the last ones: the backs of open double-sided surfaces (back_faces.h)
  std::vector<MorphDelta> morphDeltas;
  std::vector<Triangle> triangles;
  // The last ones: the exposed backs of open double-sided surfaces (back_faces.h), which the path
  // tracer leaves out.
  uint32_t backTriangles = 0;
  // The file's, then the glTF default material, then the backs' (their fronts' without emission).
  std::vector<gpu::Material> materials;
  bool glossyMaterials = false;         // some drawn material is not Lambertian
  bool lobeDominatedMaterials = false;  // in some, the lobe reflects most (gpu::lobeDominates): a metal
  // in some, the lobe sends its light too far from evenly to send it so (kEvenLobeDeviation)
  bool directionalLobes = false;
  // in some, a dielectric's base sends its light too far from evenly (scene::sendsBaseByDirection)
  bool directionalBases = false;
  bool normalTextures = false;  // some drawn material has a normal texture
  bool cutouts = false;         // some drawn material's alpha takes surface away (MASK, BLEND)
  bool blended = false;         // some of those is BLEND: there for its alpha's share of samples
  std::vector<gpu::Texture> textures;
  std::vector<uint32_t> texels;  // linear RGBA as two packHalf2x16 words per texel
  std::vector<SurfelSource> surfels;
  uint32_t backSurfels = 0;  // the last ones: the back faces' (backTriangles)
  std::vector<uint32_t> surfelVertices, surfelTriangles;
  // static: base colour × COLOR_0 × texture (emission: emissive × texture), each triangle's
  // hat-weighted mean over the surfel's triangles
  std::vector<glm::vec4> surfelAlbedo, surfelEmission;
  // The material's BRDF at each surfel (its base colour and metallic-roughness means as above), for
  // what its specular lobe reflects of the indirect light
  std::vector<gpu::SurfaceBrdf> surfelBrdf;
  // The share of each surfel's area its material's alpha leaves (alphaMode MASK, BLEND; 1 elsewhere), at
  // least kLeastCoverage: the surfel pass scales its area by it, so that a leaf's holes let light by.
  std::vector<float> surfelCoverage;

  uint32_t degenerateTriangles = 0;
  uint32_t nodeCount = 0;
  std::vector<uint32_t> skinJointBase;  // per skin: index of its first joint matrix
  std::vector<int> instanceNode;        // per instance
  uint32_t morphWeightCount = 0;

  FrameInputs frameInputs(const Scene& scene, const Pose& pose) const;
};

// Told after each node drawn how many of them are built: a scene of many is long to build.
using BuildProgress = std::function<void(size_t built, size_t nodes)>;

// `tessellation` N > 0: triangle edges longer than 1/N of the scene's size (the diagonal of its
// bounds at rest), or near a smaller primitive longer than their distance to it, are split
// (tessellation.h), so that no surface is sampled coarser than that. Throws LoadError, before
// allocating for them, where the scene draws more than `limits` allow, and where its tessellation
// reaches more triangles.
// The exposed backs of open double-sided surfaces get faces of their own (back_faces.h), those
// that see only open space where `openSpace` or a directional light lights it.
Geometry buildGeometry(const Scene& scene, uint32_t tessellation = 0, const BuildProgress& progress = {},
                       const Limits& limits = {}, OpenSpace openSpace = OpenSpace::Lit);

// The animate pass evaluated on the host: the reference the GPU is tested against.
std::vector<WorldVertex> animateOnHost(const Geometry& geometry, const FrameInputs& inputs);
// The surfel pass on the host, likewise.
std::vector<Surfel> surfelsOnHost(const Geometry& geometry, const std::vector<WorldVertex>& world);
// The surfel of each vertex (welded vertices share one), -1 for vertices without one.
std::vector<int32_t> vertexSurfels(const Geometry& geometry);

Bounds worldBounds(const std::vector<WorldVertex>& world);

// A triangle's emission (emissive factor × texture, linear) at barycentric weights b, c of its
// corners v1, v2.
glm::vec3 emissionAt(const Geometry& g, const Triangle& t, float b, float c);

// The parts of an emitting triangle its light is sampled by: where a texture varies its emission,
// its n² equal sub-triangles (about four a texel, as the surfels' means take it), else the whole
// triangle; each with its corners' barycentric weights (b, c) and the mean of its emission at its
// centroid and corners (what the points spread over it go by). None where the triangle does not
// emit.
struct EmissionCell {
  glm::vec2 corners[3];
  glm::vec3 emission;
};
std::vector<EmissionCell> emissionCells(const Geometry& g, const Triangle& t);

// A hash of a point's exact bits: vertices are welded by position through it.
uint64_t hashPoint(glm::vec3 p);

// Per surfel: whether another faces the other way in its place (a face of it is kTwinned): a back
// face's, or one of a face with a back.
std::vector<bool> twinnedSurfels(const Geometry& g);

// The triangles but the backs (Geometry::backTriangles): each face once.
inline std::vector<Triangle> frontTriangles(const Geometry& g) {
  return {g.triangles.begin(), g.triangles.end() - std::ptrdiff_t(g.backTriangles)};
}

// Per instance: whether `animation` can move its world-space geometry (its node or an ancestor is
// animated, its morph weights are, or it is skinned and the animation moves anything). The solver
// links and prunes what cannot move once.
std::vector<bool> movingInstances(const Scene& scene, const Geometry& geometry, int animation);

// Per instance: whether `animation` moves it rigidly, its shape kept: it moves, is neither skinned
// nor morphed, and its world matrix keeps the metric of its rest pose (no scale or shear changes)
// at every key time of the animation and halfway between. The iv solver prunes such an object's
// links to itself once, in its rest pose.
std::vector<bool> rigidlyMovingInstances(const Scene& scene, const Geometry& geometry, int animation);

// Per instance: whether its triangles enclose a volume, consistently wound: every edge (between
// vertices welded by position) is crossed once each way, up to T-junctions and cracks (the loops of
// the edges left over enclose under 10⁻³ of the instance's area). Along any line through such a
// surface its faces turned toward a viewer and those turned away alternate, so those turned away are
// never the first seen from outside the volume (the iv prune relies on it). Degenerate triangles are
// ignored.
std::vector<bool> closedInstances(const Geometry& geometry);

// What rays against the triangles of `geometry` pass (TriangleRays): the points its materials' alpha
// takes away (alphaMode MASK or BLEND, presenceAt). Empty where no material takes any.
TriangleRays::CutAway cutAwayOf(const Geometry& geometry);

}  // namespace ivgi::scene

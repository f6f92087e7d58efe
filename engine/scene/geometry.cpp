#include "engine/scene/geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/packing.hpp>
#include <map>
#include <memory>
#include <unordered_map>

#include "engine/core/parallel.h"
#include "engine/image/colour.h"
#include "engine/scene/back_faces.h"
#include "engine/scene/reflectance.h"
#include "engine/scene/tessellation.h"
#include "engine/scene/texture_sampling.h"

namespace ivgi::scene {

uint64_t hashPoint(glm::vec3 p) {
  uint32_t b[3];
  std::memcpy(b, &p, 12);
  return (uint64_t(b[0]) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(b[1]) * 0xC2B2AE3D27D4EB4Full) ^
         (uint64_t(b[2]) * 0x165667B19E3779F9ull);
}

namespace {

// A triangle whose area is negligible against its longest edge (or that repeats a vertex) carries no
// transport; docs/design.md §6 wants it counted and excluded.
bool degenerate(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  float cross = glm::length(glm::cross(b - a, c - a));
  float edge2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  return !(cross > 1e-7f * edge2) || edge2 == 0.0f;
}

// Normal transform without inverting: the cofactor matrix is det·M⁻ᵀ, finite for singular M too.
glm::vec3 transformNormal(const glm::mat4& m, glm::vec3 n) {
  glm::vec3 c0(m[0]), c1(m[1]), c2(m[2]);
  glm::mat3 cof(glm::cross(c1, c2), glm::cross(c2, c0), glm::cross(c0, c1));
  float det = glm::dot(c0, glm::cross(c1, c2));
  glm::vec3 r = cof * n * (det < 0.0f ? -1.0f : 1.0f);
  float len = glm::length(r);
  return len > 0.0f ? r / len : glm::vec3(0.0f);
}

// Texture t's texels, decoded once here to linear RGBA16F so that a lookup only unpacks (the sRGB
// curve per texel fetch cost lavapipe more than the rest of the resolve pass), and its record.
void appendTexture(Geometry& g, const Texture& t, bool srgb) {
  const uint32_t wrap = uint32_t(t.wrapS) | uint32_t(t.wrapT) << 16;
  g.textures.push_back({uint32_t(g.texels.size() / 2), uint32_t(t.width), uint32_t(t.height), wrap,
                        glm::vec4(TextureTransform{}.rowU(), t.nearest ? 1.0f : 0.0f),
                        glm::vec4(TextureTransform{}.rowV(), 0.0f)});
  auto decode = [srgb](uint8_t c) { return srgb ? image::srgbToLinear(c / 255.0f) : c / 255.0f; };
  for (size_t p = 0; p < t.rgba.size() / 4; ++p) {
    const uint8_t* c = &t.rgba[4 * p];
    g.texels.push_back(glm::packHalf2x16(glm::vec2(decode(c[0]), decode(c[1]))));
    g.texels.push_back(glm::packHalf2x16(glm::vec2(decode(c[2]), c[3] / 255.0f)));
  }
}

// The passes' record of material m, with the texture records it reads.
gpu::Material gpuMaterial(const Material& m, int baseColorTexture, int emissiveTexture, int metallicRoughnessTexture,
                          int normalTexture) {
  gpu::Material out{};
  out.baseColor = m.baseColor;
  out.emission = glm::vec4(m.emissive * m.emissiveStrength, 0.0f);
  out.specular = m.dielectricReflectance();
  out.baseColorTexture = baseColorTexture;
  out.emissiveTexture = emissiveTexture;
  out.metallicRoughnessTexture = metallicRoughnessTexture;
  out.normalTexture = normalTexture;
  out.metallic = m.metallic;
  out.roughness = m.roughness;
  out.normalScale = m.normalScale;
  out.alphaCutoff = m.alphaCutoff;
  return out;
}

// What a diffuse solver's surface reflects of uniform light, where its base colour is `base` and
// its texture coordinates `uv` (both sets): the base colour itself where the material is Lambertian.
glm::vec4 solverAlbedo(const Geometry& g, const gpu::Material& m, glm::vec4 base, glm::vec4 uv) {
  const gpu::SurfaceBrdf brdf = surfaceBrdf(m, glm::vec3(base), sampleTexture(g, m.metallicRoughnessTexture, uv));
  return gpu::isLambertian(brdf) ? base : glm::vec4(SpecularAlbedo::table().meanReflectance(brdf), base.a);
}

// What a surfel reflects and emits where it varies over its triangles (a texture, vertex colours):
// the means of albedo and emission over each triangle weighted by a corner's barycentric coordinate
// (its hat function: the weight with which the resolve spreads the corner's light), so that a coarse
// mesh under a detailed texture takes the texture's mean where its vertices would each pick a texel.
// Sampled at the centroids of the triangle's n² equal sub-triangles, about four a texel the
// triangle covers (at most 32² a triangle).
// Where the material takes some of the surface away (alphaMode MASK or BLEND), the means are over
// what is left, times the share left (`coverage`): the sums divided by the coverage's give what is
// there.
struct CornerMeans {
  glm::vec4 albedo[3], emission[3], base[3];
  glm::vec2 metallicRoughness[3];  // the texture's factors (B, G)
  float coverage[3];
};

int samplesAcross(const Geometry& g, const gpu::Material& m, const glm::vec4 uv[3]) {
  // The triangle's area on each coordinate set (xy, zw).
  const glm::vec4 a = uv[1] - uv[0], b = uv[2] - uv[0];
  const glm::vec2 uvArea = 0.5f * glm::abs(glm::vec2(a.x * b.y - b.x * a.y, a.z * b.w - b.z * a.w));
  float texels = 0.0f;  // covered, through the reference's transform (its determinant scales the area)
  for (int t : {m.baseColorTexture, m.emissiveTexture, m.metallicRoughnessTexture}) {
    if (t < 0) continue;
    const gpu::Texture& x = g.textures[size_t(t)];
    const float scale = std::abs(x.uvRowU.x * x.uvRowV.y - x.uvRowU.y * x.uvRowV.x);
    texels = std::max(texels, uvArea[x.uvRowV.w != 0.0f ? 1 : 0] * scale * float(x.width) * float(x.height));
  }
  const float n = 2.0f * std::sqrt(texels);  // NaN or infinite from an absurd transform: the bounds
  return n > 4.0f ? (n < 32.0f ? int(std::ceil(n)) : 32) : 4;
}

// Calls at(w, turn) with the barycentric weights w of the centroids of a triangle's n² equal
// sub-triangles; turn is 1 where one points like the triangle, -1 where it points the other way.
template <class At>
void subTriangleCentroids(int n, At&& at) {
  auto centroid = [&](float s, float t, float turn) {
    at(glm::vec3(1.0f - (s + t) / float(n), s / float(n), t / float(n)), turn);
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      centroid(float(i) + 1.0f / 3.0f, float(j) + 1.0f / 3.0f, 1.0f);
      if (i + j + 2 <= n) centroid(float(i) + 2.0f / 3.0f, float(j) + 2.0f / 3.0f, -1.0f);
    }
}

CornerMeans cornerMeans(const Geometry& g, const gpu::Material& m, const glm::vec4 uv[3], const glm::vec4 color[3]) {
  const int n = samplesAcross(g, m, uv);
  CornerMeans out{};
  auto add = [&](glm::vec3 w, float) {
    const glm::vec4 at = w.x * uv[0] + w.y * uv[1] + w.z * uv[2];
    const glm::vec4 base = m.baseColor * (w.x * color[0] + w.y * color[1] + w.z * color[2]) *
                           sampleTexture(g, m.baseColorTexture, at),
                    emission = m.emission * sampleTexture(g, m.emissiveTexture, at);
    const glm::vec4 metalRough = sampleTexture(g, m.metallicRoughnessTexture, at);
    const glm::vec4 albedo = solverAlbedo(g, m, base, at);
    const glm::vec3 there = glm::vec3(w) * gpu::presenceOf(base.a, m.alphaCutoff);
    for (int k = 0; k < 3; ++k)
      out.albedo[k] += there[k] * albedo, out.emission[k] += there[k] * emission, out.base[k] += there[k] * base,
          out.metallicRoughness[k] += there[k] * glm::vec2(metalRough.b, metalRough.g), out.coverage[k] += there[k];
  };
  subTriangleCentroids(n, add);
  // Each corner's weights sum to n²/3 over the n² samples.
  const float norm = 3.0f / float(n * n);
  for (int k = 0; k < 3; ++k)
    out.albedo[k] *= norm, out.emission[k] *= norm, out.base[k] *= norm, out.metallicRoughness[k] *= norm,
        out.coverage[k] *= norm;
  return out;
}

// Whether material `index` of `scene` takes any of its surface away (alphaMode MASK or BLEND): whether
// the least alpha it can take, its factor's times its texture's least texel's times the least
// COLOR_0 alpha of a primitive drawn with it, leaves less than all of it (gpu::presenceOf).
// Bilinear lookups and barycentric blends of the vertices' colours stay at or above those least
// values.
bool cutsAnything(const Scene& scene, size_t index) {
  const Material& m = scene.materials[index];
  if (!gpu::alphaMatters(m.alphaCutoff)) return false;
  float least = m.baseColor.a;
  if (m.baseColorTexture >= 0 && size_t(m.baseColorTexture) < scene.textures.size()) {
    const std::vector<uint8_t>& rgba = scene.textures[size_t(m.baseColorTexture)].rgba;
    uint8_t texel = 255;
    for (size_t p = 3; p < rgba.size(); p += 4) texel = std::min(texel, rgba[p]);
    least *= float(texel) / 255.0f;
  }
  float vertices = 1.0f;
  for (const Mesh& mesh : scene.meshes)
    for (const Primitive& p : mesh.primitives)
      if (p.material == int(index))
        for (const glm::vec4& c : p.colors) vertices = std::min(vertices, c.a);
  return gpu::presenceOf(least * vertices, m.alphaCutoff) < 1.0f;
}

// The world matrix a primitive's positions go through at rest (a skinned mesh's are its bind pose's).
glm::mat4 restMatrix(const Scene& scene, const Pose& rest, int nodeIndex) {
  return scene.nodes[nodeIndex].skin >= 0 ? glm::mat4(1.0f) : rest.world[nodeIndex];
}

// What a tessellation of 1/N of the scene's size allows: edges at most that long, and near a smaller
// primitive no longer than their distance to it, down to its size (tessellation.h); owner ids are
// ownerBase[node] + the primitive's index.
EdgeLimits edgeLimitsOf(const Scene& scene, const Pose& rest, uint32_t tessellation, std::vector<uint32_t>& ownerBase) {
  ownerBase.assign(scene.nodes.size(), 0u);
  struct Surface {
    std::vector<glm::vec3> world;
    const std::vector<uint32_t>* indices;
  };
  std::vector<Surface> surfaces;  // by owner
  Bounds b;
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    ownerBase[n] = uint32_t(surfaces.size());
    if (scene.nodes[n].mesh < 0) continue;
    const glm::mat4 m = restMatrix(scene, rest, int(n));
    for (const Primitive& p : scene.meshes[scene.nodes[n].mesh].primitives) {
      Surface& s = surfaces.emplace_back(Surface{{}, &p.indices});
      for (const glm::vec3& v : p.positions) b.add(s.world.emplace_back(m * glm::vec4(v, 1.0f)));
    }
  }
  EdgeLimits limits(tessellation == 0 || b.empty() ? 0.0f : glm::length(b.max - b.min) / float(tessellation));
  for (size_t owner = 0; owner < surfaces.size(); ++owner)
    limits.addSurface(uint32_t(owner), surfaces[owner].world, *surfaces[owner].indices);
  limits.finish();
  return limits;
}

// Which faces of `g` (its fronts, built) have backs that see out, at the scene's rest pose
// (back_faces.h): lit by the point and spot lights and by points on the emitters (the centroids of
// at most kEmitterPoints of their faces, evenly through their list), and by open space where
// `openSpace` or a directional light lights it.
std::unique_ptr<BackExposure> backExposure(const Scene& scene, const Pose& rest, const Geometry& g,
                                           OpenSpace openSpace) {
  constexpr size_t kEmitterPoints = 16;
  const std::vector<WorldVertex> world = animateOnHost(g, g.frameInputs(scene, rest));
  std::vector<uint32_t> objectOf(g.triangles.size()), emitters;
  for (uint32_t t = 0; t < g.triangles.size(); ++t) {
    objectOf[t] = g.vertices[g.triangles[t].v0].instance;
    if (glm::any(glm::greaterThan(glm::vec3(g.materials[g.triangles[t].material & ~gpu::kTriangleFlags].emission),
                                  glm::vec3(0.0f))))
      emitters.push_back(t);
  }
  std::vector<glm::vec3> lights;
  const size_t points = std::min(emitters.size(), kEmitterPoints);
  for (size_t k = 0; k < points; ++k) {
    const Triangle& e = g.triangles[emitters[k * emitters.size() / points]];
    lights.push_back(glm::vec3(world[e.v0].position + world[e.v1].position + world[e.v2].position) / 3.0f);
  }
  bool sun = false;
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    if (scene.nodes[n].light < 0) continue;
    if (scene.lights[size_t(scene.nodes[n].light)].type == Light::Type::Directional)
      sun = true;
    else
      lights.push_back(glm::vec3(rest.world[n][3]));
  }
  // The rays pass where a material's alpha takes the surface away, as pt's do.
  return std::make_unique<BackExposure>(world, g.triangles, std::move(objectOf), std::move(lights),
                                        sun ? OpenSpace::Lit : openSpace, cutAwayOf(g));
}

}  // namespace

Geometry buildGeometry(const Scene& scene, uint32_t tessellation, const BuildProgress& progress, const Limits& allowed,
                       OpenSpace openSpace) {
  const DrawnSize size = drawnSize(scene);
  if (size.triangles > allowed.triangles)
    throw LoadError(scene.source + ": the scene draws " + std::to_string(size.triangles) + " triangles, more than " +
                    std::to_string(allowed.triangles) + " (--max-triangles raises the limit)");
  if (size.morphDeltas > allowed.morphDeltas)
    throw LoadError(scene.source + ": the scene draws " + std::to_string(size.morphDeltas) +
                    " morph deltas (targets × vertices, each instance), more than " +
                    std::to_string(allowed.morphDeltas) + " (--max-morph-deltas raises the limit)");
  const Pose rest = evaluatePose(scene, -1, 0.0f);
  std::vector<uint32_t> ownerBase;
  const EdgeLimits limits = edgeLimitsOf(scene, rest, tessellation, ownerBase);
  Geometry g;
  g.nodeCount = uint32_t(scene.nodes.size());
  uint32_t matrices = g.nodeCount;
  for (const auto& skin : scene.skins) {
    g.skinJointBase.push_back(matrices);
    matrices += uint32_t(skin.joints.size());
  }
  for (const auto& t : scene.textures) appendTexture(g, t, true);
  // Data textures (metallic-roughness, normals) are stored as they are, without the sRGB curve: a copy of
  // their own where a texture is read both ways.
  std::map<int, int> linearCopies;
  auto linearTexels = [&](int texture) {
    if (texture < 0) return texture;
    auto [at, added] = linearCopies.try_emplace(texture, int(g.textures.size()));
    if (added) appendTexture(g, scene.textures[size_t(texture)], false);
    return at->second;
  };
  // A reference with a KHR_texture_transform, or on TEXCOORD_1, reads the texture's texels through a
  // record of its own.
  auto transformed = [&](int texture, const TextureTransform& transform) {
    if (texture < 0 || transform.identity()) return texture;
    gpu::Texture record = g.textures[size_t(texture)];
    record.uvRowU = glm::vec4(transform.rowU(), record.uvRowU.w);
    record.uvRowV = glm::vec4(transform.rowV(), float(transform.texCoord));
    g.textures.push_back(record);
    return int(g.textures.size() - 1);
  };
  for (const auto& m : scene.materials)
    g.materials.push_back(gpuMaterial(
        m, transformed(m.baseColorTexture, m.baseColorTransform), transformed(m.emissiveTexture, m.emissiveTransform),
        transformed(linearTexels(m.metallicRoughnessTexture), m.metallicRoughnessTransform),
        transformed(linearTexels(m.normalTexture), m.normalTransform)));
  g.materials.push_back(gpuMaterial(Material{}, -1, -1, -1, -1));  // glTF default material
  const uint32_t defaultMaterial = uint32_t(g.materials.size() - 1);
  // A MASK material whose alpha stays at or above its cutoff everywhere, or a BLEND one whose alpha
  // stays 1, takes nothing away: it is drawn as opaque, and the passes skip its test (and the depth
  // maps simplify its instances).
  for (size_t i = 0; i < scene.materials.size(); ++i)
    if (!cutsAnything(scene, i)) g.materials[i].alphaCutoff = gpu::kAlphaOpaque;

  // Whether a material's lobe sends by direction, asked until one does (the scene's answer then).
  // A metallic-roughness texture may hold any roughness down to a mirror's. Lobes alike in what
  // shapes them (a dielectric's base does not) are integrated once.
  std::map<std::array<float, 9>, bool> lobes;
  const auto sendsByDirection = [&](const gpu::Material& material, const gpu::SurfaceBrdf& brdf) {
    if (material.metallicRoughnessTexture >= 0) return true;
    const glm::vec3 metal = brdf.metallic > 0.0f ? glm::vec3(brdf.base) : glm::vec3(0.0f);
    const std::array<float, 9> key = {brdf.alpha,      brdf.metallic, brdf.specular.x, brdf.specular.y, brdf.specular.z,
                                      brdf.specular.w, metal.x,       metal.y,         metal.z};
    const auto [at, fresh] = lobes.try_emplace(key, false);
    if (fresh) at->second = sendsLobeByDirection(brdf);
    return at->second;
  };

  // Appends primitive p of node `nodeIndex` as an instance, with its triangles and surfels; returns
  // where each of p's triangles went in g.triangles (-1: degenerate, left out).
  auto appendInstance = [&](const Primitive& p, int nodeIndex) {
    const Node& node = scene.nodes[size_t(nodeIndex)];
    std::vector<int32_t> triangleOf(p.indices.size() / 3, -1);
    const uint32_t instance = uint32_t(g.instances.size());
    g.vertexColors = g.vertexColors || !p.colors.empty();
    const uint32_t base = uint32_t(g.vertices.size());
    const uint32_t n = uint32_t(p.positions.size());
    const bool skinned = node.skin >= 0 && !p.joints.empty();
    Instance inst{};
    inst.matrix = skinned ? g.skinJointBase[node.skin] : uint32_t(nodeIndex);
    inst.skinned = skinned;
    inst.morphTargets = uint32_t(p.targets.size());
    inst.morphWeightBase = g.morphWeightCount;
    inst.morphDeltaBase = uint32_t(g.morphDeltas.size());
    inst.vertexCount = n;
    g.morphWeightCount += inst.morphTargets;
    g.instances.push_back(inst);
    g.instanceNode.push_back(nodeIndex);
    for (const auto& t : p.targets)
      for (uint32_t v = 0; v < n; ++v)
        g.morphDeltas.push_back({glm::vec4(t.positions.empty() ? glm::vec3(0) : t.positions[v], 0),
                                 glm::vec4(t.normals.empty() ? glm::vec3(0) : t.normals[v], 0)});

    const uint32_t materialIndex = p.material >= 0 ? uint32_t(p.material) : defaultMaterial;
    const gpu::Material& material = g.materials[materialIndex];
    // At its texture's most glossy (a metallic-roughness texel of 1).
    const gpu::SurfaceBrdf brdf = surfaceBrdf(material, glm::vec3(material.baseColor), glm::vec4(1.0f));
    g.glossyMaterials |= !gpu::isLambertian(brdf);
    g.lobeDominatedMaterials |= gpu::lobeDominates(brdf, SpecularAlbedo::table().at(1.0f, std::sqrt(brdf.alpha)));
    if (!g.directionalLobes) g.directionalLobes = sendsByDirection(material, brdf);
    if (!g.directionalBases)
      g.directionalBases =
          (material.metallicRoughnessTexture >= 0 && !gpu::isLambertian(brdf)) || sendsBaseByDirection(brdf);
    g.normalTextures |= material.normalTexture >= 0;
    const bool cutout = gpu::alphaMatters(material.alphaCutoff);
    g.cutouts |= cutout;
    g.blended |= material.alphaCutoff == gpu::kAlphaBlended;
    for (uint32_t v = 0; v < n; ++v) {
      Vertex gv{};
      gv.position = p.positions[v];
      gv.instance = instance;
      gv.normal = p.normals.empty() ? glm::vec3(0) : p.normals[v];
      gv.local = v;
      gv.joints = skinned ? p.joints[v] : glm::uvec4(0);
      gv.weights = skinned ? p.weights[v] : glm::vec4(0);
      g.vertices.push_back(gv);
      g.uvs.push_back(glm::vec4(p.uvs.empty() ? glm::vec2(0) : p.uvs[v], p.uvs1.empty() ? glm::vec2(0) : p.uvs1[v]));
      g.colors.push_back(p.colors.empty() ? glm::vec4(1) : p.colors[v]);
    }

    // Weld vertices that differ only in UV (seams) into one surfel: same position, normal and skin.
    std::vector<uint32_t> surfelOf(n, ~0u);
    std::unordered_multimap<uint64_t, uint32_t> byPosition;  // hash -> first vertex of a surfel
    std::vector<std::vector<uint32_t>> welded;
    for (uint32_t v = 0; v < n; ++v) {
      const Vertex& gv = g.vertices[base + v];
      uint64_t h = hashPoint(gv.position);
      auto range = byPosition.equal_range(h);
      for (auto it = range.first; it != range.second && surfelOf[v] == ~0u; ++it) {
        const Vertex& o = g.vertices[base + it->second];
        bool same = o.position == gv.position &&
                    glm::all(glm::lessThan(glm::abs(o.normal - gv.normal), glm::vec3(1e-4f))) &&
                    o.joints == gv.joints && o.weights == gv.weights;
        if (same) surfelOf[v] = surfelOf[it->second];
      }
      if (surfelOf[v] == ~0u) {
        surfelOf[v] = uint32_t(welded.size());
        welded.push_back({});
        byPosition.emplace(h, v);
      }
      welded[surfelOf[v]].push_back(v);
    }

    std::vector<std::vector<uint32_t>> adjacent(welded.size());
    const size_t firstTriangle = g.triangles.size();
    // glTF: a node whose transform has a negative determinant (a mirror) turns its triangles'
    // front faces clockwise. Stored the other way round, every method sees the front the file
    // means where it takes a face's side from its corners' order (a primitive without normals,
    // an emitter's side). A skinned mesh's rest matrix is the identity: its joints place it,
    // and are not judged here.
    const bool mirrored = glm::determinant(glm::mat3(restMatrix(scene, rest, nodeIndex))) < 0.0f;
    for (size_t t = 0; t + 2 < p.indices.size(); t += 3) {
      uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
      if (a == b || b == c || a == c || degenerate(p.positions[a], p.positions[b], p.positions[c])) {
        ++g.degenerateTriangles;
        continue;
      }
      uint32_t tri = uint32_t(g.triangles.size());
      triangleOf[t / 3] = int32_t(tri);
      uint32_t mat = materialIndex | (p.normals.empty() ? gpu::kFlatShaded : 0u);
      if (mirrored) std::swap(b, c);
      g.triangles.push_back({base + a, base + b, base + c, mat});
      for (uint32_t v : {a, b, c}) adjacent[surfelOf[v]].push_back(tri);
    }
    if (g.triangles.size() > allowed.triangles)
      throw LoadError(scene.source + ": tessellated (--tessellate " + std::to_string(tessellation) +
                      "), the scene reaches more than " + std::to_string(allowed.triangles) +
                      " triangles (--max-triangles raises the limit, a lower --tessellate samples coarser)");

    // Where albedo or emission varies over the triangles, each surfel takes their hat-weighted
    // means over its triangles, weighted by the triangles' areas.
    const bool varies = material.baseColorTexture >= 0 || material.emissiveTexture >= 0 ||
                        material.metallicRoughnessTexture >= 0 || !p.colors.empty() || cutout;
    const glm::vec4 uniformAlbedo = solverAlbedo(g, material, material.baseColor, glm::vec4(0.0f));
    std::vector<glm::vec4> albedoSums(varies ? welded.size() : 0, glm::vec4(0.0f)),
        emissionSums(albedoSums.size(), glm::vec4(0.0f)), baseSums(albedoSums.size(), glm::vec4(0.0f));
    std::vector<glm::vec2> metalRoughSums(albedoSums.size(), glm::vec2(0.0f));
    std::vector<float> areaSums(albedoSums.size(), 0.0f), coverageSums(albedoSums.size(), 0.0f);
    for (size_t t = firstTriangle; varies && t < g.triangles.size(); ++t) {
      const uint32_t corner[3] = {g.triangles[t].v0 - base, g.triangles[t].v1 - base, g.triangles[t].v2 - base};
      glm::vec4 uv[3], color[3];
      for (int k = 0; k < 3; ++k)
        uv[k] = g.uvs[base + corner[k]], color[k] = p.colors.empty() ? glm::vec4(1) : p.colors[corner[k]];
      const float area = 0.5f * glm::length(glm::cross(p.positions[corner[1]] - p.positions[corner[0]],
                                                       p.positions[corner[2]] - p.positions[corner[0]]));
      const CornerMeans means = cornerMeans(g, material, uv, color);
      for (int k = 0; k < 3; ++k) {
        const uint32_t s = surfelOf[corner[k]];
        albedoSums[s] += area * means.albedo[k], emissionSums[s] += area * means.emission[k];
        baseSums[s] += area * means.base[k], metalRoughSums[s] += area * means.metallicRoughness[k];
        areaSums[s] += area, coverageSums[s] += area * means.coverage[k];
      }
    }

    for (size_t s = 0; s < welded.size(); ++s) {
      if (adjacent[s].empty()) continue;  // only on degenerate triangles, or unreferenced
      SurfelSource src{uint32_t(g.surfelVertices.size()), uint32_t(welded[s].size()),
                       uint32_t(g.surfelTriangles.size()), uint32_t(adjacent[s].size())};
      for (uint32_t v : welded[s]) g.surfelVertices.push_back(base + v);
      g.surfelTriangles.insert(g.surfelTriangles.end(), adjacent[s].begin(), adjacent[s].end());
      g.surfels.push_back(src);
      // Means over what is there. Where all of the surfel is cut away it keeps (nearly) no area:
      // black, of the material's own metal and roughness.
      const bool gone = cutout && !(coverageSums[s] > 0.0f);
      const float there = varies ? (cutout ? std::max(coverageSums[s], 1e-30f) : areaSums[s]) : 1.0f;
      g.surfelAlbedo.push_back(varies ? albedoSums[s] / there : uniformAlbedo);
      g.surfelEmission.push_back(varies ? emissionSums[s] / there : material.emission);
      const glm::vec2 metalRough = varies && !gone ? metalRoughSums[s] / there : glm::vec2(1.0f);
      g.surfelBrdf.push_back(surfaceBrdf(material, glm::vec3(varies ? baseSums[s] / there : material.baseColor),
                                         glm::vec4(0.0f, metalRough.y, metalRough.x, 0.0f)));
      g.surfelCoverage.push_back(cutout ? std::max(coverageSums[s] / areaSums[s], kLeastCoverage) : 1.0f);
    }
    return triangleOf;
  };

  // The double-sided primitives drawn, as tessellated, for their backs.
  struct DoubleSided {
    Primitive primitive;
    int node;
    std::vector<int32_t> triangleOf;
  };
  std::vector<DoubleSided> doubleSided;
  // The drawn nodes in the order they are appended (depth first).
  std::vector<int> drawnNodes;
  const std::function<void(int)> visit = [&](int nodeIndex) {
    if (scene.nodes[nodeIndex].mesh >= 0) drawnNodes.push_back(nodeIndex);
    for (int c : scene.nodes[nodeIndex].children) visit(c);
  };
  for (int r : scene.roots) visit(r);
  // Each primitive is tessellated apart from the rest, spread over the cores, a batch of nodes at a
  // time (so that the copies held at once stay few), then appended in order.
  constexpr size_t kBatch = 64;
  const auto primitivesOf = [&](int nodeIndex) -> const std::vector<Primitive>& {
    return scene.meshes[size_t(scene.nodes[size_t(nodeIndex)].mesh)].primitives;
  };
  for (size_t first = 0; first < drawnNodes.size(); first += kBatch) {
    const size_t last = std::min(first + kBatch, drawnNodes.size());
    std::vector<std::pair<int, size_t>> pieces;  // (node, primitive), in the order they are appended
    for (size_t n = first; n < last; ++n)
      for (size_t k = 0; k < primitivesOf(drawnNodes[n]).size(); ++k) pieces.emplace_back(drawnNodes[n], k);
    std::vector<Primitive> batch(pieces.size());
    parallelFor(pieces.size(), [&](size_t i) {
      const auto [nodeIndex, k] = pieces[i];
      const Primitive& given = primitivesOf(nodeIndex)[k];
      // At most eight times the vertices the primitive came with (and a few thousand more).
      batch[i] = limits.uniform() > 0.0f
                     ? tessellated(given, restMatrix(scene, rest, nodeIndex), limits,
                                   ownerBase[size_t(nodeIndex)] + uint32_t(k), 8 * given.positions.size() + 4096)
                     : given;
    });
    size_t i = 0;
    for (size_t n = first; n < last; ++n) {
      const int nodeIndex = drawnNodes[n];
      for (size_t k = 0; k < primitivesOf(nodeIndex).size(); ++k, ++i) {
        Primitive& p = batch[i];
        std::vector<int32_t> triangleOf = appendInstance(p, nodeIndex);
        if (p.material >= 0 && scene.materials[size_t(p.material)].doubleSided)
          doubleSided.push_back({std::move(p), nodeIndex, std::move(triangleOf)});
      }
      if (progress) progress(n + 1, drawnNodes.size());
    }
  }

  // The exposed backs of the double-sided primitives, after every front: the path tracer, which
  // lights both sides of every face itself, leaves them out. Their material is the front's without
  // emission (an emitter sends from its front alone, as the path tracer's do).
  std::map<int, int> backMaterials;
  const std::unique_ptr<BackExposure> exposure =
      doubleSided.empty() ? nullptr : backExposure(scene, rest, g, openSpace);
  const size_t fronts = g.triangles.size(), frontSurfels = g.surfels.size(), frontInstances = g.instances.size();
  // Each face's rays are its own: the faces are spread over the cores.
  std::vector<uint32_t> faces;
  for (const DoubleSided& d : doubleSided)
    for (int32_t t : d.triangleOf)
      if (t >= 0) faces.push_back(uint32_t(t));
  std::vector<uint8_t> seesOut(fronts, 0);
  parallelFor(faces.size(), [&](size_t k) { seesOut[faces[k]] = exposure->exposed(faces[k]); });
  for (DoubleSided& d : doubleSided) {
    std::vector<bool> copied(d.triangleOf.size());
    for (size_t t = 0; t < copied.size(); ++t) copied[t] = d.triangleOf[t] >= 0 && seesOut[size_t(d.triangleOf[t])];
    if (std::find(copied.begin(), copied.end(), true) == copied.end()) continue;
    auto [at, added] = backMaterials.try_emplace(d.primitive.material, int(g.materials.size()));
    if (added) {
      gpu::Material back = g.materials[size_t(d.primitive.material)];
      back.emission = glm::vec4(0.0f), back.emissiveTexture = -1;
      // The back's normals are the front's reversed, its normal texture's too: its reversed winding
      // keeps the tangent frame's tangent and bitangent, so their share turns sign with the scale.
      back.normalScale = -back.normalScale;
      g.materials.push_back(back);
    }
    const Primitive back = backOf(d.primitive, copied, at->second);
    for (size_t t = 0; t < copied.size(); ++t)
      if (copied[t]) g.triangles[size_t(d.triangleOf[t])].material |= gpu::kTwinned;
    for (int32_t t : appendInstance(back, d.node))
      if (t >= 0) g.triangles[size_t(t)].material |= gpu::kTwinned;
  }
  g.backTriangles = uint32_t(g.triangles.size() - fronts);
  g.backSurfels = uint32_t(g.surfels.size() - frontSurfels);
  g.backInstances = uint32_t(g.instances.size() - frontInstances);
  return g;
}

std::vector<bool> twinnedSurfels(const Geometry& g) {
  std::vector<bool> twinned(g.surfels.size(), false);
  for (size_t s = 0; s < g.surfels.size(); ++s)
    for (uint32_t k = 0; k < g.surfels[s].triangleCount && !twinned[s]; ++k)
      twinned[s] = (g.triangles[g.surfelTriangles[g.surfels[s].firstTriangle + k]].material & gpu::kTwinned) != 0u;
  return twinned;
}

FrameInputs Geometry::frameInputs(const Scene& scene, const Pose& pose) const {
  FrameInputs in;
  in.matrices = pose.world;
  for (size_t s = 0; s < scene.skins.size(); ++s)
    for (size_t j = 0; j < scene.skins[s].joints.size(); ++j)
      in.matrices.push_back(pose.world[scene.skins[s].joints[j]] * scene.skins[s].inverseBind[j]);
  in.morphWeights.assign(morphWeightCount, 0.0f);
  for (size_t i = 0; i < instances.size(); ++i) {
    const auto& w = pose.weights[instanceNode[i]];
    for (uint32_t k = 0; k < instances[i].morphTargets && k < w.size(); ++k)
      in.morphWeights[instances[i].morphWeightBase + k] = w[k];
  }
  return in;
}

std::vector<WorldVertex> animateOnHost(const Geometry& g, const FrameInputs& in) {
  std::vector<WorldVertex> out(g.vertices.size());
  for (size_t i = 0; i < g.vertices.size(); ++i) {
    const Vertex& v = g.vertices[i];
    const Instance& inst = g.instances[v.instance];
    glm::vec3 p = v.position, n = v.normal;
    for (uint32_t k = 0; k < inst.morphTargets; ++k) {
      float w = in.morphWeights[inst.morphWeightBase + k];
      const MorphDelta& d = g.morphDeltas[inst.morphDeltaBase + k * inst.vertexCount + v.local];
      p += w * glm::vec3(d.position), n += w * glm::vec3(d.normal);
    }
    glm::mat4 m = inst.skinned ? v.weights.x * in.matrices[inst.matrix + v.joints.x] +
                                     v.weights.y * in.matrices[inst.matrix + v.joints.y] +
                                     v.weights.z * in.matrices[inst.matrix + v.joints.z] +
                                     v.weights.w * in.matrices[inst.matrix + v.joints.w]
                               : in.matrices[inst.matrix];
    out[i].position = glm::vec4(glm::vec3(m * glm::vec4(p, 1.0f)), 1.0f);
    out[i].normal = glm::vec4(transformNormal(m, n), 0.0f);
  }
  return out;
}

std::vector<Surfel> surfelsOnHost(const Geometry& g, const std::vector<WorldVertex>& world) {
  std::vector<Surfel> out(g.surfels.size());
  for (size_t s = 0; s < g.surfels.size(); ++s) {
    const SurfelSource& src = g.surfels[s];
    float area = 0.0f;
    glm::vec3 faceSum(0.0f), vertexSum(0.0f), moment(0.0f);
    const glm::vec3 self(world[g.surfelVertices[src.firstVertex]].position);
    for (uint32_t k = 0; k < src.triangleCount; ++k) {
      const Triangle& t = g.triangles[g.surfelTriangles[src.firstTriangle + k]];
      glm::vec3 a(world[t.v0].position), b(world[t.v1].position), c(world[t.v2].position);
      glm::vec3 n = glm::cross(b - a, c - a);
      float third = glm::length(n) / 6.0f;  // a third of the triangle's area
      area += third;
      faceSum += n;
      moment += third * (22.0f * self + 7.0f * (a + b + c - self)) / 36.0f;  // centroid of the vertex's corner quad
    }
    for (uint32_t k = 0; k < src.vertexCount; ++k)
      vertexSum += glm::vec3(world[g.surfelVertices[src.firstVertex + k]].normal);
    glm::vec3 n = glm::length(vertexSum) > 1e-6f ? vertexSum : faceSum;
    float len = glm::length(n);
    glm::vec3 centre = area > 0.0f ? moment / area : self, normal = len > 0.0f ? n / len : glm::vec3(0.0f);
    glm::vec3 t1, t2;
    gpu::tangentFrame(len > 0.0f ? normal : glm::vec3(0, 0, 1), t1, t2);
    glm::vec2 quarter(0.0f);  // its axes along the mesh's edges (surfels.comp)
    for (uint32_t k = 0; k < src.triangleCount; ++k) {
      const Triangle& t = g.triangles[g.surfelTriangles[src.firstTriangle + k]];
      quarter += gpu::edgeQuarterTurns(glm::vec3(world[t.v0].position), glm::vec3(world[t.v1].position),
                                       glm::vec3(world[t.v2].position), t1, t2);
    }
    const float angle = gpu::quarterAngle(quarter);
    glm::vec3 u1, u2;
    gpu::rectangleAxes(len > 0.0f ? normal : glm::vec3(0, 0, 1), angle, u1, u2);
    glm::vec4 reach(0.0f);  // +u1, -u1, +u2, -u2 (surfels.comp)
    for (uint32_t k = 0; k < src.triangleCount; ++k) {
      const Triangle& t = g.triangles[g.surfelTriangles[src.firstTriangle + k]];
      for (uint32_t v : {t.v0, t.v1, t.v2}) {
        glm::vec3 e = glm::vec3(world[v].position) - self;
        float a = glm::dot(e, u1), b = glm::dot(e, u2);
        reach = glm::max(reach, glm::vec4(a, -a, b, -b));
      }
    }
    glm::vec2 extent = 0.25f * (glm::vec2(reach.x, reach.z) + glm::vec2(reach.y, reach.w));
    extent = extent.x * extent.y > 0.0f ? extent * std::sqrt(area / (4.0f * extent.x * extent.y))
                                        : glm::vec2(0.5f * std::sqrt(area));
    out[s].positionArea = glm::vec4(centre, len > 0.0f ? area : 0.0f);
    out[s].normal = glm::vec4(normal, 0.0f);
    out[s].shape = glm::vec4(std::sqrt(area / glm::pi<float>()), angle, extent);
  }
  return out;
}

std::vector<int32_t> vertexSurfels(const Geometry& g) {
  std::vector<int32_t> out(g.vertices.size(), -1);
  for (size_t s = 0; s < g.surfels.size(); ++s)
    for (uint32_t k = 0; k < g.surfels[s].vertexCount; ++k)
      out[g.surfelVertices[g.surfels[s].firstVertex + k]] = int32_t(s);
  return out;
}

Bounds worldBounds(const std::vector<WorldVertex>& world) {
  Bounds b;
  for (const auto& v : world) b.add(glm::vec3(v.position));
  return b;
}

std::vector<bool> movingInstances(const Scene& scene, const Geometry& g, int animation) {
  std::vector<bool> moves(g.instances.size(), false);
  if (animation < 0) return moves;
  std::vector<char> transformed(scene.nodes.size(), 0), reweighted(scene.nodes.size(), 0);
  for (const Channel& ch : scene.animations[animation].channels)
    (ch.path == Path::Weights ? reweighted : transformed)[ch.node] = 1;
  // A node moves when it or any ancestor is transformed.
  std::function<bool(int)> moved = [&](int n) {
    return transformed[n] || (scene.nodes[n].parent >= 0 && moved(scene.nodes[n].parent));
  };
  const bool anything = animationMovesGeometry(scene, animation);
  for (size_t i = 0; i < g.instances.size(); ++i) {
    const Instance& inst = g.instances[i];
    moves[i] =
        inst.skinned ? anything : moved(g.instanceNode[i]) || (inst.morphTargets > 0 && reweighted[g.instanceNode[i]]);
  }
  return moves;
}

std::vector<bool> rigidlyMovingInstances(const Scene& scene, const Geometry& g, int animation) {
  std::vector<bool> rigid = movingInstances(scene, g, animation);
  if (animation < 0) return rigid;
  std::vector<char> reweighted(scene.nodes.size(), 0);
  for (const Channel& ch : scene.animations[animation].channels)
    if (ch.path == Path::Weights) reweighted[ch.node] = 1;
  for (size_t i = 0; i < g.instances.size(); ++i)
    rigid[i] =
        rigid[i] && !g.instances[i].skinned && !(g.instances[i].morphTargets > 0 && reweighted[g.instanceNode[i]]);
  if (std::find(rigid.begin(), rigid.end(), true) == rigid.end()) return rigid;  // no pose to sample
  std::vector<float> times;
  for (const Channel& ch : scene.animations[animation].channels) {
    const std::vector<float>& keys = scene.animations[animation].samplers[ch.sampler].input;
    for (size_t k = 0; k < keys.size(); ++k) {
      times.push_back(keys[k]);
      if (k + 1 < keys.size()) times.push_back(0.5f * (keys[k] + keys[k + 1]));
    }
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  const auto metric = [](const glm::mat4& m) {
    const glm::mat3 l(m);
    return glm::transpose(l) * l;
  };
  const Pose rest = evaluatePose(scene, -1, 0.0f);
  std::vector<Pose> poses;
  for (float t : times) poses.push_back(evaluatePose(scene, animation, t));
  for (size_t i = 0; i < g.instances.size(); ++i) {
    if (!rigid[i]) continue;
    const int node = g.instanceNode[i];
    const glm::mat3 m0 = metric(rest.world[node]);
    float scale = 0.0f;
    for (int c = 0; c < 3; ++c) scale = std::max(scale, std::abs(m0[c][c]));
    for (const Pose& pose : poses) {
      const glm::mat3 m = metric(pose.world[node]);
      for (int c = 0; c < 3 && rigid[i]; ++c)
        for (int r = 0; r < 3; ++r)
          if (!(std::abs(m[c][r] - m0[c][r]) <= 1e-4f * scale)) rigid[i] = false;
    }
  }
  return rigid;
}

TriangleRays::CutAway cutAwayOf(const Geometry& g) {
  if (!g.cutouts) return {};
  return [&g](uint32_t tri, glm::vec2 uv, float sample) {
    return gpu::cutAway(presenceAt(g, g.triangles[tri], glm::vec3(1.0f - uv.x - uv.y, uv.x, uv.y)), sample);
  };
}

std::vector<bool> closedInstances(const Geometry& g) {
  // Vertices welded by their exact rest position.
  struct PositionHash {
    size_t operator()(const glm::vec3& p) const {
      uint32_t bits[3];
      std::memcpy(bits, &p, sizeof(bits));
      return (size_t(bits[0]) * 73856093u) ^ (size_t(bits[1]) * 19349663u) ^ (size_t(bits[2]) * 83492791u);
    }
  };
  std::unordered_map<glm::vec3, uint32_t, PositionHash> welded;
  std::vector<uint32_t> weld(g.vertices.size());
  std::vector<glm::vec3> positions;
  for (size_t v = 0; v < g.vertices.size(); ++v) {
    const glm::vec3 p = g.vertices[v].position + glm::vec3(0.0f);  // −0 as +0
    auto [at, added] = welded.try_emplace(p, uint32_t(positions.size()));
    if (added) positions.push_back(p);
    weld[v] = at->second;
  }
  // Per instance and edge (a < b): how often it is crossed from a to b, less from b to a; and the
  // instance's area.
  std::vector<std::unordered_map<uint64_t, int>> balance(g.instances.size());
  std::vector<double> area(g.instances.size(), 0.0);
  for (const Triangle& t : g.triangles) {
    const uint32_t w[3] = {weld[t.v0], weld[t.v1], weld[t.v2]};
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;
    const uint32_t instance = g.vertices[t.v0].instance;
    area[instance] +=
        0.5 * glm::length(glm::cross(positions[w[1]] - positions[w[0]], positions[w[2]] - positions[w[0]]));
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = w[e], b = w[(e + 1) % 3];
      balance[instance][uint64_t(std::min(a, b)) << 32 | std::max(a, b)] += a < b ? 1 : -1;
    }
  }
  // The edges left unbalanced bound holes. Where one side's edge meets several on the other (a
  // T-junction of a tessellation, a crack between a CAD export's faces meshed apart), the loop they
  // form encloses next to no area; a hole encloses its own. So: closed where the vector areas of the
  // unbalanced edges' connected pieces add up to a negligible part of the instance's area.
  std::vector<uint32_t> parent(positions.size());
  auto find = [&](uint32_t v) {  // the root of v's piece, halving the path on the way
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<bool> closed(g.instances.size(), false);
  for (size_t i = 0; i < balance.size(); ++i) {
    if (balance[i].empty()) continue;
    for (const auto& [edge, count] : balance[i])
      if (count != 0) parent[uint32_t(edge >> 32)] = uint32_t(edge >> 32), parent[uint32_t(edge)] = uint32_t(edge);
    for (const auto& [edge, count] : balance[i])
      if (count != 0) parent[find(uint32_t(edge >> 32))] = find(uint32_t(edge));
    std::unordered_map<uint32_t, glm::dvec3> holes;  // by piece: its vector area about its root vertex
    for (const auto& [edge, count] : balance[i]) {
      if (count == 0) continue;
      const uint32_t root = find(uint32_t(edge));
      const glm::dvec3 o(positions[root]), a = glm::dvec3(positions[uint32_t(edge >> 32)]) - o,
                                           b = glm::dvec3(positions[uint32_t(edge)]) - o;
      holes[root] += 0.5 * double(count) * glm::cross(a, b);
    }
    double holeArea = 0.0;
    for (const auto& [root, vectorArea] : holes) holeArea += glm::length(vectorArea);
    closed[i] = holeArea <= 1e-3 * area[i];
  }
  return closed;
}

glm::vec3 emissionAt(const Geometry& g, const Triangle& t, float b, float c) {
  const gpu::Material& m = g.materials[t.material & ~gpu::kTriangleFlags];
  if (m.emission == glm::vec4(0.0f)) return glm::vec3(0.0f);
  const glm::vec4 uv = (1.0f - b - c) * g.uvs[t.v0] + b * g.uvs[t.v1] + c * g.uvs[t.v2];
  // What is not there emits nothing: a blended emitter its alpha's share.
  return glm::vec3(m.emission * sampleTexture(g, m.emissiveTexture, uv)) *
         presenceAt(g, t, glm::vec3(1.0f - b - c, b, c));
}

std::vector<EmissionCell> emissionCells(const Geometry& g, const Triangle& t) {
  const gpu::Material& m = g.materials[t.material & ~gpu::kTriangleFlags];
  if (m.emission == glm::vec4(0.0f)) return {};
  if (m.emissiveTexture < 0) return {{{glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1)}, glm::vec3(m.emission)}};
  const glm::vec4 uv[3] = {g.uvs[t.v0], g.uvs[t.v1], g.uvs[t.v2]};
  const int n = samplesAcross(g, m, uv);
  std::vector<EmissionCell> cells;
  cells.reserve(size_t(n * n));
  subTriangleCentroids(n, [&](glm::vec3 w, float turn) {
    // The corner at the right angle lies a third of a step back from the centroid along both legs.
    const glm::vec2 centroid(w.y, w.z);
    const float step = turn / float(n);
    const glm::vec2 origin = centroid - glm::vec2(step / 3.0f);
    EmissionCell cell{{origin, origin + glm::vec2(step, 0.0f), origin + glm::vec2(0.0f, step)}, glm::vec3(0.0f)};
    for (glm::vec2 at : {centroid, cell.corners[0], cell.corners[1], cell.corners[2]})
      cell.emission += 0.25f * emissionAt(g, t, at.x, at.y);
    cells.push_back(cell);
  });
  return cells;
}

}  // namespace ivgi::scene

// The scene as the passes read it: its data (engine/scene/geometry.h builds it), the camera and
// its rays, textures, punctual lights, the surfel hierarchy; the frame's own passes' push
// constants.
// Part of shaders/interface.h, which includes it inside its namespace and language macros.
// ---- Scene data (engine/scene/geometry.h builds it; animate, surfels, raster and resolve read it) ----

struct Vertex {
  vec3 position;  // rest pose, primitive space
  uint instance;
  vec3 normal;
  uint local;  // index inside its primitive, for morph deltas
  uvec4 joints;
  vec4 weights;
};
struct Instance {
  uint matrix;  // node world matrix, or first joint matrix when skinned
  uint skinned;
  uint morphTargets;
  uint morphWeightBase;
  uint morphDeltaBase;  // deltas of target k, vertex v at morphDeltaBase + k * vertexCount + v
  uint vertexCount;
  uint pad0;
  uint pad1;
};
struct MorphDelta {
  vec4 position;
  vec4 normal;
};
struct Triangle {
  uint v0;
  uint v1;
  uint v2;
  uint material;  // material index | kFlatShaded when the primitive has no normals | kTwinned
};
IVGI_CONST uint kFlatShaded = 0x80000000u;
// A face of an open double-sided surface whose back has faces of its own (scene/back_faces.h), or
// such a back face: the camera sees each from its front alone.
IVGI_CONST uint kTwinned = 0x40000000u;
IVGI_CONST uint kTriangleFlags = kFlatShaded | kTwinned;
// Triangle a b c's front, not normalised: its corners' counter-clockwise normal, turned to the side
// its vertex normals face (`normals`, their sum) unless it is flat shaded. An emitter sends its light
// there, and a twinned face is seen from there alone.
IVGI_FN vec3 faceFront(vec3 a, vec3 b, vec3 c, vec3 normals, bool flatShaded) {
  const vec3 n = cross(b - a, c - a);
  return !flatShaded && dot(n, normals) < 0.0f ? -n : n;
}
// glTF's metallic-roughness material (interface/brdf.h evaluates it); read by the passes as
// kMaterialTexels RGBA32 texels.
struct Material {
  vec4 baseColor;
  vec4 emission;  // rgb: emissive factor × strength (radiance)
  // rgb: the dielectric's reflectance at normal incidence (0.04, or KHR_materials_ior's, times
  // KHR_materials_specular's colour and factor); a: at grazing incidence (the specular factor).
  vec4 specular;
  int baseColorTexture;
  int emissiveTexture;
  int metallicRoughnessTexture;  // linear texels: G roughness, B metallic
  int normalTexture;             // linear texels: the tangent-space normal (mappedNormal)
  float metallic;
  float roughness;    // perceptual: the distribution's α is its square
  float normalScale;  // normalTexture's scale
  float alphaCutoff;  // alphaMode MASK's cutoff (0 or more); kAlphaOpaque; kAlphaBlended (BLEND)
};
IVGI_CONST float kAlphaOpaque = -1.0f;
IVGI_CONST float kAlphaBlended = -2.0f;
// Whether a material's `alphaCutoff` lets its alpha take away any of the surface.
IVGI_FN bool alphaMatters(float alphaCutoff) { return alphaCutoff != kAlphaOpaque; }
// How much of the surface is there where its base colour's alpha (factor × texture × COLOR_0) is
// `alpha`: MASK keeps all of it at the cutoff or above and none below; BLEND keeps alpha of it.
IVGI_FN float presenceOf(float alpha, float alphaCutoff) {
  if (alphaCutoff == kAlphaBlended) return clamp(alpha, 0.0f, 1.0f);
  return alphaCutoff < 0.0f || alpha >= alphaCutoff ? 1.0f : 0.0f;
}
// Whether a point of that presence is cut away for a sample whose uniform number in [0, 1) is u: a
// blended surface is there for a share `presence` of the samples (stochastic transparency), a
// masked one for all or none.
IVGI_FN bool cutAway(float presence, float u) { return presence <= u; }
// A uniform number in [0, 1) from two words (Jarzynski and Olano's PCG hash, twice): the samples of
// stochastic transparency, the same for the same sample and triangle on every run.
IVGI_FN uint pcgHash(uint v) {
  const uint state = v * 747796405u + 2891336453u;
  const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
IVGI_FN float unitHash(uint a, uint b) { return float(pcgHash(a ^ pcgHash(b)) >> 8u) * (1.0f / 16777216.0f); }
IVGI_CONST uint kMaterialTexels = 5u;
struct Texture {
  uint offset;  // in texels; each texel is linear RGBA as two packHalf2x16 words
  uint width;
  uint height;
  uint wrap;  // wrapS | wrapT << 16 (glTF enums)
  // KHR_texture_transform as an affine map of (u, v, 1): u' = dot(uvRowU.xyz, …), v' likewise.
  // A texture referenced with another transform or coordinate set is another record over the same
  // texels. uvRowU.w: 1 where the sampler asks for the nearest texel (magFilter NEAREST), 0 for a
  // bilinear blend; uvRowV.w: the set it reads, 0 (TEXCOORD_0) or 1 (TEXCOORD_1).
  vec4 uvRowU;
  vec4 uvRowV;
};
struct SurfelSource {
  uint firstVertex;  // welded vertices, in Geometry::surfelVertices
  uint vertexCount;
  uint firstTriangle;  // adjacent non-degenerate triangles, in Geometry::surfelTriangles
  uint triangleCount;
};
struct WorldVertex {  // the animate pass's output
  vec4 position;
  vec4 normal;
};
struct Surfel {       // the surfel pass's output
  vec4 positionArea;  // centroid of the surfel's area, area
  vec4 normal;
  vec4 shape;  // as NodeState's: x the radius of a disk of its area, y the angle (0), zw half-extents
};

// Pinhole camera: right and up scaled by tan of the half field of view; origin.w = znear,
// forward.w = zfar (0: none). Image size in samples, pixel (0,0) top-left, centres at +0.5.
struct Camera {
  vec4 origin;
  vec4 right;
  vec4 up;
  vec4 forward;
};

// KHR_lights_punctual, in world space for the frame (engine/scene/lights.h).
struct PunctualLight {
  vec4 position;   // w: 0 directional, 1 point, 2 spot
  vec4 direction;  // where the light points; w: range (0: none)
  vec4 intensity;  // rgb: colour × intensity, radiometric
  vec4 cone;       // cos outer, cos inner
};
IVGI_CONST float kLightDirectional = 0.0f;
IVGI_CONST float kLightPoint = 1.0f;
IVGI_CONST float kLightSpot = 2.0f;

// ---- The surfel hierarchy (engine/gi/hierarchy.h) ----

struct TreeNode {
  int parent;       // -1 for a root
  uint firstChild;  // children are contiguous in the next level
  uint childCount;  // 0 for a leaf
  int surfel;       // the leaf's surfel, -1 for an inner node
};
// Per frame: area-weighted position and total area; normal and the half-angle of the cone holding
// every normal below; shape: x the radius of a sphere around the position holding every surfel
// disk below, y the angle of the node's rectangle in tangentFrame(normal), zw its half-extents.
struct NodeState {
  vec4 positionArea;
  vec4 normalCone;
  vec4 shape;
};

// Surfels inside another object (buried_surfels, engine/gi/refit.h): a surfel is inside where that
// object's winding number reaches kBurialWinding. A node counts as a dipole where it lies farther
// than kBurialFar of its radii; a surfel's walk of one object stops after kBurialVisits nodes (it
// then counts as outside that object).
IVGI_CONST float kBurialWinding = 0.25f;
// A surfel inside another part of its own object (an eyeball sunk into a head, a bolt merged into
// its block): its own closed surface winds ½ around it, another closed part of the object one more.
// The threshold lies midway: the surfels' rectangles, tiling a coarse curved surface, move the own
// surface's ½ by up to about ½. A face resting on another part (1) is not told apart.
IVGI_CONST float kSelfBurialWinding = 1.0f;
IVGI_CONST float kBurialFar = 1.5f;
IVGI_CONST uint kBurialVisits = 4096u;
// Per root, bits of SceneBuffers::rootFlags: its surface may hold other objects' surfels
// (Hierarchy::rootEncloses); its object stays still over the frames rendered (what it buries stays
// buried while links made once stand); its object moves rigidly, keeping its shape, and what it buries
// of itself is found at its rest pose and kept (Refit::recordRestBurial).
IVGI_CONST uint kRootEncloses = 1u;
IVGI_CONST uint kRootStill = 2u;
IVGI_CONST uint kRootRigid = 4u;
// Per surfel, bits of SceneBuffers::surfelBuried (readers test for any): it lies inside another object
// or another part of its own; the latter alone, found at the rest pose and kept by an object that
// moves rigidly.
IVGI_CONST uint kBuried = 1u;
IVGI_CONST uint kBuriedInItself = 2u;
struct BurialPush {
  uint surfelCount;
  uint rootCount;  // the trees' roots, nodes 0 to rootCount − 1
  // 1 where a pass before found which surfels of still objects lie inside still objects
  // (nodeStillBuried, kept; nodeBuried starts from it): only what moves is tested again.
  uint stillKnown;
  // 1: the items are the surfels of the leaves in movingLeaves, surfelCount of them (no object
  // that moves encloses a volume, so the still surfels' burial stands from the pass before).
  uint listed;
  // 1 where a pass at the rest pose found which surfels of objects that move rigidly lie inside
  // another part of their own (kBuriedInItself, kept).
  uint shapesKnown;
  // 1: that pass (Refit::recordRestBurial), the surfels at rest.
  uint atRest;
};

// ---- Camera rays ----

// A camera whose up.w is kOrthographic looks along forward from the plane through its origin (a
// glTF orthographic camera, a directional light's depth map): the ray of a sample starts at
// origin + ndc.x·right + ndc.y·up, right and up being the view's half-extents. Else every ray
// starts at the origin.
IVGI_CONST float kOrthographic = 1.0f;

IVGI_FN vec3 cameraRay(Camera cam, vec2 samplePos, uvec2 size) {
  if (cam.up.w == kOrthographic) return vec3(cam.forward);
  vec2 ndc = vec2(2.0f * samplePos.x / float(size.x) - 1.0f, 1.0f - 2.0f * samplePos.y / float(size.y));
  return vec3(cam.forward) + ndc.x * vec3(cam.right) + ndc.y * vec3(cam.up);
}
IVGI_FN vec3 cameraRayOrigin(Camera cam, vec2 samplePos, uvec2 size) {
  if (cam.up.w != kOrthographic) return vec3(cam.origin);
  vec2 ndc = vec2(2.0f * samplePos.x / float(size.x) - 1.0f, 1.0f - 2.0f * samplePos.y / float(size.y));
  return vec3(cam.origin) + ndc.x * vec3(cam.right) + ndc.y * vec3(cam.up);
}

// The eye in homogeneous coordinates: a perspective camera's origin (w 1), or the direction toward
// an orthographic one (−forward, w 0), so that towardEye() points from a surface to it either way.
IVGI_FN vec4 cameraEye(Camera cam) {
  return cam.up.w == kOrthographic ? vec4(-vec3(cam.forward), 0.0f) : vec4(vec3(cam.origin), 1.0f);
}
IVGI_FN vec3 towardEye(vec4 eye, vec3 p) { return vec3(eye) - eye.w * p; }  // not normalised

// ---- Textures ----

// The texture coordinates a lookup of texture t reads at a point whose two sets are `uvs`
// (TEXCOORD_0 in xy, TEXCOORD_1 in zw): its set's, with its KHR_texture_transform applied.
IVGI_FN vec2 transformedUv(Texture t, vec4 uvs) {
  vec3 h = t.uvRowV.w != 0.0f ? vec3(uvs.z, uvs.w, 1.0f) : vec3(uvs.x, uvs.y, 1.0f);
  return vec2(dot(vec3(t.uvRowU.x, t.uvRowU.y, t.uvRowU.z), h), dot(vec3(t.uvRowV.x, t.uvRowV.y, t.uvRowV.z), h));
}

// The two texels and the weight of the second along one axis of a bilinear lookup under a glTF wrap
// mode (33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT, else REPEAT). No integer division: lavapipe
// runs it one lane at a time.
IVGI_FN ivec2 texelPair(float u, int size, uint mode, IVGI_OUT(float) weight) {
  // A coordinate beyond float's range (huge UVs interpolated, a transform scaling them past it) has
  // no texel: it reads as 0, not as an index out of the texture.
  if (!(abs(u) < 1e30f)) u = 0.0f;
  if (mode == 33648u) {
    float t = fract(u * 0.5f) * 2.0f;
    u = t < 1.0f ? t : 2.0f - t;
  } else if (mode != 33071u) {
    u = fract(u);
  } else {
    u = clamp(u, 0.0f, 1.0f);  // the same texels, and no integer overflow far outside
  }
  float x = u * float(size) - 0.5f, f = floor(x);
  weight = x - f;
  int i = int(f), j = i + 1;
  if (mode == 33071u || mode == 33648u) return clamp(ivec2(i, j), 0, size - 1);
  return ivec2(i < 0 ? i + size : i, j >= size ? j - size : j);
}

// The shading normal a normal texture's texel (rgb, linear, in [0, 1]) gives at a point of triangle
// a b c whose unit normal is n, where the corners' coordinates in that texture (transformed) are
// uvA, uvB and uvC, at glTF's normalTexture `scale`. The tangent frame is the triangle's own, as
// glTF viewers derive it where a file gives no tangents: the tangent along increasing u, the
// bitangent n × tangent, turned to decreasing v (glTF's v runs down the image and a texel's green up)
// where the mapping is mirrored. n where the triangle spans no area of the texture, or where the
// result would not be finite.
IVGI_FN vec3 mappedNormal(vec3 n, vec3 a, vec3 b, vec3 c, vec2 uvA, vec2 uvB, vec2 uvC, vec3 texel, float scale) {
  const vec3 e1 = b - a, e2 = c - a;
  const vec2 d1 = uvB - uvA, d2 = uvC - uvA;
  const float det = d1.x * d2.y - d1.y * d2.x;
  if (!(abs(det) > 0.0f)) return n;
  const vec3 alongU = (e1 * d2.y - e2 * d1.y) / det, alongV = (e2 * d1.x - e1 * d2.x) / det;
  vec3 t = alongU - n * dot(n, alongU);
  const float tLength = length(t);
  if (!(tLength > 0.0f) || !(tLength < 3.4e38f)) return n;
  t = t / tLength;
  vec3 bitangent = cross(n, t);
  if (dot(bitangent, alongV) > 0.0f) bitangent = -bitangent;
  const vec3 m = texel * 2.0f - 1.0f;
  const vec3 turned = t * (m.x * scale) + bitangent * (m.y * scale) + n * m.z;
  const float turnedLength = length(turned);
  return turnedLength > 0.0f && turnedLength < 3.4e38f ? turned / turnedLength : n;
}

// The shading normal n (unit) as shading takes it at a point whose surface faces the eye with unit
// normal ng (ng·toEye ≥ 0): where the view's mirror image about n would fall below, or barely above,
// the surface's plane, n turned toward ng within their common plane just far enough that the
// mirror image rises to t = min(0.9·(ng·toEye), 0.01) above it. Cycles treats bumped and
// interpolated normals so (its ensure_valid_reflection), and a glTF surface compared against it
// then keeps a reflection where a normal texture slopes away from the eye. n where its mirror image
// is high enough; ng where no turn in that plane lifts it (n parallel to ng).
IVGI_FN vec3 liftedShadingNormal(vec3 ng, vec3 toEye, vec3 n) {
  const float iz = dot(toEye, ng), t = min(0.9f * iz, 0.01f);
  if (dot(ng, n * (2.0f * dot(n, toEye)) - toEye) >= t) return n;
  const vec3 across = n - ng * dot(n, ng);
  const float acrossLength = length(across);
  if (!(acrossLength > 0.0f)) return ng;
  const vec3 x = across / acrossLength;
  // n' = x·√(1 − c) + ng·√c, whose mirror image's height 2(n'·toEye)√c − iz is t where
  // 4a·c² − 4(a + iz·t)·c + (iz + t)² = 0, a = ix² + iz² (the mirror condition squared: of its two
  // roots the one that holds it, nearest n).
  const float ix = dot(toEye, x), a = ix * ix + iz * iz;
  if (!(a > 0.0f)) return ng;
  const float mid = (a + iz * t) / (2.0f * a), spread = abs(ix) * sqrt(max(a - t * t, 0.0f)) / (2.0f * a);
  vec3 lifted = ng;
  float nearest = -2.0f;
  for (int k = 0; k < 2; ++k) {
    const float c = k == 0 ? mid + spread : mid - spread;
    if (!(c > 1e-5f && c <= 1.0f + 1e-5f)) continue;
    const float z = sqrt(min(c, 1.0f)), along = sqrt(max(1.0f - c, 0.0f));
    if (2.0f * (along * ix + z * iz) * z - iz < t - 1e-4f) continue;  // the root squaring brought in
    const vec3 candidate = x * along + ng * z;
    if (dot(candidate, n) > nearest) nearest = dot(candidate, n), lifted = candidate;
  }
  return lifted;
}

// texelPair's weight as texture t blends: as it is (bilinear), or where t takes the nearest texel,
// all on whichever of the two has its centre nearer (the second at a tie, as floor(u·size) picks).
IVGI_FN float texelWeight(Texture t, float weight) {
  return t.uvRowU.w == 0.0f ? weight : (weight >= 0.5f ? 1.0f : 0.0f);
}

// ---- Punctual lights ----

// Irradiance per unit intensity on a surface at p facing the light: 1/d², the range window and the
// spot cone as KHR_lights_punctual's reference code gives them: 1 − (d/range)⁴ (clamped to [0, 1]),
// and t² where t goes from 0 at the outer cone's cosine to 1 at the inner's (the steep decline
// after the inner cone, levelling off toward the outer, that the extension asks conforming
// renderers to follow). The reference code's guard on the cosines' difference, 0.001, is 10⁻⁶
// here, so that a cone narrower than 2.6° still lights. toLight is not normalised; dist2 is its
// squared length, 3.4e38 for a directional light.
IVGI_FN float lightFalloff(PunctualLight light, vec3 p, IVGI_OUT(vec3) toLight, IVGI_OUT(float) dist2) {
  dist2 = 3.4e38f;
  if (light.position.w == kLightDirectional) {
    toLight = -vec3(light.direction);
    return 1.0f;
  }
  toLight = vec3(light.position) - p;
  dist2 = dot(toLight, toLight);
  if (dist2 <= 0.0f) return 0.0f;
  float falloff = 1.0f / dist2;
  if (light.direction.w > 0.0f) {
    const float r2 = dist2 / (light.direction.w * light.direction.w);
    falloff *= clamp(1.0f - r2 * r2, 0.0f, 1.0f);
  }
  if (light.position.w == kLightSpot) {
    float c = dot(normalize(-toLight), vec3(light.direction));
    float t = clamp((c - light.cone.x) / max(light.cone.y - light.cone.x, 1e-6f), 0.0f, 1.0f);
    falloff *= t * t;
  }
  return falloff;
}

// ---- Direct light from depth maps (engine/gi/direct_light.h) ----

// A point chosen on an emissive triangle by power: the triangle, the barycentric weights of its
// corners b and c, 1 / (samples × the triangle's probability), which times the triangle's area in
// the frame is the area the point stands for, and the emission there (the texture's, rgb).
struct EmitterSample {
  uint triangle;
  float b;
  float c;
  float weightPerArea;
  vec4 radiance;
};
// A point the depth maps are drawn around, in the frame (light_views): an emitter sample (where it
// is and the area it stands for, the emitter's front, its radiance) or a punctual light (the
// PunctualLight's position, direction and range, intensity, and cone with its kind in cone.z; a
// directional light's one map is orthographic over the scene's bounds, kOrthographic).
struct LightPoint {
  vec4 positionArea;
  vec4 normal;
  vec4 radiance;  // w: the first of its views in the raster's target (uint bits)
  vec4 cone;      // w: kLightPointIsPunctual for a punctual light or an environment direction, else 0
};
IVGI_CONST float kLightPointIsPunctual = 1.0f;
// Each sample's and point light's depth maps are the faces of a cube of 90° views around it, face =
// 2·axis + (negative ? 1 : 0) as the bins'; an environment direction has one orthographic view.
IVGI_CONST uint kCubeFaces = 6u;

// ---- Push constants of the frame's passes ----

struct RasterPush {  // drawn_bounds, drawn_views, raster_slices, raster
  uvec2 size;        // a view's image in samples
  uint triangleCount;
  uint viewCount;  // the views drawn, from `firstView` on (the target's other views are left as they are)
  uint firstView;
  uint cull;  // 1: drawn_views lists only the views that the triangles' box reaches
};
struct ResolvePush {  // resolve
  Camera camera;
  uvec2 size;           // the image in pixels
  uint samples;         // per pixel and axis
  uint lightSamples;    // with kDirectPixels: the emitter samples (DirectLightPush::sampleCount)
  uint shadowMap;       // and their depth maps' side
  uint punctualLights;  // the punctual lights after them
  uint pad1;
  uint pad2;
};
// Per surfel, what the frame's image reads of its reflections (mark_shown, mark_fit, iv's
// mark_taps), so that the reflections are computed there alone: bits of a uint.
IVGI_CONST uint kShownVertex = 1u;  // at a vertex of a triangle some sample of the image hits
IVGI_CONST uint kShownFit = 2u;     // read by such a vertex's fit (vertex_irradiance), itself included
IVGI_CONST uint kShownTap = 4u;     // iv: a receiver whose reflection a kShownFit surfel interpolates

struct LobePush {  // reflect_receivers, reflect_surfels, mark_taps, ar_reflect
  vec4 eye;        // cameraEye(): toward it from p is towardEye(eye, p)
  uint surfelCount;
  uint maskWords;     // iv: of a static leaf's override mask
  float leastSpread;  // the least spread (brdf.h's widenedLobe) the method's directions resolve
  uint pad;
};
// --direct pixels: the pixels of each block of b × b take the emitter samples interleaved (pixel k
// of the block the samples k, k + b², …), and each sample of the image takes its share of the light
// seen from its neighbours on its surface within b/2 pixels (resolve.comp). b is kShadowBlock at one
// sample a pixel, less as a pixel's samples grow (shadowBlock): the window's blur stays within
// about a pixel's samples.
IVGI_CONST uint kShadowBlock = 4u;
IVGI_FN uint shadowBlock(uint samplesPerAxis) {
  return samplesPerAxis >= kShadowBlock ? 1u : kShadowBlock / samplesPerAxis;
}
// A neighbour's light counts for a sample where its normal is within this cosine of the sample's
// and the sample lies within kShadowPlanePixels pixels' width of its plane.
IVGI_CONST float kShadowNormalCos = 0.9f;
IVGI_CONST float kShadowPlanePixels = 2.0f;
// Per pixel (direct_pixels), at the point its central sample sees: the direct light of its share of
// the emitter samples with their shadows and without (rgb), that of every punctual light with
// their shadows (w: 1, or 0 where the pixel sees no surface), and the point's plane: its unit
// normal packed (packUnitVector, w of `shadowed`) and n·p (w of `unshadowed`).
struct PixelLight {
  vec4 shadowed;
  vec4 unshadowed;
  vec4 punctual;
};
struct DirectLightPush {  // direct_surfels
  uint count;             // points lit
  uint sampleCount;       // emitter samples, then the environment's directions
  uint resolution;        // a depth map's side in texels
  uint punctualLights;    // the punctual lights after them
  // With `changed` set, only the surfels whose light the moving objects can have changed are lit
  // again, the rest keep theirs: the maps' origins lie within `lights` and the moving objects within
  // `moved[0]` now and `moved[1]` when last drawn (spheres: centre, radius).
  vec4 lights;
  vec4 moved[2];
  uint changed;
  // A surfel looks up the maps of every surfelStride-th of the points (from its index modulo the
  // stride on), each standing for `surfelStride` of them; its unshadowed light takes them all.
  uint surfelStride;
  uint pad1, pad2;
};
// Where the pixels look the maps up themselves, the surfels' shadowed light is only the bounces'
// source, and each surfel looks up the maps of this many of the points (surfelStride).
IVGI_CONST uint kSurfelMapPoints = 16u;
// A directional light's maps nested around the camera for the pixels, past its map over the scene:
// the spare faces of its cube.
IVGI_CONST uint kCascades = kCubeFaces - 1u;
struct LightViewsPush {        // light_views
  uint sampleCount;            // emitter samples
  uint punctualLights;         // after them, `punctualLights`: the environment's directions, the punctual lights
  uint environmentDirections;  // the first of those
  uint cascadeCount;           // cascades a directional punctual light has (0 to kCascades)
  vec4 cascades[kCascades];    // the spheres they cover, finest first: centre, radius
  uint side;                   // a map's side in texels
};

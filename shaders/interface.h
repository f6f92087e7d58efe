// What the host and the shaders share, written once: buffer layouts, constants, push-constant
// structs and the functions whose results both sides use (keys, bins, form factors, lights, rays).
// Included by GLSL (shaders/common/common.glsl) and by C++ (namespace ivgi::gpu, on glm), so that nothing
// is mirrored by hand. Only the common subset of the two languages goes here: no swizzles, float
// literals with an f, IVGI_OUT for out parameters. Structs are std430 and hold no vec3 that a
// scalar does not follow (C++ aligns vec3 to 4 bytes, std430 to 16).
#ifndef IVGI_SHADERS_INTERFACE_H
#define IVGI_SHADERS_INTERFACE_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace ivgi::gpu {
using namespace glm;
using uint = uint32_t;
#define IVGI_CONST inline constexpr
#define IVGI_FN inline
#define IVGI_OUT(T) T&
#else
#define IVGI_CONST const
#define IVGI_FN
#define IVGI_OUT(T) out T
#endif

IVGI_CONST float kPi = 3.14159265358979f;

// Indirect dispatch size for `items` invocations of `size`, laid out over x then y (itemIndex()).
IVGI_FN uvec4 groupsFor(uint items, uint size) {
  const uint groups = (items + size - 1u) / size;
  return uvec4(min(groups, 65535u), (groups + 65534u) / 65535u, 1u, 0u);
}

// The items of a dispatch (emit, pull_up, refit, receiver_reach, scan_counts,
// vertex_irradiance, ar_order_receivers, ar_sort_senders).
struct CountPush {
  uint count;
};
// The items of a dispatch over every item, or over those listed (animate and surfels: the vertices
// and surfels of the objects that move, once a frame has posed them all).
struct ListedPush {
  uint count;   // items, or items listed
  uint listed;  // 1: item i is the i-th listed
};

// The parts, each after those it uses (so in this order, not sorted):
// the scene's data, the camera, textures, lights and the frame's passes;
#include "interface/scene.h"

// the surfaces' reflection (glTF's metallic-roughness BRDF);
#include "interface/brdf.h"

// direction bins, keys, form factors and tangent frames;
#include "interface/bins.h"

// link creation, which both solvers share;
#include "interface/links.h"

// iv's passes;
#include "interface/iv.h"

// ar's passes.
#include "interface/ar.h"

#ifdef __cplusplus
static_assert(sizeof(Vertex) == 64 && sizeof(Instance) == 32 && sizeof(Material) == 16 * kMaterialTexels &&
              sizeof(Surfel) == 48);
static_assert(sizeof(NodeState) == 48 && sizeof(PunctualLight) == 64 && sizeof(RasterPush) == 24 &&
              sizeof(DirectLightPush) == 80 && sizeof(ResolvePush) == 96);
#undef IVGI_CONST
#undef IVGI_FN
#undef IVGI_OUT
}  // namespace ivgi::gpu
#endif

#endif

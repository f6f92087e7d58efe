#include "engine/scene/triangle_rays.h"

#include <bit>
#include <stdexcept>
#include <string>
#include <utility>

namespace ivgi::scene {

namespace {

// A uniform number in [0, 1) of ray i's origin and direction and the triangle it meets: the same
// each time Embree asks of that hit (a triangle may lie in more than one of its leaves).
float raySample(const RTCFilterFunctionNArguments* args, unsigned i) {
  RTCRayN* ray = args->ray;
  const unsigned n = args->N;
  const uint32_t triangle = RTCHitN_primID(args->hit, n, i);
  uint32_t h = triangle;
  for (float x : {RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i),
                  RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i)})
    h = gpu::pcgHash(h ^ std::bit_cast<uint32_t>(x));
  return gpu::unitHash(h, triangle);
}

// Embree's filter for hits found, nearest and occluding alike: those on a cut-away point are not hits.
void passCutAway(const RTCFilterFunctionNArguments* args) {
  const auto& cutAway = *static_cast<const TriangleRays::CutAway*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 &&
        cutAway(RTCHitN_primID(args->hit, args->N, i),
                glm::vec2(RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)), raySample(args, i)))
      args->valid[i] = 0;
}

}  // namespace

TriangleRays::TriangleRays(const std::vector<gpu::WorldVertex>& world, const std::vector<gpu::Triangle>& triangles,
                           size_t count, bool watertight, CutAway cutAway)
    : cutAway_(std::move(cutAway)) {
  device_ = rtcNewDevice(nullptr);
  if (!device_)
    throw std::runtime_error("Embree: cannot create a device (error " +
                             std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  scene_ = rtcNewScene(device_);
  if (watertight) rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry mesh = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), world.size()));
  for (size_t v = 0; v < world.size(); ++v)
    for (int k = 0; k < 3; ++k) vertices[3 * v + size_t(k)] = world[v].position[k];
  auto* indices = static_cast<uint32_t*>(
      rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), count));
  for (size_t t = 0; t < count; ++t)
    indices[3 * t] = triangles[t].v0, indices[3 * t + 1] = triangles[t].v1, indices[3 * t + 2] = triangles[t].v2;
  if (cutAway_) {
    rtcSetGeometryUserData(mesh, &cutAway_);
    rtcSetGeometryIntersectFilterFunction(mesh, passCutAway);
    rtcSetGeometryOccludedFilterFunction(mesh, passCutAway);
  }
  rtcCommitGeometry(mesh);
  rtcAttachGeometry(scene_, mesh);
  rtcReleaseGeometry(mesh);
  rtcCommitScene(scene_);
  if (RTCError e = rtcGetDeviceError(device_); e != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: building the scene failed (error " + std::to_string(int(e)) + ")");
}

TriangleRays::~TriangleRays() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

std::optional<TriangleRays::Hit> TriangleRays::nearest(glm::vec3 o, glm::vec3 d, float tnear, float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z, rh.ray.tnear = tnear;
  rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z, rh.ray.tfar = tfar;
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return Hit{rh.hit.primID, rh.ray.tfar, glm::vec2(rh.hit.u, rh.hit.v)};
}

bool TriangleRays::occluded(glm::vec3 o, glm::vec3 d, float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = o.x, ray.org_y = o.y, ray.org_z = o.z, ray.tnear = 0.0f;
  ray.dir_x = d.x, ray.dir_y = d.y, ray.dir_z = d.z, ray.tfar = tfar;
  ray.mask = ~0u;
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;
}

}  // namespace ivgi::scene

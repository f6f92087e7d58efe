#version 460
// Pass 2, surfel update: area = a third of the adjacent triangles; position = the centroid of that
// area (the vertex's corner quad of each triangle: vertex, edge midpoints, centroid), so that a surfel
// on a hard edge lies inside its own face; normal from the welded vertex normals or, where the mesh
// has none, area-weighted face normals.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Sources { SurfelSource sources[]; };
layout(std430, binding = 1) readonly buffer SurfelVertices { uint surfelVertices[]; };
layout(std430, binding = 2) readonly buffer SurfelTriangles { uint surfelTriangles[]; };
layout(std430, binding = 3) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = 4) readonly buffer World { WorldVertex world[]; };
layout(std430, binding = 5) writeonly buffer Surfels { Surfel surfels[]; };
layout(push_constant) uniform Push { uint surfelCount; };

void main() {
  uint s = itemIndex();
  if (s >= surfelCount) return;
  SurfelSource src = sources[s];
  float area = 0.0;
  vec3 faceSum = vec3(0.0), vertexSum = vec3(0.0), moment = vec3(0.0);
  vec3 self = world[surfelVertices[src.firstVertex]].position.xyz;
  for (uint k = 0; k < src.triangleCount; ++k) {
    Triangle t = triangles[surfelTriangles[src.firstTriangle + k]];
    vec3 a = world[t.v0].position.xyz, b = world[t.v1].position.xyz, c = world[t.v2].position.xyz;
    vec3 n = cross(b - a, c - a);
    float third = length(n) / 6.0;
    area += third;
    faceSum += n;
    moment += third * (22.0 * self + 7.0 * (a + b + c - self)) / 36.0;  // the other two vertices: a + b + c - self
  }
  for (uint k = 0; k < src.vertexCount; ++k) vertexSum += world[surfelVertices[src.firstVertex + k]].normal.xyz;
  vec3 n = length(vertexSum) > 1e-6 ? vertexSum : faceSum;
  float len = length(n);
  surfels[s].positionArea = vec4(area > 0.0 ? moment / area : self, len > 0.0 ? area : 0.0);
  surfels[s].normal = vec4(len > 0.0 ? n / len : vec3(0.0), 0.0);
}

#version 460
// The animate pass: morph targets, then skinning or the node transform, per vertex.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Vertices { Vertex vertices[]; };
layout(std430, binding = 1) readonly buffer Instances { Instance instances[]; };
layout(std430, binding = 2) readonly buffer MorphDeltas { MorphDelta deltas[]; };
layout(std430, binding = 3) readonly buffer Matrices { mat4 matrices[]; };
layout(std430, binding = 4) readonly buffer MorphWeights { float morphWeights[]; };
layout(std430, binding = 5) writeonly buffer World { WorldVertex world[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: vertices

// det·M⁻ᵀ without a division: finite for singular matrices (a joint scaled to zero).
vec3 transformNormal(mat4 m, vec3 n) {
  vec3 c0 = m[0].xyz, c1 = m[1].xyz, c2 = m[2].xyz;
  mat3 cof = mat3(cross(c1, c2), cross(c2, c0), cross(c0, c1));
  float det = dot(c0, cross(c1, c2));
  vec3 r = cof * n * (det < 0.0 ? -1.0 : 1.0);
  float len = length(r);
  return len > 0.0 ? r / len : vec3(0.0);
}

void main() {
  uint i = itemIndex();
  if (i >= push.count) return;
  Vertex v = vertices[i];
  Instance inst = instances[v.instance];
  vec3 p = v.position, n = v.normal;
  for (uint k = 0; k < inst.morphTargets; ++k) {
    float w = morphWeights[inst.morphWeightBase + k];
    MorphDelta d = deltas[inst.morphDeltaBase + k * inst.vertexCount + v.local];
    p += w * d.position.xyz;
    n += w * d.normal.xyz;
  }
  mat4 m;
  if (inst.skinned != 0u) {
    m = v.weights.x * matrices[inst.matrix + v.joints.x] + v.weights.y * matrices[inst.matrix + v.joints.y] +
        v.weights.z * matrices[inst.matrix + v.joints.z] + v.weights.w * matrices[inst.matrix + v.joints.w];
  } else {
    m = matrices[inst.matrix];
  }
  world[i].position = vec4((m * vec4(p, 1.0)).xyz, 1.0);
  world[i].normal = vec4(transformNormal(m, n), 0.0);
}

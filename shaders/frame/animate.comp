#version 460
// The animate pass: morph targets, then skinning or the node transform, per vertex.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Vertices { Vertex vertices[]; };
layout(std430, binding = 1) readonly buffer Instances { Instance instances[]; };
// Read per target and per joint: texels (common.glsl).
layout(binding = 2, rgba32f) readonly uniform imageBuffer morphDeltas;  // MorphDelta: position, normal
layout(binding = 3, rgba32f) readonly uniform imageBuffer matrices;     // mat4: four columns
layout(binding = 4, r32f) readonly uniform imageBuffer morphWeights;
layout(std430, binding = 5) writeonly buffer World { WorldVertex world[]; };
// The vertices of the objects that move: the others keep the pose a frame before gave them.
layout(binding = 6, r32ui) readonly uniform uimageBuffer movingVertices;
layout(push_constant) uniform Push { ListedPush push; };  // the vertices, or those listed

// det·M⁻ᵀ without a division: finite for singular matrices (a joint scaled to zero).
vec3 transformNormal(mat4 m, vec3 n) {
  vec3 c0 = m[0].xyz, c1 = m[1].xyz, c2 = m[2].xyz;
  mat3 cof = mat3(cross(c1, c2), cross(c2, c0), cross(c0, c1));
  float det = dot(c0, cross(c1, c2));
  vec3 r = cof * n * (det < 0.0 ? -1.0 : 1.0);
  float len = length(r);
  return len > 0.0 ? r / len : vec3(0.0);
}

mat4 matrixAt(uint j) { return FOUR_TEXELS(mat4, matrices, j); }

void main() {
  uint i = itemIndex();
  if (i >= push.count) return;
  if (push.listed != 0u) i = imageLoad(movingVertices, int(i)).x;
  Vertex v = vertices[i];
  Instance inst = instances[v.instance];
  vec3 p = v.position, n = v.normal;
  for (uint k = 0; k < inst.morphTargets; ++k) {
    float w = imageLoad(morphWeights, int(inst.morphWeightBase + k)).x;
    const int d = int(2u * (inst.morphDeltaBase + k * inst.vertexCount + v.local));
    p += w * imageLoad(morphDeltas, d).xyz;
    n += w * imageLoad(morphDeltas, d + 1).xyz;
  }
  mat4 m;
  if (inst.skinned != 0u) {
    m = v.weights.x * matrixAt(inst.matrix + v.joints.x) + v.weights.y * matrixAt(inst.matrix + v.joints.y) +
        v.weights.z * matrixAt(inst.matrix + v.joints.z) + v.weights.w * matrixAt(inst.matrix + v.joints.w);
  } else {
    m = matrixAt(inst.matrix);
  }
  world[i].position = vec4((m * vec4(p, 1.0)).xyz, 1.0);
  world[i].normal = vec4(transformNormal(m, n), 0.0);
}

#version 460
// Runs the definitions of shaders/interface.h on the cases of tests/shared_definitions_test.cpp.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

struct Case {
  float value;
  uint id;
  uint size;
  uint mode;
};
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Keys { uint64_t keys[]; };
layout(std430, binding = 2) writeonly buffer Pairs { vec4 pairs[]; };  // texel pair, weight, key round trip
layout(std430, binding = 3) writeonly buffer Rays { vec4 rays[]; };
layout(std430, binding = 4) writeonly buffer StaticBins { uvec4 staticBins[]; };  // packed, bin, coverage
layout(push_constant) uniform Push { ResolvePush push; };  // the resolve's camera; samples: the cases

void main() {
  uint i = itemIndex();
  if (i >= push.samples) return;
  Case c = cases[i];
  uint64_t key = packDepthKey(c.value, c.id);
  keys[i] = key;
  float weight;
  ivec2 pair = texelPair(c.value, int(c.size), c.mode, weight);
  pairs[i] = vec4(float(pair.x), float(pair.y), weight, keyDepth(key) == c.value && keyId(key) == c.id ? 1.0 : 0.0);
  rays[i] = vec4(cameraRay(push.camera, vec2(c.value, float(c.id % 7u)) * float(push.size.x), push.size), 0.0);
  uint packed = packStaticBin(c.id % 24576u, c.id >> 13);
  staticBins[i] = uvec4(packed, staticBinOf(packed), staticCoverageOf(packed), 0u);
}

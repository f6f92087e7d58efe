#version 460
// Runs the bin and form-factor definitions of shaders/interface.h on the cases of
// tests/shared_definitions_test.cpp.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

struct BinCase {
  vec4 direction;
  uint n;
  uint bin;
  float area;
  float distance2;
};
struct BinResult {
  uint bin;
  float solidAngle;
  float formFactor;
  uint roundTrip;
  vec4 centre;
  uint64_t key;
  uint64_t fringeKey;
  float fringeDepth;
  uint beyond;
  uint pad[2];
  vec4 tangent;
};
layout(std430, binding = 0) readonly buffer Cases { BinCase cases[]; };
layout(std430, binding = 1) writeonly buffer Results { BinResult results[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = itemIndex();
  if (i >= count) return;
  BinCase c = cases[i];
  results[i].bin = binOf(c.direction.xyz, c.n);
  results[i].solidAngle = binSolidAngle(c.bin, c.n);
  results[i].formFactor = formFactor(c.area, c.direction.w, c.direction.x, c.distance2);
  results[i].roundTrip = binOf(binDirection(c.bin, c.n), c.n);
  results[i].centre = vec4(binDirection(c.bin, c.n), 0.0);
  results[i].key = packLinkKey(c.distance2, c.bin, false);
  results[i].fringeKey = packLinkKey(c.distance2, c.bin, true);
  results[i].fringeDepth = linkKeyDepth(results[i].fringeKey);
  uint r = c.bin % (c.n * c.n);
  results[i].beyond =
      binOfCell(c.bin / (c.n * c.n), ivec2(int(r % c.n), -1 - int(r / c.n)), c.n);  // mirrored past the lower edge
  vec3 t1, t2;
  tangentFrame(normalize(c.direction.xyz), t1, t2);
  results[i].tangent = vec4(t1, 0.0);
}

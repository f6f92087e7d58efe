// An object's pose (interface/iv.h, kPoseWords after the nodes' flags): where it moves rigidly, the
// motion from where it is this frame back to its rest pose; and the axes its surfaces follow.
// Expects `nodeFlags` and `push.poseBase`.
#ifndef OBJECT_POSE_GLSL
#define OBJECT_POSE_GLSL

float poseWord(uint root, uint k) {
  return uintBitsToFloat(imageLoad(nodeFlags, int(push.poseBase + kPoseWords * root + k)).x);
}

// Its rotation (rows 0–2 of the 3×4 matrix, without the shift).
mat3 restTurn(uint root) {
  return transpose(mat3(poseWord(root, 0u), poseWord(root, 1u), poseWord(root, 2u), poseWord(root, 4u),
                        poseWord(root, 5u), poseWord(root, 6u), poseWord(root, 8u), poseWord(root, 9u),
                        poseWord(root, 10u)));
}

vec3 restShift(uint root) { return vec3(poseWord(root, 3u), poseWord(root, 7u), poseWord(root, 11u)); }

// The axes its surfaces follow, as rows (gi::objectAxes): at rest, or as it stands this frame.
mat3 objectAxes(uint root, bool atRest) {
  const uint at = atRest ? kRestAxesWord : kAxesWord;
  const vec3 x = vec3(poseWord(root, at), poseWord(root, at + 1u), poseWord(root, at + 2u)),
             z = vec3(poseWord(root, at + 3u), poseWord(root, at + 4u), poseWord(root, at + 5u));
  return transpose(mat3(x, cross(z, x), z));
}

#endif

// A rigidly moving object's pose (interface/iv.h, kPoseWords after the nodes' flags): the motion
// from where it is this frame back to its rest pose. Expects `nodeFlags` and `push.poseBase`.
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

#endif

#version 460
// The indirect dispatch size of a workgroup per item of a queue whose first word counts its items
// (one invocation).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 1) in;

layout(std430, binding = 0) readonly buffer Queue { uint queue[]; };
layout(std430, binding = 1) writeonly buffer Args { uvec4 args[]; };
layout(push_constant) uniform Push { QueueArgsPush push; };

void main() { args[push.slot] = groupsFor(queue[0], 1u); }

#version 460
// ar: each surfel's incident light per bin, what its node and its ancestors gathered (summed down
// the trees by ar_sum_down) plus the environment and the punctual lights (unoccluded: antiradiance
// cancels them where they are blocked); and its irradiance: its normal against the vector sums of
// what its flat node and ancestors gathered (each sender along its own direction), the bins of its
// front for what its curved ancestors gathered and the environment (Σ L·max(n·∫ω dω, 0), the weights
// scaled to sum to π: a bin across the horizon weighs less than its part above it), and the
// lights' exact cosines; where the depth maps give the emitters' direct light, that too. The workgroup sums what the
// host judges the iteration by.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint kDirs = 4;  // --dirs: a constant, so that the bins' arithmetic folds

layout(binding = 1, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(std430, binding = 2) readonly buffer LeafOfSurfel { uint leafOfSurfel[]; };
layout(binding = 3, rgba32f) readonly uniform imageBuffer binTable;     // per bin ∫ω dω, Ω
layout(binding = 4, rgba32f) readonly uniform imageBuffer environment;  // radiance per bin
layout(std430, binding = 5) readonly buffer Lights { PunctualLight lights[]; };
layout(binding = 6, rgba32f) readonly uniform imageBuffer gathered;  // per node and bin, with its ancestors'
layout(binding = 7, rgba32f) uniform imageBuffer incident;           // per surfel and bin
layout(std430, binding = 8) buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 9) writeonly buffer Sums { IterationSum sums[]; };
layout(binding = 10, rgba32f) readonly uniform imageBuffer gatheredVector;  // per node: x, y, z texels
layout(std430, binding = 11) readonly buffer SurfelDirect { vec4 surfelDirect[]; };
layout(push_constant) uniform Push { ArIncidentPush push; };

shared vec3 partial[64];

void main() {
  uint s = itemIndex(), lid = gl_LocalInvocationID.x;
  // A damped step goes ω of the way from the tables before it (an undamped one just writes them).
  const float w = push.damping;
  const bool damped = w < 1.0;
  vec3 mine = vec3(0.0);
  if (s < push.surfelCount) {
    uint leaf = leafOfSurfel[s], n = kDirs, bins = 6u * n * n;
    vec4 pa = nodePositionArea(leaf);
    vec3 normal = nodeNormalCone(leaf).xyz;
    vec3 E = push.emittersByMaps != 0u ? surfelDirect[s].rgb : vec3(0.0);
    // Every inner node's table holds what it and its ancestors gathered (ar_sum_down): the leaf's
    // and its parent's are what reaches the surfel through its tree. A curved node's ancestors are
    // curved (a node's normal cone holds its children's) and a leaf is flat, so what the curved
    // nodes of the path gathered, which reaches the irradiance through the bins, is the table of
    // the lowest of them.
    int parent = int(imageLoad(tree, int(leaf)).x), curved = parent;
    while (curved >= 0 && nodeNormalCone(uint(curved)).w <= kArFlatCone) curved = int(imageLoad(tree, curved).x);
    vec3 binsLight = vec3(0.0);
    float binsWeight = 0.0;
    for (uint b = 0u; b < bins; ++b) {
      vec3 sky = push.environmentOn != 0u ? imageLoad(environment, int(b)).rgb : vec3(0.0);
      vec3 I = sky + imageLoad(gathered, int(leaf * bins + b)).rgb;
      if (parent >= 0) I += imageLoad(gathered, int(uint(parent) * bins + b)).rgb;
      vec3 fromBins = curved >= 0 ? sky + imageLoad(gathered, int(uint(curved) * bins + b)).rgb : sky;
      int texel = int(s * bins + b);
      imageStore(incident, texel, vec4(damped ? mix(imageLoad(incident, texel).rgb, I, w) : I, 0.0));
      const float cosine = max(dot(normal, imageLoad(binTable, int(b)).xyz), 0.0);
      binsLight += fromBins * cosine, binsWeight += cosine;
    }
    E += binsWeight > 0.0 ? binsLight * (kPi / binsWeight) : vec3(0.0);
    for (int node = int(leaf); node >= 0; node = int(imageLoad(tree, node).x)) {
      uint v = kArVectorTexels * uint(node);
      const vec3 offset = pa.xyz - nodePositionArea(uint(node)).xyz;
      E += normal.x * imageLoad(gatheredVector, int(v)).rgb + normal.y * imageLoad(gatheredVector, int(v + 1u)).rgb +
           normal.z * imageLoad(gatheredVector, int(v + 2u)).rgb;
      E += offset.x * imageLoad(gatheredVector, int(v + 3u)).rgb +
           offset.y * imageLoad(gatheredVector, int(v + 4u)).rgb +
           offset.z * imageLoad(gatheredVector, int(v + 5u)).rgb;
    }
    for (uint k = 0u; k < push.lightCount; ++k) {  // radiance over the bins around the light
      if (push.emittersByMaps != 0u) break;        // the depth maps give the lights' direct light
      vec3 toLight;
      float dist2;
      float falloff = lightFalloff(lights[k], pa.xyz, toLight, dist2);
      if (falloff <= 0.0) continue;
      uvec4 taps;
      vec4 weights;
      binTaps(normalize(toLight), n, taps, weights);
      vec3 added = lights[k].intensity.rgb * falloff;  // irradiance, as radiance over the bins around the light
      E += added * max(dot(normal, normalize(toLight)), 0.0);
      for (uint j = 0u; j < 4u; ++j) {
        uint bin = taps[j];
        vec3 radiance = w * weights[j] * added / imageLoad(binTable, int(bin)).w;
        int texel = int(s * bins + bin);
        imageStore(incident, texel, vec4(imageLoad(incident, texel).rgb + radiance, 0.0));
      }
    }
    // The change is the whole step's, damped or not: the iteration has settled when a step would
    // change nothing, not when a damped one changes little.
    vec3 shown = max(E, vec3(0.0)), before = irradiance[s].rgb;
    vec3 kept = damped ? mix(before, shown, w) : shown;
    mine = pa.w * vec3(luminance(shown), abs(luminance(shown) - luminance(before)), luminance(max(-E, vec3(0.0))));
    irradiance[s] = vec4(kept, 0.0);
  }
  partial[lid] = mine;
  barrier();
  for (uint width = 32u; width > 0u; width >>= 1u) {  // a fixed order: the sums do not vary run to run
    if (lid < width) partial[lid] += partial[lid + width];
    barrier();
  }
  if (lid == 0u)
    sums[push.sumSlot * gl_NumWorkGroups.x * gl_NumWorkGroups.y + groupIndex()] =
        IterationSum(partial[0].x, partial[0].y, partial[0].z, 0.0);
}

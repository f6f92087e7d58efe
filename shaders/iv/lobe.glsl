// A glossy surfel's lobe as the eye sees it (lobe_links.glsl, and the passes that need only the lobe
// itself). Declares what it reads at bindings 1 to 3 (0: the nodes, NODE_TEXELS) and the
// push constants; lobe_links.glsl declares more after them.
#ifndef LOBE_GLSL
#define LOBE_GLSL
layout(binding = 1, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(std430, binding = 2) readonly buffer SurfelBrdf { SurfaceBrdf surfelBrdf[]; };
layout(binding = 3, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(push_constant) uniform Push { LobePush push; };
#include "common/specular_albedo.glsl"

// A surfel's lobe: its material, its point, its tangent frame and the view in it.
struct Lobe {
  SurfaceBrdf brdf;
  vec3 x, t1, t2, n, view;
  vec3 evenShare;  // what it reflects toward the view of light arriving evenly, over π
  bool seen;       // glossy, and the eye in front of it
};

Lobe lobeOf(uint s) {
  Lobe lobe;
  lobe.brdf = surfelBrdf[s];
  const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
  lobe.x = nodePositionArea(leaf).xyz, lobe.n = nodeNormalCone(leaf).xyz;
  const vec3 toEye = towardEye(push.eye, lobe.x);
  const float nv = dot(lobe.n, toEye);
  lobe.seen = !isLambertian(lobe.brdf) && nv > 0.0;
  tangentFrame(lobe.n, lobe.t1, lobe.t2);
  lobe.view = lobe.seen ? normalize(vec3(dot(toEye, lobe.t1), dot(toEye, lobe.t2), nv)) : vec3(0.0, 0.0, 1.0);
  lobe.evenShare = lobeReflectanceOf(lobe.brdf, specularAlbedoAt(lobe.brdf, lobe.view.z)) / kPi;
  return lobe;
}
#endif

// The direct light of the emitter samples at a point, each seen or hidden by its depth maps
// (light_views, the raster). Expects `lightPoints` and `lightViews` (rgba32f texels: 4 a LightPoint,
// 4 a Camera) and `lightDepth` (depths' float bits, each view `side` texels square) declared before
// it. The points and views are read as texels, not from storage buffers, because every lane reads
// the same point in the loops over them (common.glsl: lavapipe reads a storage buffer a lane at a
// time).

LightPoint lightPointAt(uint i) { return FOUR_TEXELS(LightPoint, lightPoints, i); }
Camera lightViewAt(uint v) { return CAMERA_TEXELS(lightViews, v); }

// Texels' depth, in the view's depth along its forward axis; an empty texel is infinitely deep.
float depthAt(uint view, ivec2 texel, uint side) {
  const ivec2 t = clamp(texel, ivec2(0), ivec2(int(side) - 1));
  const uint bits = imageLoad(lightDepth, int((view * side + uint(t.y)) * side + uint(t.x))).x;
  return bits == 0xFFFFFFFFu ? 3.4e38 : uintBitsToFloat(bits);
}

// How the maps are looked up: at the pixels, the nearest texel (the resolve's window filters the
// emitter samples' shadows) and a directional light's finest cascade around the camera that holds
// the point; at the surfels, the four texels' bilinear share and the maps over the scene alone (their
// light does not depend on the camera). Where a blended surface (alphaMode BLEND) is in the maps,
// each texel keeps or passes it by chance, and the pixels take the four texels' bilinear share of
// the finest cascade (kBlendedPixelLookup), four of those chances.
const uint kPixelLookup = 0u, kSurfelLookup = 1u, kBlendedPixelLookup = 2u;
// How near a point, in texels, a surface the maps hold stands for the point's own (texelSees): the
// texels looked up lie up to a diagonal to the side of its ray, and a mesh is drawn into the maps
// within half a texel of its surface (scene::MapMeshes). And the margin by which a depth may lie
// nearer than the point's own plane and still pass, for the rounding of depths far from the view.
const float kOwnTexels = 2.0, kDepthMarginTexels = 0.05;

// Where p lies in orthographic view `view`: in its texels, its depth, and a texel's width.
void orthographicAt(uint view, vec3 p, float size, out vec2 at, out float z, out float texel) {
  const Camera c = lightViewAt(view);
  const vec3 d = p - c.origin.xyz;
  const vec2 ndc =
      vec2(dot(d, c.right.xyz) / dot(c.right.xyz, c.right.xyz), dot(d, c.up.xyz) / dot(c.up.xyz, c.up.xyz));
  z = dot(d, c.forward.xyz);
  texel = 2.0 * length(c.right.xyz) / size;
  at = vec2((ndc.x + 1.0) * 0.5 * size, (1.0 - ndc.y) * 0.5 * size) - 0.5;
}

// Where p lies in the views of emitter sample `point`: the view (at a pixel, a directional light's
// finest cascade around the camera whose texels around p lie within it), p in its texels, its depth
// there, and a texel's width at that depth.
void lightViewOf(LightPoint point, vec3 p, uint size, uint lookup, out uint view, out vec2 at, out float z,
                 out float texel) {
  const uint first = floatBitsToUint(point.radiance.w);
  const float s = float(size);
  if (point.cone.w == kLightPointIsPunctual && point.cone.z == kLightDirectional) {
    view = first;
    orthographicAt(view, p, s, at, z, texel);
    const uint cascades = lookup != kSurfelLookup ? uint(point.positionArea.w) : 0u;
    for (uint k = 1u; k <= cascades; ++k) {
      vec2 atK;
      float zK, texelK;
      orthographicAt(first + k, p, s, atK, zK, texelK);
      if (all(greaterThanEqual(atK, vec2(2.0))) && all(lessThanEqual(atK, vec2(s - 3.0)))) {
        view = first + k, at = atK, z = zK, texel = texelK;
        break;
      }
    }
  } else {
    // The cube's faces are axis-aligned (light_views): the face and where on it follow from d alone.
    const vec3 d = p - imageLoad(lightViews, int(4u * first)).xyz, m = abs(d);  // the cube's origin
    const uint axis = m.x >= m.y && m.x >= m.z ? 0u : (m.y >= m.z ? 1u : 2u);
    view = first + 2u * axis + (d[axis] < 0.0 ? 1u : 0u);
    z = m[axis];
    const float x = d[axis == 2u ? 0u : axis + 1u], y = d[axis == 0u ? 2u : axis - 1u];
    texel = 2.0 * z / s;
    at = vec2((x / z + 1.0) * 0.5 * s, (1.0 - y / z) * 0.5 * s) - 0.5;
  }
}

// Whether texel t of view `c` (`side` texels square), whose depth is `stored`, lets the light by to
// the point q (unit normal n, depth z, a texel `texel` wide there): where what the texel holds lies
// no nearer than q's plane along the texel's own ray (a plane is at its own depth in every texel,
// however steeply it is seen), or within kOwnTexels of q (a surface that meets q's at a crease
// stands for q's own there). Along a ray that runs nearly along the plane, the plane counts as
// within `reach` of z.
bool texelSees(Camera c, ivec2 t, uint side, float stored, vec3 q, vec3 n, float z, float texel, float reach) {
  const vec2 centre = vec2(clamp(t, ivec2(0), ivec2(int(side) - 1))) + 0.5;
  const vec3 dir = cameraRay(c, centre, uvec2(side)), origin = cameraRayOrigin(c, centre, uvec2(side));
  const float along = dot(n, dir);
  const float plane = along < 0.0 ? clamp(dot(n, q - origin) / along, z - reach, z + reach) : z + reach;
  if (stored + kDepthMarginTexels * texel >= plane) return true;
  const vec3 held = origin + stored * dir - q;
  return dot(held, held) <= kOwnTexels * kOwnTexels * texel * texel;
}

// The share of the four texels around the ray from emitter sample `point`'s views to the point `p`
// (unit normal n) that see p (kSurfelLookup, kBlendedPixelLookup: bilinear weights; kPixelLookup:
// whether the nearest texel does; texelSees), where `cosine` is the cosine of the ray at p's
// surface. A depth bias instead of p's plane would have to grow with the plane's slope, and would
// let the light under whatever stands on the surface as far as it reaches (behind a wall, along its
// foot).
float seenShare(LightPoint point, vec3 p, vec3 n, float cosine, uint side, uint lookup) {
  uint view;
  float z, texel;  // p's depth in the view, a texel's width there
  vec2 at;         // p in the view's texels
  lightViewOf(point, p, side, lookup, view, at, z, texel);
  const Camera c = lightViewAt(view);
  // As far as a texel and a half of the slope reach, where the plane is seen edge on.
  const float reach = 1.5 * texel * (1.0 + sqrt(max(1.0 - cosine * cosine, 0.0)) / max(cosine, 0.1));
  if (lookup == kPixelLookup) {
    const ivec2 t = ivec2(floor(at + 0.5));
    return texelSees(c, t, side, depthAt(view, t, side), p, n, z, texel, reach) ? 1.0 : 0.0;
  }
  const ivec2 corner = ivec2(floor(at));
  const vec2 f = at - vec2(corner);
  vec4 seen;
  for (int k = 0; k < 4; ++k) {
    const ivec2 t = corner + ivec2(k & 1, k >> 1);
    seen[k] = texelSees(c, t, side, depthAt(view, t, side), p, n, z, texel, reach) ? 1.0 : 0.0;
  }
  return mix(mix(seen.x, seen.y, f.x), mix(seen.z, seen.w, f.x), f.y);
}

// The light of point `l` (an emitter sample or a point or spot light) at p (unit normal n) where it
// is seen; zero where p faces away from it or lies behind the emitter. `cosine`: the ray's at p;
// `toward`: the unit direction from p to the light.
vec3 lightFrom(LightPoint l, vec3 p, vec3 n, out float cosine, out vec3 toward) {
  cosine = 0.0;
  toward = n;
  if (l.cone.w == kLightPointIsPunctual) {
    vec3 toLight;
    float d2;
    const float falloff =
        lightFalloff(PunctualLight(vec4(l.positionArea.xyz, l.cone.z), l.normal, l.radiance, l.cone), p, toLight, d2);
    if (!(falloff > 0.0) || !(d2 > 0.0)) return vec3(0.0);
    toward = l.cone.z == kLightDirectional ? normalize(toLight) : toLight * inversesqrt(d2);
    cosine = dot(n, toward);
    return cosine > 0.0 ? l.radiance.rgb * (falloff * cosine) : vec3(0.0);
  }
  const vec3 toLight = l.positionArea.xyz - p;
  const float d2 = dot(toLight, toLight);
  if (!(d2 > 0.0)) return vec3(0.0);
  const float inv = inversesqrt(d2), cosL = -dot(l.normal.xyz, toLight) * inv;
  toward = toLight * inv;
  cosine = dot(n, toLight) * inv;
  if (cosine <= 0.0 || cosL <= 0.0) return vec3(0.0);
  return l.radiance.rgb * (l.positionArea.w * cosine * cosL / (d2 + l.positionArea.w / kPi));
}

// What a surface reflects toward the camera of the light of points first, first + stride, … before
// `end`, each where its maps see p, through its specular lobe (kGlossy): the material and the view
// (unit, away from the surface) in the tangent frame of its shading normal n.
struct Lobe {
  bool glossy;  // false: nothing reflected (a Lambertian surface, or none asked)
  SurfaceBrdf brdf;
  vec3 t1, t2, n, view;
};
Lobe noLobe(vec3 n) { return Lobe(false, SurfaceBrdf(vec4(0.0), vec4(0.0), 0.0, 1.0, 0.0, 0.0), n, n, n, n); }
vec3 lobeOf(Lobe lobe, vec3 toward) {
  const vec3 l = vec3(dot(toward, lobe.t1), dot(toward, lobe.t2), dot(toward, lobe.n));
  return evalBrdf(lobe.brdf, l, lobe.view, 0.0);  // weight 0: the lobe alone, not the base
}

// The light at a point from a run of light points (lightAt): each point's where its maps see the
// point, and every point's. With each, its luminance as a vector: the points' luminance at normal
// incidence along their directions, whose dot product with the normal is the luminance of the sum,
// and with another normal what the same light gives there while it stays above that normal's
// horizon (how a normal texture turns it).
struct PointsLight {
  vec3 seen, unshadowed;
  vec3 seenVector, unshadowedVector;
  vec3 reflected;   // what the lobe reflects of the seen light toward the camera
  vec4 arrival;     // the seen light's directions weighed by its luminance (xyz), and that luminance (w)
  float footprint;  // the solid angle a disk facing n spans from the lights, weighed likewise
};

// Light at p (unit normal n) from points first, first + stride, … before `end`, each where its maps
// see p (`lookup`: seenShare's), times `scale` but for `arrival` and `footprint`. The lobe reflects
// about its own normal (lobe.n, a normal texture's shading normal), each light weighed by the
// cosine there; `area` is the footprint's disk's.
PointsLight lightAt(vec3 p, vec3 n, uint first, uint end, uint stride, float scale, uint side, uint lookup, Lobe lobe,
                    float area) {
  PointsLight sums = PointsLight(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec4(0.0), 0.0);
  const bool turned = any(notEqual(lobe.n, n));
  for (uint i = first; i < end; i += stride) {
    float cosine;
    vec3 toward;
    const LightPoint point = lightPointAt(i);
    const vec3 seen = lightFrom(point, p, n, cosine, toward);
    if (cosine <= 0.0 || all(equal(seen, vec3(0.0)))) continue;
    const vec3 lit = seen * seenShare(point, p, n, cosine, side, lookup);
    sums.seen += lit;
    sums.unshadowed += seen;
    const float litLuminance = luminance(lit);
    sums.seenVector += litLuminance / cosine * toward;
    sums.unshadowedVector += luminance(seen) / cosine * toward;
    sums.arrival += litLuminance * vec4(toward, 1.0);
    const bool directional = point.cone.w == kLightPointIsPunctual && point.cone.z == kLightDirectional;
    const vec3 fromLight = point.positionArea.xyz - p;
    if (area > 0.0 && !directional)
      sums.footprint += litLuminance * area * cosine / (dot(fromLight, fromLight) + area / kPi);
    // Light from above the surface's horizon, weighed by the cosine at the lobe's normal.
    const float turn = turned ? max(dot(lobe.n, toward), 0.0) / cosine : 1.0;
    if (lobe.glossy) sums.reflected += lobeOf(lobe, toward) * lit * turn;
  }
  sums.seen *= scale, sums.unshadowed *= scale, sums.reflected *= scale;
  sums.seenVector *= scale, sums.unshadowedVector *= scale;
  return sums;
}

// Irradiance at a surfel's p (unit normal n) from the emitter samples first, first + stride, … of
// `samples`, each a disk of the area it stands for, L·A·cos θ·cos θ' / (d² + A/π) (finite where p
// comes near it), times the stride: every stride-th of the stratified samples is an estimate of them
// all. And in `unshadowed`, the same with every sample seen; in `arrival` and `footprint`, lightAt's.
vec3 sampledIrradiance(vec3 p, vec3 n, uint samples, uint side, uint first, uint stride, out vec3 unshadowed,
                       out vec4 arrival, float area, out float footprint) {
  const PointsLight l = lightAt(p, n, first, samples, stride, float(stride), side, kSurfelLookup, noLobe(n), area);
  unshadowed = l.unshadowed, arrival = l.arrival, footprint = l.footprint;
  return l.seen;
}

// Irradiance at a surfel's p (unit normal n) from the `punctual` lights (point, spot, directional)
// after the `samples` emitter samples, each where its maps see p; in `arrival` and `footprint`, lightAt's.
vec3 punctualIrradiance(vec3 p, vec3 n, uint samples, uint punctual, uint side, out vec4 arrival, float area,
                        out float footprint) {
  const PointsLight l = lightAt(p, n, samples, samples + punctual, 1u, 1.0, side, kSurfelLookup, noLobe(n), area);
  arrival = l.arrival, footprint = l.footprint;
  return l.seen;
}

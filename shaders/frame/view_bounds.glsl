// Where world points and boxes fall in a view's samples (the raster's passes). Expects `push`
// (RasterPush) declared before it.

// Samples of slack around a triangle's projected bounds: float rounding there is far below it.
const float kBoundsSlack = 1.0 / 16.0;

// Sample-space x/y of a world point at distance z (> 0) along the view's forward axis (an
// orthographic view's do not depend on z).
vec2 projectAt(Camera camera, vec3 p, float z) {
  const vec3 d = p - camera.origin.xyz;
  const vec2 ndc = vec2(dot(d, camera.right.xyz) / dot(camera.right.xyz, camera.right.xyz),
                        dot(d, camera.up.xyz) / dot(camera.up.xyz, camera.up.xyz)) /
                   (camera.up.w == kOrthographic ? 1.0 : z);
  return vec2((ndc.x + 1.0) * 0.5 * float(push.size.x), (1.0 - ndc.y) * 0.5 * float(push.size.y));
}

// The samples whose centres (x + 0.5) lie within sample-space bounds [mn, mx], widened by
// kBoundsSlack for the rounding between the projection and the ray test that decides: a triangle
// smaller than a sample mostly walks none. Empty (hi < lo) where nothing of them is on screen.
void boundsOf(vec2 mn, vec2 mx, out ivec2 lo, out ivec2 hi) {
  const vec2 far = vec2(push.size) + 2.0;  // past it, bounds convert to int safely and stay off screen
  lo = max(ivec2(0), ivec2(ceil(clamp(mn - 0.5 - kBoundsSlack, vec2(-2.0), far))));
  hi = min(ivec2(push.size) - 1, ivec2(floor(clamp(mx - 0.5 + kBoundsSlack, vec2(-2.0), far))));
  if (mx.x < -1.0 || mx.y < -1.0 || mn.x > float(push.size.x) + 1.0 || mn.y > float(push.size.y) + 1.0)
    hi = ivec2(-1);  // off screen, or wholly behind the near plane (mn > mx)
}

// Whether a triangle within the box [lo, hi] may cover samples of `camera`'s view; not for no view,
// an empty box, one wholly behind the near plane, or one whose bounds are off screen. `across`: the
// box crosses the near plane (it may cover any sample); else `blo`, `bhi` bound the samples its
// triangles can cover: a convex hull in front of the camera projects within the hull of its
// corners' projections.
bool boxInView(Camera camera, vec3 lo, vec3 hi, out bool across, out ivec2 blo, out ivec2 bhi) {
  across = false;
  blo = ivec2(0), bhi = ivec2(-1);
  if (camera.origin.w < 0.0 || lo.x > hi.x) return false;
  vec2 mn = vec2(3.4e38), mx = vec2(-3.4e38);
  uint beyond = 0u;  // corners beyond the near plane
  for (int i = 0; i < 8; ++i) {
    const vec3 p = vec3((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, (i & 4) != 0 ? hi.z : lo.z);
    const float z = dot(p - camera.origin.xyz, camera.forward.xyz);
    if (z > camera.origin.w) {
      const vec2 s = projectAt(camera, p, z);
      mn = min(mn, s), mx = max(mx, s), ++beyond;
    }
  }
  if (beyond < 8u) {
    across = beyond > 0u;
    return across;
  }
  boundsOf(mn, mx, blo, bhi);
  return all(greaterThanEqual(bhi, blo));
}

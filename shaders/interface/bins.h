// Direction bins, link and visibility keys, form factors and the tangent frames the passes share
// (docs/design.md §5).
// Part of shaders/interface.h, which includes it inside its namespace and language macros.
// ---- Keys for 64-bit atomicMin ----

IVGI_CONST uint64_t kEmptyVisibility = 0xFFFFFFFFFFFFFFFFul;

// Visibility key: depth (positive float bits order like unsigned integers) above the id, so that
// 64-bit atomicMin keeps the nearest hit and breaks ties by the lower id.
IVGI_FN uint64_t packDepthKey(float depth, uint id) { return (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(id); }
IVGI_FN uint keyId(uint64_t key) { return uint(key & 0xFFFFFFFFul); }
IVGI_FN float keyDepth(uint64_t key) { return uintBitsToFloat(uint(key >> 32)); }

// Link key: squared distance above the sender node, so that atomicMin keeps the nearest sender per
// bin and breaks ties by id. The top bit marks a footprint's fringe (a bin it only brushes):
// fringes rank behind every core (a bin holding the footprint's centre or half covered by it), so
// that a near sender's blur does not hide what lies beside it.
IVGI_CONST uint64_t kFringeKey = 0x8000000000000000ul;
IVGI_FN uint64_t packLinkKey(float distance2, uint sender, bool fringe) {
  return packDepthKey(distance2, sender) | (fringe ? kFringeKey : 0ul);
}
IVGI_FN float linkKeyDepth(uint64_t key) { return keyDepth(key & ~kFringeKey); }

// A bin's covered solid angle is counted in 1/kCoverageUnit of the bin's (integer sums do not depend
// on the order of the atomics).
IVGI_CONST uint kCoverageUnit = 65536u;
// StaticBin, one r32ui texel beside each surviving link of a static leaf: its bin (15 bits;
// 6·64² < 2^15) and the bin's covered solid angle capped at the whole bin (17 bits; coverage only
// counts up to the whole bin, so the cap changes nothing).
IVGI_FN uint packStaticBin(uint bin, uint covered) { return bin | min(covered, kCoverageUnit) << 15; }
IVGI_FN uint staticBinOf(uint packed) { return packed & 0x7FFFu; }
IVGI_FN uint staticCoverageOf(uint packed) { return packed >> 15; }

// ---- Direction bins and form factors (docs/design.md §5) ----

// Cube-map bin of a non-zero direction: face = 2·axis + (negative ? 1 : 0), then (i, j) from the two
// other coordinates divided by the major one. Bins are numbered face·N² + j·N + i.
IVGI_FN uint binOf(vec3 d, uint n) {
  vec3 a = abs(d);
  uint axis = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
  float major = axis == 0u ? d.x : (axis == 1u ? d.y : d.z);
  vec2 uv = axis == 0u ? vec2(d.y, d.z) : (axis == 1u ? vec2(d.z, d.x) : vec2(d.x, d.y));
  uv /= abs(major);
  uvec2 ij = uvec2(clamp(floor((uv + 1.0f) * 0.5f * float(n)), vec2(0.0f), vec2(float(n - 1u))));
  uint face = 2u * axis + (major < 0.0f ? 1u : 0u);
  return face * n * n + ij.y * n + ij.x;
}

// Direction (unnormalised) through position uv of face `face`'s plane; beyond (−1, 1) the plane
// extends past the face, toward its neighbours.
IVGI_FN vec3 faceDirection(uint face, vec2 uv) {
  float s = (face & 1u) == 0u ? 1.0f : -1.0f;
  uint axis = face / 2u;
  if (axis == 0u) return vec3(s, uv.x, uv.y);
  if (axis == 1u) return vec3(uv.y, s, uv.x);
  return vec3(uv.x, uv.y, s);
}

// Centre direction (unnormalised, on the unit cube) of bin b.
IVGI_FN vec3 binDirection(uint b, uint n) {
  uint face = b / (n * n), r = b % (n * n);
  return faceDirection(face, (vec2(float(r % n), float(r / n)) + 0.5f) / float(n) * 2.0f - 1.0f);
}

// The bin opposite bin b (binOf(−binDirection(b))): the face of the other sign, its cell mirrored.
IVGI_FN uint oppositeBin(uint b, uint n) {
  uint perFace = n * n;
  return (b / perFace ^ 1u) * perFace + perFace - 1u - b % perFace;
}

// Bin of cell (x, y) of face `face`'s plane, n cells a side: the face's own bin, or past its edge
// the bin of the neighbouring face that the cell's centre falls in.
IVGI_FN uint binOfCell(uint face, ivec2 cell, uint n) {
  if (all(greaterThanEqual(cell, ivec2(0))) && all(lessThan(cell, ivec2(n))))
    return face * n * n + uint(cell.y) * n + uint(cell.x);
  return binOf(faceDirection(face, (vec2(cell) + 0.5f) / (0.5f * float(n)) - 1.0f), n);
}

IVGI_FN float cubeAreaIntegral(float u, float v) { return atan(u * v, sqrt(u * u + v * v + 1.0f)); }

// Exact solid angle of bin b: Φ(u1,v1) − Φ(u0,v1) − Φ(u1,v0) + Φ(u0,v0). GLSL's atan is an
// approximation: the solver builds its table of bins on the host.
IVGI_FN float binSolidAngle(uint b, uint n) {
  uint r = b % (n * n);
  float step = 2.0f / float(n);
  float u0 = -1.0f + float(r % n) * step, v0 = -1.0f + float(r / n) * step;
  float u1 = u0 + step, v1 = v0 + step;
  return cubeAreaIntegral(u1, v1) - cubeAreaIntegral(u0, v1) - cubeAreaIntegral(u1, v0) + cubeAreaIntegral(u0, v0);
}

// Disk-to-point form factor: at most 1, and finite as d → 0.
IVGI_FN float formFactor(float senderArea, float cosSender, float cosReceiver, float distance2) {
  return senderArea * max(cosSender, 0.0f) * max(cosReceiver, 0.0f) / (kPi * distance2 + senderArea);
}

// A tangent frame of unit normal n that depends on n alone (so that neighbours on a flat face agree).
IVGI_FN void tangentFrame(vec3 n, IVGI_OUT(vec3) t1, IVGI_OUT(vec3) t2) {
  t1 = normalize(abs(n.x) < 0.9f ? cross(n, vec3(1, 0, 0)) : cross(n, vec3(0, 1, 0)));
  t2 = cross(n, t1);
}

// Direction d in the tangent frame (t1, t2) as its angle times four (a right angle a full turn),
// weighted by its length there: summed over a grid's edges, or over elements' axes, it gives their
// common orientation modulo a right angle (quarterAngle), whatever the grid's rotation.
IVGI_FN vec2 quarterTurns(vec3 d, vec3 t1, vec3 t2) {
  float x = dot(d, t1), y = dot(d, t2), r2 = x * x + y * y;
  if (r2 <= 0.0f) return vec2(0.0f);
  float c2 = (x * x - y * y) / r2, s2 = 2.0f * x * y / r2;  // the angle doubled
  return sqrt(r2) * vec2(c2 * c2 - s2 * s2, 2.0f * c2 * s2);
}
IVGI_FN float quarterAngle(vec2 sum) { return length(sum) > 0.0f ? 0.25f * atan(sum.y, sum.x) : 0.0f; }
// quarterTurns() of the three edges of triangle abc.
IVGI_FN vec2 edgeQuarterTurns(vec3 a, vec3 b, vec3 c, vec3 t1, vec3 t2) {
  return quarterTurns(b - a, t1, t2) + quarterTurns(c - b, t1, t2) + quarterTurns(a - c, t1, t2);
}

// The axes of a rectangle (a surfel's, a node's) turned by `angle` in the tangent frame of n.
IVGI_FN void rectangleAxes(vec3 n, float angle, IVGI_OUT(vec3) u1, IVGI_OUT(vec3) u2) {
  vec3 t1, t2;
  tangentFrame(n, t1, t2);
  float c = cos(angle), s = sin(angle);
  u1 = c * t1 + s * t2;
  u2 = c * t2 - s * t1;
}

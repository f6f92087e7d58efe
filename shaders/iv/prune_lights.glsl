// The prune's lights (prune_bins.comp): whether a surface in the bins hides a light (an emitter's
// piece, a punctual light) from the receiver, finer than the bins; the punctual lights' and the
// emitters' direct light.
// Included by prune_bins.comp after its bindings, specialization constants and shared memory.

// Whether the ray from p along q crosses node o's rectangle (false for a curved node: it has none).
bool rectangleHit(uint o, vec3 p, vec3 q) {
  vec4 plane = nodeNormalCone(o);
  vec3 sideA, sideB, centre = nodePositionArea(o).xyz;
  senderSides(o, plane, sideA, sideB);
  float along = dot(plane.xyz, q);
  if (sideA == vec3(0.0) || along == 0.0) return false;
  vec3 h = p + q * (dot(plane.xyz, centre - p) / along) - centre;
  return abs(dot(h, sideA)) <= dot(sideA, sideA) && abs(dot(h, sideB)) <= dot(sideB, sideB);
}

// Whether the ray from p along q crosses the surface of sender o: the rectangle of o or of the
// whole flat surface o lies on (its highest ancestor flat in its plane; o may be one of that
// surface's elements, and the ray cross its neighbour). Or, unless `surely`, where neither is a bin
// wide: o is one of many elements smaller than a bin (or a curved one, which has no rectangle), and
// where the ray meets them is not known.
bool crosses(uint o, vec3 p, vec3 q, bool surely) {
  const float flatCone = 0.02;  // radians: a cone this narrow is a plane
  vec3 normal = nodeNormalCone(o).xyz, onPlane = nodePositionArea(o).xyz;
  int top = -1;
  for (int i = int(o); i >= 0; i = int(imageLoad(tree, i).x)) {
    vec4 cone = nodeNormalCone(uint(i));
    if (cone.w > flatCone || dot(cone.xyz, normal) < cos(flatCone) ||
        abs(dot(normal, nodePositionArea(uint(i)).xyz - onPlane)) > 1e-3 * nodeRadius(uint(i)))
      break;  // not in o's plane (parallel surfaces apart share a normal)
    top = i;
  }
  if (top < 0) return !surely;
  if (rectangleHit(o, p, q) || (top != int(o) && rectangleHit(uint(top), p, q))) return true;
  vec4 surface = nodePositionArea(uint(top));
  vec3 d = surface.xyz - p;
  return !surely && surface.w * float(kN * kN) < 4.0 * dot(d, d);  // a bin: (2/N)² at distance 1
}

// A light that is no surface: the punctual lights.
const uint kPunctual = 0xFFFFFFFFu;

// Whether the surface of bin key `key` stands between the receiver at p and the light at p + q:
// emitter s's piece (its node at squared distance dist²), or a punctual light (s = kPunctual, at
// dist²). It is nearer than the light, and for an emitter its plane separates them, each side
// judged within a thousandth of its own distance to that surface (a receiver just under an object
// resting on it lies behind its plane by less than the lamp is far; the ceiling beside a lamp and
// the lamp's own other pieces do not separate).
bool standsBetween(uint64_t key, uint s, float dist2, vec3 p, vec3 q) {
  uint o = keyId(key);
  if (key == kEmptyVisibility || o == s) return false;
  if (s == kPunctual) return linkKeyDepth(key) <= dist2;
  if (linkKeyDepth(key) >= dist2 * 0.999) return false;
  vec4 plane = nodeNormalCone(o);
  vec3 onPlane = nodePositionArea(o).xyz;
  float sideOfReceiver = dot(plane.xyz, p - onPlane), sideOfEmitter = dot(plane.xyz, p + q - onPlane);
  float nearMargin = 1e-3 * sqrt(linkKeyDepth(key)), farMargin = 1e-3 * length(q);
  return plane.w >= 0.5 * kPi || (sideOfReceiver > nearMargin && sideOfEmitter < -farMargin) ||
         (sideOfReceiver < -nearMargin && sideOfEmitter > farMargin);
}

// Whether the surface of bin key `key` hides the light: it stands between, and the ray crosses it
// (crosses(), `surely` or not).
bool hides(uint64_t key, uint s, float dist2, vec3 p, vec3 q, bool surely) {
  return standsBetween(key, s, dist2, p, q) && crosses(keyId(key), p, q, surely);
}

// Whether the light along q, in bin b, is hidden: the ray to it crosses a surface that stands
// between, over the bin's centre or over one of the eight neighbouring bins' centres (the light may
// lie up to a bin from its bin's centre, where another surface holds the view): shadows and
// penumbrae finer than the bins, either way. Over the bin's own centre, a surface whose rectangle
// does not tell where the ray meets it (curved, or elements smaller than a bin) hides it too.
// The eight neighbours are tested one after another, not in a loop (lavapipe's loop budget).
bool hidden(uint slot, uint b, uint s, float dist2, vec3 p, vec3 q) {
  uint64_t key = binAt(slot, b).key;
  return hides(key, s, dist2, p, q, false) ||
         hides(binAt(slot, neighbourBin(b, ivec2(1, 0))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(-1, 0))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(0, 1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(0, -1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(1, 1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(-1, 1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(1, -1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(-1, -1))).key, s, dist2, p, q, true);
}

// Punctual light l as the leaf sees it (moved with the nodes, common.glsl's NODE_POSE).
PunctualLight posedLight(uint l) {
  PunctualLight light = lights[l];
  light.position.xyz = posedPoint(light.position.xyz);
  light.direction.xyz = posedDirection(light.direction.xyz);
  return light;
}

// Irradiance at the receiver from the punctual lights it does not find hidden (none where the
// depth maps give their light).
vec3 punctualLight(uint slot, vec3 p, vec3 n) {
  vec3 sum = vec3(0.0);
  for (uint l = 0u; l < (push.emittersByMaps != 0u ? 0u : push.lightCount); ++l) {
    vec3 toLight;
    float dist2, falloff = lightFalloff(posedLight(l), p, toLight, dist2);
    float cosR = dot(n, normalize(toLight));
    if (cosR <= 0.0 || falloff <= 0.0) continue;
    if (hidden(slot, binOf(toLight, kN), kPunctual, dist2, p, toLight)) continue;
    sum += lights[l].intensity.rgb * cosR * falloff;
  }
  return sum;
}

// Emitted radiosity π·Le of node s (pulled up); zero for a node that emits nothing.
vec3 emitted(uint s) { return imageLoad(nodeEmission, int(s)).rgb; }

// Direct light from emitter s at the receiver (p, n): each of its pieces (as filed) with its own
// form factor, where it is not hidden. Exact where the bins only credit whole bins, so that a small
// emitter's light does not jump as its footprint crosses bin borders.
vec3 directLight(uint slot, vec3 p, vec3 n, uint s) {
  vec4 normalCone = nodeNormalCone(s);
  View v = viewOf(p, nodePositionArea(s), normalCone);
  float sum = 0.0;
  for (uint index = 0u; index < v.k * v.k; ++index) {
    Piece piece;
    if (!pieceOf(n, s, normalCone, v, index, piece) ||
        (dot(normalCone.xyz, piece.q) >= 0.0 && normalCone.w < 0.5 * kPi))
      continue;  // its back
    vec3 q = piece.q;
    float q2 = dot(q, q);
    if (!hidden(slot, binOf(q, kN), s, v.dist2, p, q)) sum += piece.omega * dot(n, q) * inversesqrt(q2) / kPi;
  }
  return sum * emitted(s);
}

// Emitter e of a leaf's list: its static ones first, then those the walk queued.
uint emitterAt(uint surfel, uint staticListed, uint e) {
  return e < staticListed ? staticEmitters[surfel * kStaticEmitters + e] : emitterQueue[e - staticListed];
}

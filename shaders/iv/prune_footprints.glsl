// The prune's filing (prune_bins.comp): a sender as the receiver sees it, filed into the bins as a
// footprint of its solid angle (its core and fringe), whole or in pieces, with the key it ranks by.
// Included by prune_bins.comp after its bindings, specialization constants and shared memory.

// Corner c (an offset from the receiver) on cube face `axis`, `sign`, in bin units; false behind it.
bool projectCorner(vec3 c, uint axis, float sign, out vec2 at) {
  float major = sign * (axis == 0u ? c.x : (axis == 1u ? c.y : c.z));
  vec2 minor = axis == 0u ? c.yz : (axis == 1u ? c.zx : c.xy);
  at = (minor / max(major, 1e-30) + 1.0) * 0.5 * float(kN);
  return major > 1e-3 * length(c);
}

float edgeSide(vec2 a, vec2 b, vec2 m) { return (b.x - a.x) * (m.y - a.y) - (b.y - a.y) * (m.x - a.x); }

// Whether m lies in the convex quadrilateral c0 c1 c2 c3 (either winding) scaled by 9/8 about its
// centre: elements of one surface whose rectangles do not quite tile (a mesh that is no grid) leave
// no bin centre between them.
bool insideOutline(vec2 m, vec2 c0, vec2 c1, vec2 c2, vec2 c3) {
  vec2 centre = 0.25 * (c0 + c1 + c2 + c3);
  m = centre + (m - centre) / 1.125;
  vec4 e = vec4(edgeSide(c0, c1, m), edgeSide(c1, c2, m), edgeSide(c2, c3, m), edgeSide(c3, c0, m));
  return all(greaterThanEqual(e, vec4(0.0))) || all(lessThanEqual(e, vec4(0.0)));
}

// Files a solid angle ω seen along d as a rectangular footprint of the same solid angle on the cube
// face, shaped like the filed element (half-sides `sideA`, `sideB` in the world; zero: a square):
// the bounding box of their projection gives its aspect, at most 8:1. Box-filtered over the bins it
// overlaps, on the face of its centre and past its edges on the neighbouring faces: even coverage
// for senders of any size and slant, across cube edges too. Its core bins take the key as it is,
// its fringe bins the fringe key, which ranks behind every core: a bin goes to the nearest surface
// over its centre, as a ray through it would find, so that a nearer object's outline takes its bins
// only as far as it reaches (given whole to any face centred in them, every outline would widen by
// up to a bin and darken its penumbra). The core bins are those whose centre lies in the element's
// own rectangle as the receiver sees it (a quadrilateral on the face): neighbouring elements tile
// the view as their rectangles tile the surface, where footprints of the same solid angle would not
// follow a slanted or turned element's outline and leave gaps, which growing them over would widen
// every outline by. A curved sender, a square without sides, is core where it holds the bin's
// centre (grown by an eighth of its sides) or covers half. A
// footprint at most one bin wide overlaps two bins from the one under its lower edge, so that the
// lanes of a subgroup walk loops of the same length (a CPU device runs a subgroup's loop as long as
// its longest lane); wider footprints walk their own range.
void insertFootprint(uint slot, vec3 d, uint64_t key, float omega, vec3 sideA, vec3 sideB, bool covers) {
  vec2 at;
  uint face = binFace(d, kN, at);
  vec2 uv = at / (0.5 * float(kN)) - 1.0;
  float stretch = 1.0 + dot(uv, uv);  // face area per solid angle: stretch^1.5
  float side = min(sqrt(omega * stretch * sqrt(stretch)) * 0.5 * float(kN), 16.0);  // in bins, as a square
  // A side's step on the face: d(uv) = (d(minor) − uv · d|major|) / |major|; the common factor drops out.
  uint axis = face / 2u;
  float sign = (face & 1u) == 0u ? 1.0 : -1.0;
  vec3 a = axis == 0u ? sideA.yzx : (axis == 1u ? sideA.zxy : sideA),
       b = axis == 0u ? sideB.yzx : (axis == 1u ? sideB.zxy : sideB);
  vec2 box = abs(a.xy - uv * (sign * a.z)) + abs(b.xy - uv * (sign * b.z));
  float aspect = box.x + box.y > 0.0 ? clamp(box.x / max(box.y, 1e-30), 0.125, 8.0) : 1.0;
  vec2 sides = min(side * vec2(sqrt(aspect), inversesqrt(aspect)), vec2(16.0));
  vec2 lo = at - 0.5 * sides, hi = at + 0.5 * sides;
  // The element's own outline on the face, where its corners lie in front of the receiver.
  vec2 c0, c1, c2, c3;
  bool outline = sideA != vec3(0.0) && projectCorner(d - sideA - sideB, axis, sign, c0) &&
                 projectCorner(d + sideA - sideB, axis, sign, c1) && projectCorner(d + sideA + sideB, axis, sign, c2) &&
                 projectCorner(d - sideA + sideB, axis, sign, c3);
  // Cells past the face's edge, up to half a face beyond, lie on the neighbouring faces (binOfCell),
  // so that a footprint across a cube edge does not overfill the face's border bins; the outermost
  // reach to infinity, so that nothing falls off.
  ivec2 lowest = ivec2(-int(kN / 2u)), highest = ivec2(int(kN - 1u + kN / 2u));
  ivec2 first = clamp(ivec2(floor(lo)), lowest, highest), end = clamp(ivec2(floor(hi)), lowest, highest);
  end = mix(end, min(first + 1, highest), lessThanEqual(sides, vec2(1.0)));
  float norm = 1.0 / max(sides.x * sides.y, 1e-12);
  for (int y = first.y; y <= end.y; ++y)
    for (int x = first.x; x <= end.x; ++x) {
      vec2 cellLo = vec2(x == lowest.x ? -1e9 : float(x), y == lowest.y ? -1e9 : float(y));
      vec2 cellHi = vec2(x == highest.x ? 1e9 : float(x + 1), y == highest.y ? 1e9 : float(y + 1));
      vec2 overlap = max(min(hi, cellHi) - max(lo, cellLo), vec2(0.0));
      float covered = overlap.x * overlap.y;  // in bins
      vec2 mid = vec2(x, y) + 0.5, grow = 0.125 * sides;
      bool core = outline ? insideOutline(mid, c0, c1, c2, c3)
                          : covered >= 0.5 || (all(greaterThanEqual(mid, lo - grow)) && all(lessThan(mid, hi + grow)));
      if (covered > 0.0 || side <= 0.0 || core)
        insert(slot, binOfCell(face, ivec2(x, y), kN), core ? key : key | kFringeKey,
               side > 0.0 ? omega * covered * norm : omega, covers);
    }
}

// Solid angle of a disk of radius r facing a point at squared distance d²: 2π(1 − d/√(d² + r²)),
// exact, and 2π (not infinity) as d → 0.
float diskSolidAngle(float r, float dist2) { return 2.0 * kPi * (1.0 - sqrt(dist2 / (dist2 + r * r))); }

// A sender as the receiver sees it: offset d, distance², the solid angle ω it subtends, the least
// cosine it is seen under, and the number k of pieces per side it is filed as (1: whole).
struct View {
  vec3 d;
  float dist2;
  float omega;
  float radius;
  float minCos;
  uint k;
};

View viewOf(vec3 p, vec4 positionArea, vec4 normalCone) {
  View v;
  v.d = positionArea.xyz - p;
  v.dist2 = dot(v.d, v.d);
  v.radius = sqrt(positionArea.w / kPi);
  // A curved node is seen at least as much as along the edge of its cone.
  v.minCos = sin(min(normalCone.w, 0.5 * kPi));
  float cosS = abs(dot(normalCone.xyz, v.d)) * inversesqrt(max(v.dist2, 1e-30));
  v.omega = diskSolidAngle(v.radius, v.dist2) * max(cosS, v.minCos);
  // Width in bins (a bin at a face centre is 2/N wide). Within three radii its near side is seen at
  // twice the scale of its far side or more: footprints centred on a few pieces' directions fall
  // short of the near side (along a room's edges, of the next wall's bottom row), so it is filed as
  // the most pieces.
  float width = sqrt(v.omega) * 0.5 * float(kN);
  v.k = v.dist2 <= 9.0 * v.radius * v.radius ? 8u : uint(clamp(ceil(width), 1.0, 8.0));
  return v;
}

// Piece `index` of the k×k pieces of a sender's rectangle as the receiver (normal n) sees it: its
// offset q, its own solid angle and half-sides. A curved sender is the square of its area facing
// the receiver. False for a piece below the receiver's horizon.
struct Piece {
  vec3 q;
  float omega;
  vec3 sideA, sideB;
};
bool pieceOf(vec3 n, uint s, vec4 normalCone, View v, uint index, out Piece piece) {
  vec3 sideA, sideB;
  senderSides(s, normalCone, sideA, sideB);
  if (sideA == vec3(0.0)) {
    vec3 t1, t2;
    tangentFrame(n, t1, t2);
    sideA = 0.5 * sqrt(kPi) * v.radius * t1, sideB = 0.5 * sqrt(kPi) * v.radius * t2;
  }
  vec2 at = (vec2(index % v.k, index / v.k) + 0.5) / float(v.k) * 2.0 - 1.0;  // in (−1, 1)²
  piece.q = v.d + at.x * sideA + at.y * sideB;
  float q2 = dot(piece.q, piece.q), k = float(v.k);
  if (dot(piece.q, n) <= 0.0 || q2 <= 0.0) return false;
  float cosQ = abs(dot(normalCone.xyz, piece.q)) * inversesqrt(q2);
  piece.omega = diskSolidAngle(v.radius / k, q2) * max(cosQ, v.minCos);
  piece.sideA = sideA / k, piece.sideB = sideB / k;
  return true;
}

// Sender s's key in the bins it is filed into, seen from the receiver (View v), and whether it adds
// to their coverage. On a closed surface the faces turned away from the receiver lie behind faces
// turned toward it in the same directions. So they add no coverage: counted, they would cover a
// silhouette's bins twice over, darkening what is seen past it (the sky between an engine's parts).
// And they rank as if at the far side of their object (its diameter further): by its centre a face
// behind is often nearer than the face in front of it (across a thin part, or a finely meshed back
// behind a coarse front), and would win bins to send nothing. Where the faces in front leave a bin empty
// (a receiver just under the object), the face behind still stands for its object there, at the
// distance of that far side. An open surface's back covers and ranks like a front: nothing else may
// stand in front of it.
uint64_t senderKey(uint s, vec4 normalCone, View v, out bool covers) {
  uint flags = imageLoad(nodeFlags, int(s)).x;
  covers = normalCone.w >= 0.5 * kPi || dot(normalCone.xyz, v.d) <= 0.0 || (flags & kNodeClosed) == 0u;
  float farSide = sqrt(v.dist2) + 2.0 * nodeRadius(flags >> kNodeRootShift);
  return packLinkKey(covers ? v.dist2 : farSide * farSide, s, false);
}

// Piece `index`, filed along its own direction with its own solid angle: the footprints follow the
// sender's outline, and a coincident sender on a hard edge is seen through its off-centre pieces.
void filePiece(uint slot, vec3 n, uint s, vec4 normalCone, View v, uint index) {
  Piece piece;
  bool covers;
  uint64_t key = senderKey(s, normalCone, v, covers);
  if (pieceOf(n, s, normalCone, v, index, piece))
    insertFootprint(slot, piece.q, key, piece.omega, piece.sideA, piece.sideB, covers);
}

// Files one sender of the leaf's root path (`marked`: its node, kEmitterBit if it emits), seen from
// the receiver (p, n, area): skipped where its disk cannot rise above the receiver's tangent plane
// (wholly below it, or lying in it: the receiver's own neighbours on a flat face); an emitter is
// also listed for its direct light; one at most a bin wide is filed whole, a wider one queued for
// its pieces (filed one per lane here, their k² pieces would hold up the whole subgroup).
void fileSender(uint slot, uint leaf, vec3 p, vec3 n, float area, uint marked) {
  uint s = marked & ~kEmitterBit;
  vec4 positionArea = nodePositionArea(s), normalCone = nodeNormalCone(s);
  View v = viewOf(p, positionArea, normalCone);
  float along = dot(normalCone.xyz, n);
  float rise = normalCone.w < 0.5 * kPi ? v.radius * sqrt(max(1.0 - along * along, 0.0)) : nodeRadius(s);
  if (s == leaf || dot(v.d, n) + rise <= 1e-4 * sqrt(area)) return;
  // A loop, not an if: lavapipe would run the if's atomic lane by lane, masked, for every sender,
  // and emitters are rare.
  for (bool emitter = (marked & kEmitterBit) != 0u && push.emittersByMaps == 0u; emitter; emitter = false) {
    uint queued = atomicAdd(emitterCount, 1u);
    if (queued < kEmitterQueue) emitterQueue[queued] = s;
  }
  if (v.k == 1u) {
    vec3 sideA, sideB;
    senderSides(s, normalCone, sideA, sideB);
    bool covers;
    uint64_t key = senderKey(s, normalCone, v, covers);
    insertFootprint(slot, v.d, key, v.omega, sideA, sideB, covers);
  } else {
    wideQueue[atomicAdd(wideCount, 1u)] = s;  // at most one per sender of the chunk
  }
}

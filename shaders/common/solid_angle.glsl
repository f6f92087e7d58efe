// Solid angles of polygons seen from a point, exact (Van Oosterom and Strackee).

// Signed solid angle of triangle abc (its corners relative to the point), positive where the point
// lies behind it (on the side away from its counter-clockwise normal).
float triangleSolidAngle(vec3 a, vec3 b, vec3 c) {
  const float la = length(a), lb = length(b), lc = length(c);
  const float numerator = dot(a, cross(b, c));
  const float denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
  return 2.0 * atan(numerator, denominator);
}

// Signed solid angle of the rectangle of centre q (relative to the point) and half-sides u, v: as
// triangleSolidAngle, its normal u × v.
float rectangleSolidAngle(vec3 q, vec3 u, vec3 v) {
  const vec3 q0 = q - u - v, q1 = q + u - v, q2 = q + u + v, q3 = q - u + v;
  return triangleSolidAngle(q0, q1, q2) + triangleSolidAngle(q0, q2, q3);
}

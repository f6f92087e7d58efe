// Solid angles of polygons seen from a point, exact.

// Signed solid angle of the rectangle of centre q (relative to the point) and half-sides u, v,
// positive where the point lies behind it (on the side away from u × v). Each of its two triangles'
// half-angles is the argument of D + iN (Van Oosterom and Strackee), so their sum is the argument
// of the product: one atan.
float rectangleSolidAngle(vec3 q, vec3 u, vec3 v) {
  const vec3 q0 = q - u - v, q1 = q + u - v, q2 = q + u + v, q3 = q - u + v;
  const float l0 = length(q0), l1 = length(q1), l2 = length(q2), l3 = length(q3);
  const float n1 = dot(q0, cross(q1, q2)), n2 = dot(q0, cross(q2, q3));
  const float d1 = l0 * l1 * l2 + dot(q0, q1) * l2 + dot(q0, q2) * l1 + dot(q1, q2) * l0;
  const float d2 = l0 * l2 * l3 + dot(q0, q2) * l3 + dot(q0, q3) * l2 + dot(q2, q3) * l0;
  return 2.0 * atan(n1 * d2 + n2 * d1, d1 * d2 - n1 * n2);
}

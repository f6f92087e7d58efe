// Interpolation of irradiance from receivers (docs/design.md §2.4), shared by the receivers'
// refinement (a sample predicted from its neighbours) and the interpolation weights. The including
// shader declares the node texels (NODE_TEXELS).

// Loops over the taps and over the fit's terms run a constant count with no early exit, each index
// the loop's own (those past the count skipped): unrolled, the arrays stay in registers. lavapipe
// keeps an array that any loop indexes at run time in memory, read and written a lane at a time.
#define FOR_TAPS(t)                              \
  for (uint t = 0u; t < kInterpolationTaps; ++t) \
    if (t < tapCount)
#define FOR_TERMS(i, m)                 \
  for (uint i = 0u; i < kFitTerms; ++i) \
    if (i < (m))

// The taps found so far: receiver surfel, weight (then coefficient), offset in the query's tangent plane.
uint tapCount = 0u;
uint tapReceiver[kInterpolationTaps];
float tapWeight[kInterpolationTaps];
vec2 tapOffset[kInterpolationTaps];

// Weight of a receiver at p (normal ns, support radius `radius`) for the surfel at x (normal n):
// (1 − t²)³ over the support, peaked where t → 0 (1/(t² + 0.01)), so that the fit all but passes
// through a receiver at its own place; over the support's radius, so that where finer receivers were
// needed (a shadow, a contact) they outweigh a coarse one whose support reaches over them: it was
// judged where the light is smooth and says less about the place than they do.
float receiverWeight(vec3 x, vec3 n, vec3 p, vec3 ns, float radius) {
  const float c = dot(n, ns);
  if (c <= kReceiverNormalCos) return 0.0;
  const vec3 d = p - x;
  const float across = dot(d, n), stretch = kReceiverPlaneStretch * kReceiverPlaneStretch - 1.0;
  const float t2 = (dot(d, d) + stretch * across * across) / (radius * radius);
  if (t2 >= 1.0) return 0.0;
  const float w = (1.0 - t2) * (1.0 - t2) * (1.0 - t2), a = (c - kReceiverNormalCos) / (1.0 - kReceiverNormalCos);
  return w * a * a / ((t2 + 0.01) * radius);
}

// Whether a receiver whose normal is at least `apart` radians from a surfel's may weigh for it:
// receiverWeight's normal test, with a margin for rounding (a walk skips what it rules out).
bool normalsMayWeigh(float apart) { return apart < acos(kReceiverNormalCos) + 1e-3; }

// Keeps a tap (a receiver met again, standing for another node, adds its weight), or where all
// kInterpolationTaps are taken, replaces the lightest if it is heavier (the first found of equal
// weights stays: a fixed order).
void keepTap(uint receiver, float weight, vec2 offset) {
  bool held = false;
  FOR_TAPS(t) if (tapReceiver[t] == receiver) tapWeight[t] += weight, held = true;
  uint slot = tapCount;
  if (!held && tapCount == kInterpolationTaps) {
    slot = 0u;
    float lightest = tapWeight[0];
    FOR_TAPS(t) if (tapWeight[t] < lightest) slot = t, lightest = tapWeight[t];
    held = lightest >= weight;
  }
  if (held) return;
  if (tapCount < kInterpolationTaps) ++tapCount;
  FOR_TAPS(t) if (t == slot) tapReceiver[t] = receiver, tapWeight[t] = weight, tapOffset[t] = offset;
}

// Considers receiver surfel s (at leaf node `leaf`) standing for a node of support radius `radius`
// and the given presence, for the surfel at x (normal n; t1, t2 its tangents).
void considerReceiver(uint s, uint leaf, float radius, float presence, vec3 x, vec3 n, vec3 t1, vec3 t2) {
  const vec3 p = nodePositionArea(leaf).xyz;
  const float w = receiverWeight(x, n, p, nodeNormalCone(leaf).xyz, radius) * presence;
  if (w > 0.0) keepTap(s, w, vec2(dot(p - x, t1), dot(p - x, t2)));
}

// The fit's regularisation, against the taps' total weight: slopes and curvatures the taps leave
// undetermined go to 0. A quadratic fit whose coefficients sum in magnitude past kMaxFitGain is
// replaced by the linear one (fitCoefficients).
const float kSlopeRegularisation = 0.01, kCurvatureRegularisation = 0.1, kMaxFitGain = 1.5;

// The terms of the fit at a tap offset o (in σ): constant, slopes and curvatures.
const uint kFitTerms = 6u;
float[kFitTerms] fitTerms(vec2 o) { return float[kFitTerms](1.0, o.x, o.y, o.x * o.x, o.x * o.y, o.y * o.y); }

// z = A⁻¹e₀ over the first m terms, A = Σ w q qᵀ with the slopes and the curvatures regularised
// (by Cholesky: A is symmetric and, regularised, positive definite).
float[kFitTerms] solveFit(uint m, float unit) {
  float a[kFitTerms][kFitTerms];
  FOR_TERMS(i, m) FOR_TERMS(j, i + 1u) a[i][j] = 0.0;
  FOR_TAPS(t) {
    const float q[kFitTerms] = fitTerms(tapOffset[t] * unit);
    FOR_TERMS(i, m) FOR_TERMS(j, i + 1u) a[i][j] += tapWeight[t] * q[i] * q[j];
  }
  FOR_TERMS(i, m) if (i > 0u) a[i][i] += (i < 3u ? kSlopeRegularisation : kCurvatureRegularisation) * a[0][0];
  FOR_TERMS(j, m) {  // A = L·Lᵀ, L in the lower triangle
    float d = a[j][j];
    FOR_TERMS(k, j) d -= a[j][k] * a[j][k];
    a[j][j] = sqrt(max(d, 1e-12 * a[0][0]));  // taps nearly in a line: rounding may leave ≤ 0
    FOR_TERMS(i, m) if (i > j) {
      float v = a[i][j];
      FOR_TERMS(k, j) v -= a[i][k] * a[j][k];
      a[i][j] = v / a[j][j];
    }
  }
  float z[kFitTerms] = float[kFitTerms](0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  FOR_TERMS(i, m) {  // L·y = e₀
    float v = i == 0u ? 1.0 : 0.0;
    FOR_TERMS(k, i) v -= a[i][k] * z[k];
    z[i] = v / a[i][i];
  }
  FOR_TERMS(r, m) {  // Lᵀ·z = y, from the last row up
    const uint i = m - 1u - r;
    float v = z[i];
    FOR_TERMS(k, m) if (k > i) v -= a[k][i] * z[k];
    z[i] = v / a[i][i];
  }
  return z;
}

// Tap t's factor in the fit z (its coefficient over its weight): (A⁻¹q_t)₀ = q_t·z.
float fitFactor(uint t, float unit, float z[kFitTerms]) {
  const float q[kFitTerms] = fitTerms(tapOffset[t] * unit);
  float c = 0.0;
  for (uint i = 0u; i < kFitTerms; ++i) c += z[i] * q[i];
  return c;
}

// Turns the taps' weights into the coefficients of a weighted least-squares fit evaluated at the
// query: c_k = w_k·(A⁻¹q_k)₀ with A = Σ w q qᵀ, so that irradiance changing linearly along the
// surface is interpolated exactly. Offsets are measured in σ, the taps' RMS offset, so that the solve
// does not depend on the scene's scale. The slopes are regularised: one or two taps, or taps in a
// line, give the weighted mean along what they leave undetermined; taps all at the query's place
// give their weighted mean. Σ c_k = 1.
// With `curvature` the fit is quadratic, so that light brightest between receivers (a wall's middle)
// is not flattened toward them, nor the darkest lifted. Where the taps determine a quadratic poorly
// it swings, and coefficients of large magnitude would amplify the receivers' differences from one
// bounce to the next (on a CAD file's slivers, taps nearly in a line, enough to make the bounces
// diverge): past kMaxFitGain the fit stays linear.
void fitCoefficients(bool curvature) {
  float total = 0.0, spread = 0.0;
  FOR_TAPS(t) total += tapWeight[t], spread += tapWeight[t] * dot(tapOffset[t], tapOffset[t]);
  spread /= total;
  if (!(spread > 0.0)) {
    FOR_TAPS(t) tapWeight[t] /= total;
    return;
  }
  const float unit = inversesqrt(spread);
  float z[kFitTerms] = solveFit(curvature ? kFitTerms : 3u, unit);
  if (curvature) {
    float gain = 0.0;
    FOR_TAPS(t) gain += abs(tapWeight[t] * fitFactor(t, unit, z));
    if (!(gain <= kMaxFitGain)) z = solveFit(3u, unit);
  }
  FOR_TAPS(t) tapWeight[t] *= fitFactor(t, unit, z);
}

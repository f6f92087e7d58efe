// glTF 2.0's metallic-roughness BRDF (the specification's Appendix B, with KHR_materials_specular
// and KHR_materials_ior folded into the dielectric's reflectance): a Lambertian base under a
// Trowbridge–Reitz (GGX) specular layer with Smith's height-correlated masking-shadowing and
// Schlick's Fresnel, mixed with the metal's by `metallic`. Directions are unit vectors in a frame
// whose z is the shading normal, pointing away from the surface.
//
// One departure from the appendix: its dielectric weighs the base by 1 − F(v·h), the Fresnel of
// each light's half vector, which reflects more than arrives at grazing views (a white surface of
// roughness 0.25 returns 1.13 of a uniform sky at 72°, 1.43 at 89°). Here the base is weighed as an
// energy-conserving, reciprocal layer (Kulla and Conty 2017's form): (1 − E(μ_l))(1 − E(μ_v)) /
// (1 − Ē), E the specular layer's directional albedo and Ē its cosine-weighted mean, from a table
// (engine/scene/reflectance.h), so that a white surface returns at most what arrives, as in
// Cycles' and OpenPBR's layering.
// Part of shaders/interface.h, which includes it inside its namespace and language macros.

// The smallest α (roughness²) the distribution is evaluated at: below it D's peak exceeds what a
// float holds, and a mirror needs a delta lobe that no method here models.
IVGI_CONST float kMinAlpha = 1e-3f;

IVGI_FN float alphaOf(float roughness) { return max(roughness * roughness, kMinAlpha); }

// The Trowbridge–Reitz distribution of normals at cos θ_h = nh, with a2 = α².
IVGI_FN float ggxD(float nh, float a2) {
  if (nh <= 0.0f) return 0.0f;
  const float d = nh * nh * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

// Smith's masking of one direction at cos θ = c.
IVGI_FN float smithG1(float c, float a2) { return 2.0f * c / (c + sqrt(a2 + (1.0f - a2) * c * c)); }

// G2 / (4 nl nv) with the height-correlated G2: the specular BRDF is V · D.
IVGI_FN float smithVisibility(float nl, float nv, float a2) {
  if (nl <= 0.0f || nv <= 0.0f) return 0.0f;
  return 0.5f / (nl * sqrt(nv * nv * (1.0f - a2) + a2) + nv * sqrt(nl * nl * (1.0f - a2) + a2));
}

IVGI_FN float schlickWeight(float vh) {
  const float m = clamp(1.0f - abs(vh), 0.0f, 1.0f);
  const float m2 = m * m;
  return m2 * m2 * m;
}

// One surface point's material, textures applied.
struct SurfaceBrdf {
  vec4 base;      // rgb: base colour
  vec4 specular;  // the dielectric's Fresnel: rgb at normal incidence, a at grazing (Material::specular)
  float metallic;
  float alpha;  // alphaOf(roughness)
  float pad0;
  float pad1;
};

// The dielectric's Fresnel (rgb) at cos θ = vh between the view and the half vector.
IVGI_FN vec3 dielectricFresnel(SurfaceBrdf m, float vh) {
  const vec3 f0 = vec3(m.specular.x, m.specular.y, m.specular.z);
  return f0 + (vec3(m.specular.w) - f0) * schlickWeight(vh);
}
IVGI_FN vec3 metalFresnel(SurfaceBrdf m, float vh) {
  const vec3 f0 = vec3(m.base.x, m.base.y, m.base.z);
  return f0 + (vec3(1.0f) - f0) * schlickWeight(vh);
}
IVGI_FN float maxOf(vec3 v) { return max(v.x, max(v.y, v.z)); }

// The specular layer's directional albedo is linear in the Fresnel's two ends: with the table's
// (A, B) = ∫ ((1 − w), w) · D · V · cos θ_l dω_l at a direction and roughness (w: Schlick's weight),
// E = F0 · A + F90 · B; taken at the largest channel of F0, as KHR_materials_specular's mix does.
IVGI_FN float layerAlbedo(SurfaceBrdf m, vec2 table) {
  return maxOf(vec3(m.specular.x, m.specular.y, m.specular.z)) * table.x + m.specular.w * table.y;
}

// The weight of the dielectric's base under its specular layer, from the layer's albedo toward
// l and v and its mean Ē: 1 wherever the layer reflects nothing.
IVGI_FN float baseWeight(float albedoL, float albedoV, float albedoMean) {
  return (1.0f - albedoL) * (1.0f - albedoV) / max(1.0f - albedoMean, 1e-6f);
}

// f(l, v): the radiance reflected toward v per unit irradiance from l (both above the surface:
// z > 0), the dielectric's base weighed by `weight` (baseWeight()).
IVGI_FN vec3 evalBrdf(SurfaceBrdf m, vec3 l, vec3 v, float weight) {
  if (l.z <= 0.0f || v.z <= 0.0f) return vec3(0.0f);
  const vec3 h = normalize(l + v);
  const float vh = dot(v, h), a2 = m.alpha * m.alpha;
  const float specular = ggxD(h.z, a2) * smithVisibility(l.z, v.z, a2);
  const vec3 fd = dielectricFresnel(m, vh);
  const vec3 base = vec3(m.base.x, m.base.y, m.base.z);
  const vec3 dielectric = weight * base / kPi + fd * specular;
  const vec3 metal = metalFresnel(m, vh) * specular;
  return mix(dielectric, metal, m.metallic);
}

// Whether the material reflects only diffusely (a Lambertian base, no specular layer).
IVGI_FN bool isLambertian(SurfaceBrdf m) {
  return m.metallic <= 0.0f && m.specular.w <= 0.0f && maxOf(vec3(m.specular.x, m.specular.y, m.specular.z)) <= 0.0f;
}

// Whether m's diffuse base lies under a specular layer, which sends it by its exit angle (baseWeight).
IVGI_FN bool baseLeavesByAngle(SurfaceBrdf m) { return !isLambertian(m) && m.metallic < 1.0f; }

// The specular albedo table (engine/scene/reflectance.h): kAlbedoTableSize directions, cos θ
// at ((i + ½) / size)² (denser toward grazing, where the albedo turns fastest), by
// kAlbedoTableSize roughnesses at (j / (size − 1))² (denser toward smooth, likewise).
IVGI_CONST uint kAlbedoTableSize = 32u;

// Where the table holds (A, B) toward cos θ = mu at a roughness: the first of the four nodes
// along each axis (x, y) and the weights of the second (z, w).
IVGI_FN vec4 albedoTableCell(float mu, float roughness) {
  const float last = float(kAlbedoTableSize - 1u);
  const float x = clamp(sqrt(max(mu, 0.0f)) * float(kAlbedoTableSize) - 0.5f, 0.0f, last);
  const float y = sqrt(clamp(roughness, 0.0f, 1.0f)) * last;
  const float x0 = min(floor(x), last - 1.0f), y0 = min(floor(y), last - 1.0f);
  return vec4(x0, y0, x - x0, y - y0);
}

// The fraction of uniform incident light a surface reflects: toward a direction, with the table's
// (A, B) there; over the hemisphere, with their means. The diffuse base returns ρ (1 − E) of it
// (its weight's mean over the light is exactly 1 − E toward the view), the layer its albedo.
// Split in two: what the diffuse base reflects, and what the specular lobe does.
IVGI_FN vec3 baseReflectanceOf(SurfaceBrdf m, vec2 table) {
  return (1.0f - m.metallic) * (1.0f - layerAlbedo(m, table)) * vec3(m.base.x, m.base.y, m.base.z);
}
IVGI_FN vec3 lobeReflectanceOf(SurfaceBrdf m, vec2 table) {
  const vec3 layer = vec3(m.specular.x, m.specular.y, m.specular.z) * table.x + vec3(m.specular.w * table.y);
  const vec3 metal = vec3(m.base.x, m.base.y, m.base.z) * table.x + vec3(table.y);
  return mix(layer, metal, m.metallic);
}
IVGI_FN vec3 reflectanceOf(SurfaceBrdf m, vec2 table) {
  return baseReflectanceOf(m, table) + lobeReflectanceOf(m, table);
}
// Whether m's lobe reflects, of light from its normal (`table` the specular albedo there), at
// least half of what m reflects and at least a tenth of what arrives: a metal's does; a
// dielectric's (F0 0.04) reflects a twentieth or so, a tenth of what a light base reflects. iv
// sends the first bounce's light along the lobes of such surfaces alone (send_arrival.comp).
IVGI_FN bool lobeDominates(SurfaceBrdf m, vec2 table) {
  const vec3 lobe = lobeReflectanceOf(m, table), all = reflectanceOf(m, table);
  const float reflected = lobe.x + lobe.y + lobe.z;
  return !isLambertian(m) && reflected >= 0.5f * (all.x + all.y + all.z) && reflected >= 0.3f;
}

// The specular lobe of m reflecting light whose directions spread around the one it is evaluated
// at (a sender's extent, a bin's) with per-axis angular variance `spread` (rad²): the distribution
// convolved with that spread, as Gaussians matched at their peaks add. GGX's slopes near its peak
// spread as α²/4 per axis, and near normal incidence the half vector turns half as far as the
// light, so α'² = α² + spread (toward grazing it turns further across the plane of incidence:
// widenedSpecular). A disk of solid angle Ω spreads Ω/(4π).
IVGI_FN SurfaceBrdf widenedLobe(SurfaceBrdf m, float spread) {
  m.alpha = min(sqrt(m.alpha * m.alpha + max(spread, 0.0f)), 1.0f);
  return m;
}

// Smith's Λ toward d (in the lobe's frame, its normal z) of an anisotropic GGX of α_x² = ax2 and
// α_y² = ay2: the isotropic Λ at α projected on d's azimuth (Heitz 2014).
IVGI_FN float smithLambda(vec3 d, float ax2, float ay2) {
  const float c2 = d.z * d.z, s2 = max(1.0f - c2, 0.0f), r2 = d.x * d.x + d.y * d.y;
  const float a2 = r2 > 0.0f ? (ax2 * d.x * d.x + ay2 * d.y * d.y) / r2 : ax2;
  return 0.5f * (sqrt(1.0f + a2 * s2 / max(c2, 1e-12f)) - 1.0f);
}

// GGX's slopes over a disk, against the widened lobe at the disk's centre. GGX's distribution of
// slopes is the stereographic image of a sphere's even one, which maps disks to caps: at roughness
// α, a disk of radius ρα around slopes δα from the peak holds sin²(x/2), x = atan2(2ρ, 1 + δ² − ρ²),
// the cap's share of the sphere. Its mean density over the disk, against that of the lobe widened
// by it (α'² = α²(1 + ρ²)) at the disk's centre: 1 at the peak, where the widening is the disk's
// mean; above 1 on the lobe's shoulder, which the disk takes in; 1/(1 + ρ²) far from the peak,
// where the disk's mean is the narrow lobe's value and the widened tail is heavier by α'²/α².
IVGI_FN float diskMeanOverWidened(float delta2, float rho2) {
  if (!(rho2 > 0.0f)) return 1.0f;
  // The widened density is (1 + ρ²)/t², t = 1 + ρ² + δ²; the disk's mean sin²(x/2)/ρ² is taken
  // without cancellation on either side of c = 0, its terms scaled by t (no overflow far out).
  const float t = 1.0f + rho2 + delta2, c = (1.0f + delta2 - rho2) / t, h = sqrt(c * c + 4.0f * rho2 / t / t);
  return c > 0.0f ? 2.0f / (h * (h + c) * (1.0f + rho2)) : (h - c) * t * t / (2.0f * h * rho2 * (1.0f + rho2));
}

// The same for widenedSpecular's anisotropic widening (α_x², α_y² of the narrow α²; hf the half
// vector in the frame turned to the view's azimuth). Along the half vector's slope direction e the
// spread is the widening ellipse's radius there, and far out the narrow lobe's tail over the
// widened one's is α²(e_x²α_y² + e_y²α_x²)²/(α_x α_y)³. The isotropic ratio's way from 1 at the
// peak to its far value, taken along e, carries the factor from 1 to that.
IVGI_FN float widenedTailFactor(vec3 hf, float a2, float ax2, float ay2) {
  const float sx = max(ax2 - a2, 0.0f), sy = max(ay2 - a2, 0.0f), across2 = hf.x * hf.x + hf.y * hf.y;
  if (!(sx + sy > 0.0f) || !(hf.z > 0.0f) || !(across2 > 0.0f)) return 1.0f;
  const float ex2 = hf.x * hf.x / across2, ey2 = 1.0f - ex2;
  const float radius2 = sx * sy / max(ex2 * sy + ey2 * sx, 1e-30f);
  const float narrow2 = max(a2, 1e-8f), rho2 = radius2 / narrow2, delta2 = across2 / (hf.z * hf.z) / narrow2;
  // The ratio's way from 1 at the peak (0) to its far value (1), negative on the shoulder; for a
  // small disk its limit, the disk's mean being the density plus ρ²/8 times its Laplacian.
  const float way = rho2 < 1e-3f ? delta2 * (delta2 - 2.0f) / ((1.0f + delta2) * (1.0f + delta2))
                                 : (1.0f - diskMeanOverWidened(delta2, rho2)) * (1.0f + rho2) / rho2;
  const float axy = ax2 * ay2, tail = ex2 * ay2 + ey2 * ax2;
  const float farRatio = a2 * tail * tail / (axy * sqrt(axy));
  return max(1.0f - way * (1.0f - farRatio), 0.0f);
}

// The specular lobe of m (its Fresnel times D·V, the base left out) toward v of light from l, both in
// the lobe's frame, where the light's directions spread around l with per-axis angular variance
// `spread` (a sender's extent, a bin's; a disk of solid angle Ω spreads Ω/(4π)). As widenedLobe,
// but the half vector turns half as far as the light only within the plane of v and l: across it,
// 1/(2·v·h) as far. So toward grazing a spread of the light is a wider spread of the half vector
// across the view's azimuth, and the lobe is widened there alone: an anisotropic GGX of α_x² = α² +
// spread along the azimuth and α_y² = α² + spread/(v·h)² across it, its masking height-correlated.
// That is the lobe's mean over the spread near its peak; away from it the mean is the narrow lobe's
// value, which widenedTailFactor restores. With no spread it is evalBrdf's lobe.
IVGI_FN vec3 widenedSpecular(SurfaceBrdf m, vec3 l, vec3 v, float spread) {
  if (l.z <= 0.0f || v.z <= 0.0f) return vec3(0.0f);
  const vec3 h = normalize(l + v);
  const float vh = dot(v, h), a2 = m.alpha * m.alpha, s = max(spread, 0.0f);
  // The frame turned to v's azimuth: x along it, y across.
  const float r = sqrt(v.x * v.x + v.y * v.y);
  const float cx = r > 1e-6f ? v.x / r : 1.0f, cy = r > 1e-6f ? v.y / r : 0.0f;
  const vec3 hf = vec3(cx * h.x + cy * h.y, cx * h.y - cy * h.x, h.z);
  const vec3 lf = vec3(cx * l.x + cy * l.y, cx * l.y - cy * l.x, l.z), vf = vec3(r, 0.0f, v.z);
  const float ax2 = min(a2 + s, 1.0f), ay2 = min(a2 + s / max(vh * vh, 1e-6f), 1.0f);
  const float k = hf.x * hf.x / ax2 + hf.y * hf.y / ay2 + hf.z * hf.z;
  const float d = hf.z > 0.0f ? widenedTailFactor(hf, a2, ax2, ay2) / (kPi * sqrt(ax2 * ay2) * k * k) : 0.0f;
  const float specular = d / ((1.0f + smithLambda(lf, ax2, ay2) + smithLambda(vf, ax2, ay2)) * 4.0f * l.z * v.z);
  return mix(dielectricFresnel(m, vh) * specular, metalFresnel(m, vh) * specular, m.metallic);
}

// A normal of the distribution as seen from v (Dupuy and Benyoub 2023, "Sampling visible GGX
// normals with spherical caps"): reflecting v about it samples the specular lobe in proportion to
// D_v(h) = G1(v) max(0, v·h) D(h) / v.z.
IVGI_FN vec3 sampleVisibleNormal(vec3 v, float alpha, float u1, float u2) {
  const vec3 vs = normalize(vec3(alpha * v.x, alpha * v.y, v.z));  // the view in the unit-roughness space
  const float phi = 2.0f * kPi * u1;
  const float z = (1.0f - u2) * (1.0f + vs.z) - vs.z;
  const float sinTheta = sqrt(clamp(1.0f - z * z, 0.0f, 1.0f));
  const vec3 hs = vec3(sinTheta * cos(phi), sinTheta * sin(phi), z) + vs;
  return normalize(vec3(alpha * hs.x, alpha * hs.y, max(hs.z, 0.0f)));
}

// The share, of what a lobe of roughness α reflects toward v of light arriving evenly, that arrives
// from above the plane whose unit normal is `plane` (v and plane in the lobe's frame, its normal z):
// what a surface whose shading normal is turned from its face keeps of an even sky, the face's
// plane hiding the rest. A quadrature of the visible normals at kLobeShareNodes points of a
// Fibonacci lattice (against 10⁵ random ones over views, tilts up to 50° and roughnesses, with the
// plane leaning along x: off by 0.007 on average, 0.021 at the 95th percentile), each direction
// weighed by its masking
// (height-correlated G2 over G1(v)) and counted by a ramp about the plane, and about the lobe's own
// horizon alike, so that the share turns continuously with the normal and is 1 where the plane is
// the lobe's own. The ramp is α wide (in the cosine), at most 0.25: about a node's spread.
IVGI_CONST int kLobeShareNodes = 32;
IVGI_FN float lobeShareAbove(float alpha, vec3 v, vec3 plane) {
  const float a2 = alpha * alpha, lambdaV = 0.5f * (sqrt(1.0f + a2 * (1.0f / (v.z * v.z) - 1.0f)) - 1.0f);
  const float ramp = clamp(alpha, 1e-4f, 0.25f);
  float above = 0.0f, all = 0.0f;
  for (int k = 0; k < kLobeShareNodes; ++k) {
    const float u1 = fract(float(k) * 0.618034f + 0.5f / float(kLobeShareNodes));
    const vec3 h = sampleVisibleNormal(v, alpha, u1, (float(k) + 0.5f) / float(kLobeShareNodes));
    const vec3 l = h * (2.0f * dot(h, v)) - v;
    if (!(l.z > 0.0f)) continue;
    const float lambdaL = 0.5f * (sqrt(1.0f + a2 * (1.0f / (l.z * l.z) - 1.0f)) - 1.0f);
    const float w = (1.0f + lambdaV) / (1.0f + lambdaV + lambdaL);
    all += w * clamp(0.5f + l.z / ramp, 0.0f, 1.0f);
    above += w * clamp(0.5f + dot(l, plane) / ramp, 0.0f, 1.0f);
  }
  return all > 0.0f ? min(above / all, 1.0f) : 1.0f;
}

// The density (per solid angle) of l = reflect(-v, h) with h from sampleVisibleNormal.
IVGI_FN float visibleNormalPdf(vec3 l, vec3 v, float alpha) {
  if (l.z <= 0.0f || v.z <= 0.0f) return 0.0f;
  const vec3 h = normalize(l + v);
  const float a2 = alpha * alpha;
  return smithG1(v.z, a2) * ggxD(h.z, a2) / (4.0f * v.z);
}

// The chance of sampling the specular lobe rather than the diffuse base, from their reflectances
// toward v (the layer's albedo `albedoV`, the metal's Fresnel at v): 0 for a Lambertian surface,
// 1 for a metal.
IVGI_FN float specularChance(SurfaceBrdf m, float nv, float albedoV) {
  const vec3 base = vec3(m.base.x, m.base.y, m.base.z);
  const float specular = mix(albedoV, maxOf(metalFresnel(m, nv)), m.metallic);
  const float diffuse = (1.0f - m.metallic) * (1.0f - albedoV) * maxOf(base);
  const float total = specular + diffuse;
  return total > 0.0f ? specular / total : 0.0f;
}

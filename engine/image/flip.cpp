// LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild: "FLIP: A Difference
// Evaluator for Alternating Images", HPG 2020), written from the paper's definition:
//   colour pipeline: sRGB → linear → YCxCz; each opponent channel filtered with its contrast
//   sensitivity function (sums of Gaussians, scaled by pixels per degree); back to linear RGB,
//   clamped; CIELAB with the Hunt adjustment; HyAB distance, raised to q_c = 0.7 and redistributed
//   to [0, 1] against the distance between green and blue (p_c = 0.4, p_t = 0.95);
//   feature pipeline: edges (first Gaussian derivative) and points (second derivative) of the
//   normalised achromatic channel, σ = ½·0.082° in pixels; the larger difference of their magnitudes,
//   scaled by 1/√2 and raised to q_f = 0.5;
//   error = ΔE_c ^ (1 − ΔE_f).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/image/colour.h"
#include "engine/image/metrics.h"

namespace ivgi::image {

namespace {

constexpr double kPi = 3.14159265358979323846;

// sRGB primaries, D65 white.
const glm::mat3 kLinearToXyz = glm::transpose(glm::mat3(0.4123908f, 0.3575843f, 0.1804808f,  //
                                                        0.2126390f, 0.7151687f, 0.0721923f,  //
                                                        0.0193308f, 0.1191948f, 0.9505322f));
const glm::mat3 kXyzToLinear = glm::inverse(kLinearToXyz);
const glm::vec3 kWhite = kLinearToXyz * glm::vec3(1.0f);

glm::vec3 linearToYcxcz(glm::vec3 rgb) {
  glm::vec3 n = kLinearToXyz * rgb / kWhite;
  return {116.0f * n.y - 16.0f, 500.0f * (n.x - n.y), 200.0f * (n.y - n.z)};
}

glm::vec3 ycxczToLinear(glm::vec3 c) {
  float y = (c.x + 16.0f) / 116.0f;
  glm::vec3 n(y + c.y / 500.0f, y, y - c.z / 200.0f);
  return kXyzToLinear * (n * kWhite);
}

glm::vec3 linearToHuntLab(glm::vec3 rgb) {
  glm::vec3 n = kLinearToXyz * rgb / kWhite;
  constexpr float d = 6.0f / 29.0f;
  auto f = [&](float t) { return t > d * d * d ? std::cbrt(t) : t / (3.0f * d * d) + 4.0f / 29.0f; };
  glm::vec3 fn(f(n.x), f(n.y), f(n.z));
  float L = 116.0f * fn.y - 16.0f;
  // Hunt effect: chroma is perceived weaker at low luminance.
  return {L, 0.01f * L * 500.0f * (fn.x - fn.y), 0.01f * L * 200.0f * (fn.y - fn.z)};
}

float hyab(glm::vec3 a, glm::vec3 b) { return std::abs(a.x - b.x) + std::hypot(a.y - b.y, a.z - b.z); }

// A separable 2-D kernel: weight(x, y) = scale · alongX[x] · alongY[y], indices from −radius.
struct SeparableTerm {
  std::vector<float> alongX, alongY;
  float scale = 1.0f;
};

// Correlation of one channel with a sum of separable terms, edges clamped (replicated).
std::vector<float> filter(const std::vector<float>& in, int w, int h, const std::vector<SeparableTerm>& terms) {
  std::vector<float> out(in.size(), 0.0f), rows(in.size());
  for (const auto& t : terms) {
    int rx = int(t.alongX.size() / 2), ry = int(t.alongY.size() / 2);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float s = 0.0f;
        for (int k = -rx; k <= rx; ++k) s += t.alongX[k + rx] * in[size_t(y) * w + std::clamp(x + k, 0, w - 1)];
        rows[size_t(y) * w + x] = s;
      }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float s = 0.0f;
        for (int k = -ry; k <= ry; ++k) s += t.alongY[k + ry] * rows[size_t(std::clamp(y + k, 0, h - 1)) * w + x];
        out[size_t(y) * w + x] += t.scale * s;
      }
  }
  return out;
}

// Contrast sensitivity of one opponent channel: Σ a_i·√(π/b_i)·exp(−π²·r²/b_i), r in degrees,
// normalised to sum 1 over the kernel. The radius covers three standard deviations of the widest
// Gaussian of all channels (b = 0.04), so that every channel uses the same support.
std::vector<SeparableTerm> csfKernel(double ppd, const std::vector<std::pair<double, double>>& gaussians) {
  int r = int(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * kPi * kPi)) * ppd));
  std::vector<SeparableTerm> terms;
  double total = 0;
  for (auto [a, b] : gaussians) {
    if (a == 0.0) continue;
    SeparableTerm t;
    double sum1d = 0;
    for (int i = -r; i <= r; ++i) {
      double x = i / ppd;
      t.alongX.push_back(float(std::exp(-kPi * kPi * x * x / b)));
      sum1d += t.alongX.back();
    }
    t.alongY = t.alongX;
    double peak = a * std::sqrt(kPi / b);
    t.scale = float(peak);
    total += peak * sum1d * sum1d;
    terms.push_back(t);
  }
  for (auto& t : terms) t.scale = float(t.scale / total);
  return terms;
}

// Edge (first derivative of a Gaussian) or point (second derivative) detector along x, with the
// positive weights normalised to sum 1 and the negative ones to −1; the transposed term is along y.
SeparableTerm featureKernel(double ppd, bool edge, bool transposed) {
  double sd = 0.5 * 0.082 * ppd;
  int r = int(std::ceil(3.0 * sd));
  std::vector<float> d, g;
  double pos = 0, neg = 0, gsum = 0;
  for (int i = -r; i <= r; ++i) {
    double e = std::exp(-double(i) * i / (2.0 * sd * sd));
    double v = edge ? -i * e : (double(i) * i / (sd * sd) - 1.0) * e;
    d.push_back(float(v));
    g.push_back(float(e));
    (v > 0 ? pos : neg) += std::abs(v);
    gsum += e;
  }
  for (auto& v : d) v = float(v > 0 ? v / pos : v / neg);
  for (auto& v : g) v = float(v / gsum);
  SeparableTerm t;
  t.alongX = transposed ? g : d;
  t.alongY = transposed ? d : g;
  return t;
}

struct Prepared {
  std::vector<glm::vec3> lab;        // filtered, Hunt-adjusted CIELAB
  std::vector<float> edges, points;  // feature magnitudes
};

Prepared prepare(const RgbImage& srgb, double ppd) {
  const int w = int(srgb.width), h = int(srgb.height);
  const size_t n = srgb.pixels.size();
  std::vector<float> c[3], achromatic(n);
  for (auto& ch : c) ch.resize(n);
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 p = glm::clamp(srgb.pixels[i], 0.0f, 1.0f);
    glm::vec3 o = linearToYcxcz({srgbToLinear(p.r), srgbToLinear(p.g), srgbToLinear(p.b)});
    c[0][i] = o.x, c[1][i] = o.y, c[2][i] = o.z;
    achromatic[i] = (o.x + 16.0f) / 116.0f;
  }
  // (a1, b1), (a2, b2) of the achromatic, red-green and blue-yellow contrast sensitivity functions.
  const std::vector<std::pair<double, double>> csf[3] = {
      {{1.0, 0.0047}}, {{1.0, 0.0053}}, {{34.1, 0.04}, {13.5, 0.025}}};
  for (int k = 0; k < 3; ++k) c[k] = filter(c[k], w, h, csfKernel(ppd, csf[k]));
  Prepared out;
  out.lab.resize(n);
  for (size_t i = 0; i < n; ++i)
    out.lab[i] = linearToHuntLab(glm::clamp(ycxczToLinear({c[0][i], c[1][i], c[2][i]}), 0.0f, 1.0f));
  for (bool edge : {true, false}) {
    auto gx = filter(achromatic, w, h, {featureKernel(ppd, edge, false)});
    auto gy = filter(achromatic, w, h, {featureKernel(ppd, edge, true)});
    auto& dst = edge ? out.edges : out.points;
    dst.resize(n);
    for (size_t i = 0; i < n; ++i) dst[i] = std::hypot(gx[i], gy[i]);
  }
  return out;
}

}  // namespace

std::vector<float> flipErrorMap(const RgbImage& test, const RgbImage& reference, double ppd) {
  if (test.width != reference.width || test.height != reference.height || test.pixels.size() != reference.pixels.size())
    throw std::invalid_argument("FLIP needs two images of the same size");
  Prepared t = prepare(test, ppd), r = prepare(reference, ppd);
  constexpr float qc = 0.7f, qf = 0.5f, pc = 0.4f, pt = 0.95f;
  const float cmax = std::pow(hyab(linearToHuntLab({0, 1, 0}), linearToHuntLab({0, 0, 1})), qc);
  std::vector<float> error(test.pixels.size());
  for (size_t i = 0; i < error.size(); ++i) {
    float e = std::pow(hyab(t.lab[i], r.lab[i]), qc);
    float colour = e < pc * cmax ? pt / (pc * cmax) * e : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0f - pt);
    float feature = std::pow(
        std::max(std::abs(t.edges[i] - r.edges[i]), std::abs(t.points[i] - r.points[i])) / std::sqrt(2.0f), qf);
    error[i] = std::clamp(std::pow(colour, 1.0f - feature), 0.0f, 1.0f);
  }
  return error;
}

}  // namespace ivgi::image

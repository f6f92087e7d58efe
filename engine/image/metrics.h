#pragma once
// How far a rendered image is from a reference: the error measures of docs/design.md §7 on linear
// radiance (relMSE, RMSE, PSNR, max error) and FLIP (Andersson et al., HPG 2020) on the tone-mapped
// display images.
#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "engine/image/frame_image.h"

namespace ivgi::image {

struct RgbImage {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec3> pixels;  // row-major, top row first
};

// The R, G, B channels of an OpenEXR file (linear radiance). Throws std::runtime_error naming the
// file and the problem (missing, not an EXR, no RGB, NaN or Inf).
RgbImage readLinearRgb(const std::string& path);
RgbImage radianceOf(const FrameChannels& frame);

struct ErrorMetrics {
  double relMse = 0;    // mean over pixels and channels of (x − r)² / (r² + 0.01)
  double rmse = 0;      // over pixels and channels
  double psnr = 0;      // 20·log10(1 / RMSE), peak 1 (dB); infinite for identical images
  double maxError = 0;  // largest |x − r| of any channel
  double flip = 0;      // mean LDR-FLIP over the tone-mapped images, in [0, 1]
  size_t pixels = 0;    // pixels measured (not ignored)
};

// `ignore`, if not empty, holds one flag per pixel: non-zero pixels are left out of every mean (FLIP
// still filters the whole image, as the eye would). `flipMap`, if given, receives the per-pixel FLIP
// error. Throws std::invalid_argument on a size mismatch.
ErrorMetrics measureError(const RgbImage& test, const RgbImage& reference, const std::vector<uint8_t>& ignore = {},
                          const DisplaySettings& display = {}, std::vector<float>* flipMap = nullptr);

// The image as the PNG shows it: exposure, tone map, sRGB encoding, in [0, 1].
RgbImage displayed(const RgbImage& linear, const DisplaySettings& display);

// Default viewing condition of the FLIP paper: a 0.7 m wide 4K monitor seen from 0.7 m.
constexpr double kFlipPixelsPerDegree = 0.7 * 3840.0 / 0.7 * 3.14159265358979 / 180.0;

// Per-pixel LDR-FLIP error in [0, 1] between two sRGB-encoded display images in [0, 1].
std::vector<float> flipErrorMap(const RgbImage& testSrgb, const RgbImage& referenceSrgb,
                                double pixelsPerDegree = kFlipPixelsPerDegree);

// A per-pixel error in [0, 1] as an 8-bit PNG with the magma colour map (black: none, yellow-white: 1).
void writeHeatmap(const std::string& path, const std::vector<float>& error, uint32_t width, uint32_t height);

// Per pixel, the luminance of test over reference as an 8-bit PNG with a diverging colour map
// (Moreland's cool-warm): blue where the test is darker, grey-white where they agree, red where it
// is brighter, saturating at kRatioRange (or its inverse). Black where both are black.
inline constexpr float kRatioRange = 1.25f;
void writeRatioMap(const std::string& path, const RgbImage& test, const RgbImage& reference);

}  // namespace ivgi::image

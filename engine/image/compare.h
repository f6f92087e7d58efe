#pragma once
// Comparison of two multi-layer EXRs layer by layer, as golden-image tests need it: a pixel fails
// when any channel of a layer differs by more than the layer's threshold, and a layer fails when
// more than a given fraction of its pixels fail.
#include <string>
#include <vector>

namespace ivgi::image {

struct LayerTolerance {
  std::string layer;         // "" for R,G,B; "A"; "Z"; "albedo"; "N"; "emission"
  float relativeThreshold;   // per-pixel threshold as a fraction of the reference's largest |value| (at least 1 for
                             // colours)
  float maxFailingFraction;  // of all pixels
  // HDR radiance: the threshold is a fraction of each reference pixel's own largest |value| plus 5 %
  // of the layer's 99th percentile (so that black is not held to zero), not of the layer's largest
  // value (a light 100 times brighter than the walls would hide any change of their light).
  bool perPixel = false;
};

struct LayerDifference {
  std::string layer;
  float threshold = 0;  // the absolute per-pixel threshold used (perPixel: at a black pixel)
  float maxError = 0;
  double failingFraction = 0;
  double allowedFraction = 0;  // the tolerance's maxFailingFraction
  bool passed = true;
};

// Throws std::runtime_error if a file cannot be read, sizes differ, a layer is missing or holds a
// NaN or infinite value.
std::vector<LayerDifference> compareLayers(const std::string& test, const std::string& reference,
                                           const std::vector<LayerTolerance>& tolerances);

// The layers ivgi writes, by their names in compare's --layers: rgb (""), A, albedo, N, Z, emission.
const std::vector<std::string>& layerNames();
// One rule on each of `layers`: radiance (rgb) held to each pixel's own value, the others to their
// range, `tolerance` per pixel, at most `maxFailingFraction` of the pixels beyond it.
std::vector<LayerTolerance> pixelRule(const std::vector<std::string>& layers, float tolerance,
                                      float maxFailingFraction);
// Every layer with the tolerances ivgi's own golden tests use (`ivgi compare --golden`).
std::vector<LayerTolerance> goldenTolerances();

}  // namespace ivgi::image

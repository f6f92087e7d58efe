#pragma once
// Flicker, measured: how far a sequence's frame-to-frame change departs from a reference
// sequence's, where the scene's surfaces stay put in the image (pixels that a moving object
// covers or uncovers change abruptly in both and are left out).
#include <string>
#include <vector>

#include "engine/image/metrics.h"

namespace ivgi::image {

// Per pixel, 1 where what the reference frames `before` and `after` show differs (OpenEXR files as
// ivgi writes them: coverage A, depth Z or normal N changed by more than a percent or 8°, or
// nothing hit), dilated by a pixel. Throws std::runtime_error naming a file that cannot be read.
std::vector<uint8_t> surfacesMoved(const std::string& before, const std::string& after);

struct TemporalError {
  double sum = 0;     // Σ over pixels and channels of ((t₁ − t₀) − (r₁ − r₀))² / (r₁² + 0.01)
  size_t count = 0;   // pixel channels summed
  size_t pixels = 0;  // of all the pixels compared
  double relMse() const { return count ? sum / double(count) : 0.0; }
  TemporalError& operator+=(const TemporalError& o) {
    sum += o.sum, count += o.count, pixels += o.pixels;
    return *this;
  }
};

// The change from test0 to test1 against the change from ref0 to ref1 on the pixels `ignore` leaves
// (0), as relMSE does a frame. Throws std::invalid_argument on a size mismatch.
TemporalError temporalError(const RgbImage& test0, const RgbImage& test1, const RgbImage& ref0, const RgbImage& ref1,
                            const std::vector<uint8_t>& ignore);

}  // namespace ivgi::image

#pragma once
// The channels of a rendered frame and how they are written: linear OpenEXR with named layers, and a
// tone-mapped sRGB PNG for display. Every file is written under a temporary name and renamed.
#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace ivgi::image {

struct FrameChannels {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec4> radiance;           // rgb, a = coverage
  std::vector<glm::vec4> albedo;             // rgb
  std::vector<glm::vec4> normalDepth;        // world normal, w = depth along the view axis (0: background)
  std::vector<glm::vec4> emission;           // rgb
  std::vector<glm::vec4> roughnessMetallic;  // r: roughness, g: metallic (glTF's factors × texture)

  size_t bytes() const {
    return (radiance.size() + albedo.size() + normalDepth.size() + emission.size() + roughnessMetallic.size()) *
           sizeof(glm::vec4);
  }
};

// Replaces NaN/Inf by 0 (a solver bug must never reach a file); returns how many values it replaced.
size_t sanitize(FrameChannels& frame);

enum class ToneMap { Clamp, Aces };
struct DisplaySettings {
  ToneMap tonemap = ToneMap::Aces;
  float exposure = 0.0f;  // stops
};
// Throws SettingsError naming --exposure when it is not a finite number of stops within ±64.
void validate(const DisplaySettings& display);

// How a frame was made, kept in its EXR header: the method (iv, ar, pt) and the samples that make a
// pixel (iv and ar: the supersampling's N×N; pt: its paths), so that a comparison can say what
// the two sides' pixels mean.
struct Provenance {
  std::string method;
  uint32_t samplesPerPixel = 0;  // 0: unknown
};
// What `path`'s header says; empty where it says nothing (another program's file).
Provenance readProvenance(const std::string& path);

// Channels R G B A, albedo.R/G/B, N.X/Y/Z, Z, emission.R/G/B, roughness, metallic, 32-bit float, ZIP
// compression.
void writeExr(const std::string& path, const FrameChannels& frame, const Provenance& provenance = {});
// radiance × 2^exposure, tone mapped, sRGB encoded, 8-bit RGB.
void writePng(const std::string& path, const FrameChannels& frame, const DisplaySettings& display);

// 8-bit RGB rows, top first.
void writeRgb8Png(const std::string& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb);

float toneMap(float linear, ToneMap mode);  // to [0, 1], before the sRGB curve

}  // namespace ivgi::image

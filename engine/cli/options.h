#pragma once
// Parsing and checking of the values users type: frame ranges, image sizes, output patterns.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/errors.h"

namespace ivgi::cli {

struct FrameRange {
  int first = 0, last = 0, step = 1;
  std::vector<int> frames() const;
};
// "A", "A-B" or "A-B:step"; throws SettingsError.
FrameRange parseFrameRange(const std::string& text);
// "WxH"; throws SettingsError.
void parseSize(const std::string& text, uint32_t& width, uint32_t& height);
// "exr,png" → {"exr", "png"}; throws SettingsError on anything else.
std::vector<std::string> parseFormats(const std::string& text);

// One of `count` shards of a render's frames, 0 ≤ index < count.
struct Shard {
  uint32_t index = 0, count = 1;
};
// "I/N", or "slurm": the task's place in its Slurm job array (SLURM_ARRAY_TASK_ID less
// SLURM_ARRAY_TASK_MIN, over SLURM_ARRAY_TASK_STEP) of SLURM_ARRAY_TASK_COUNT; throws SettingsError.
Shard parseShard(const std::string& text);
// The frames of `frames` that `shard` renders: of the runs of frames that share a chain
// (Solver::chainStart; by default each frame is its own), every count-th from its index on, so that a
// costly stretch of the animation is spread over all shards and no chain is split between two.
std::vector<int> shardFrames(
    const std::vector<int>& frames, const Shard& shard,
    const std::function<int(int)>& chainStart = [](int frame) { return frame; });

// Output pattern with a printf-style frame number (%d, %04d, …). The extension, if any, is
// replaced by each format's.
struct OutputPattern {
  explicit OutputPattern(const std::string& pattern);  // throws SettingsError
  std::string path(int frame, const std::string& format) const;
  std::string sidecar() const;  // the pattern without frame number and extension, + ".json"
  std::string directory() const;

 private:
  std::string prefix_, suffix_;  // around the %…d conversion, extension removed
  int width_ = 0;
  bool zeroPad_ = false;
  bool hasNumber_ = false;
};

}  // namespace ivgi::cli

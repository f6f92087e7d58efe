#pragma once
// The frames two image sequences hold, paired for comparison: two files, two folders (their .exr
// files, paired by name), or two printf-style patterns (e.g. out/f_%04d.exr, paired by number).
#include <string>
#include <vector>

namespace ivgi::cli {

struct FramePair {
  std::string name;             // the file name, or "frame N"
  std::string test, reference;  // empty where that side lacks the frame
};

// Every frame either side holds, in order. Throws SettingsError when a side does not exist or the
// two are not of one kind.
std::vector<FramePair> pairFrames(const std::string& test, const std::string& reference);

}  // namespace ivgi::cli

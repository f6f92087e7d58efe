#pragma once
// The progress line on stderr: units (frames, or rows of a path-traced frame) done / total, rate, ETA. Redrawn in place
// on a terminal; on a pipe or file, plain lines at most once a second and at the end.
#include <chrono>
#include <string>

namespace ivgi::cli {

class Progress {
 public:
  Progress(std::string label, size_t total, std::string unit = "frame");
  void advance(size_t count = 1, bool skipped = false);  // units done (skipped ones do not count for the rate)
  void finish();

 private:
  void draw();
  std::string label_, unit_;
  size_t total_, done_ = 0, rendered_ = 0, drawnDone_ = 0;
  bool terminal_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
};

}  // namespace ivgi::cli

#pragma once
// The progress line on stderr: frames done / total, frames per second, ETA. Redrawn in place on a
// terminal; on a pipe or file, plain lines at most once a second and at the end.
#include <chrono>
#include <string>

namespace ivgi::cli {

class Progress {
 public:
  Progress(std::string label, size_t total);
  void advance(size_t skipped = 0);  // one more frame done (or skipped, which does not count for fps)
  void finish();

 private:
  void draw();
  std::string label_;
  size_t total_, done_ = 0, rendered_ = 0, drawnDone_ = 0;
  bool terminal_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
};

}  // namespace ivgi::cli

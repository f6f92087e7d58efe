#pragma once
// A render's frames put on disk: each frame's images written on a thread of their own while the
// next frames render, and its record added to the sidecar, in order, once they are in place (a run
// killed later keeps it).
#include <chrono>
#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <string>
#include <utility>
#include <vector>

#include "engine/cli/sidecar.h"
#include "engine/gi/frame_renderer.h"

namespace ivgi::cli {

class FrameWriter {
 public:
  // Writes a frame's channels to its paths.
  using WriteImages = std::function<void(const std::vector<std::string>& paths, const image::FrameChannels&)>;

  // `writeAhead`: the frames still being written while the next one renders (0: each frame is on
  // disk before the next begins); those in flight hold at most about kWritingBytes, or one frame.
  // `recording`: called as each frame's record joins the sidecar, before the sidecar is written.
  FrameWriter(Sidecar& sidecar, size_t writeAhead, WriteImages writeImages, std::function<void()> recording);
  // Waits for the frames still being written and records them, up to one whose writing failed.
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  // `result` of `frame` at `time`, rendered from `started` on, to `paths`.
  void add(int frame, double time, std::vector<std::string> paths, gi::FrameResult result,
           std::chrono::steady_clock::time_point started);
  // Waits for every frame being written and records it; a writing error is thrown here.
  void finish();

  static constexpr size_t kWritingBytes = size_t(256) << 20;

 private:
  struct Writing {
    int frame;
    double time;
    std::vector<std::pair<std::string, double>> passMs, solverFigures;
    std::vector<std::string> paths;
    std::future<double> wallMs;  // from the frame's start until its last image was renamed into place
  };
  void recordOldest();

  Sidecar& sidecar_;
  size_t writeAhead_;
  WriteImages writeImages_;
  std::function<void()> recording_;
  std::deque<Writing> writing_;
};

}  // namespace ivgi::cli

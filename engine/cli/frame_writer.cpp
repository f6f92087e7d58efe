#include "engine/cli/frame_writer.h"

namespace ivgi::cli {

FrameWriter::FrameWriter(Sidecar& sidecar, size_t writeAhead, WriteImages writeImages, std::function<void()> recording)
    : sidecar_(sidecar),
      writeAhead_(writeAhead),
      writeImages_(std::move(writeImages)),
      recording_(std::move(recording)) {}

FrameWriter::~FrameWriter() {
  try {
    finish();
  } catch (...) {  // the error that ended the run is already on its way
  }
}

void FrameWriter::add(int frame, double time, std::vector<std::string> paths, gi::FrameResult result,
                      std::chrono::steady_clock::time_point started) {
  while (!writing_.empty() &&
         (writing_.size() >= writeAhead_ || (writing_.size() + 1) * result.channels.bytes() > kWritingBytes))
    recordOldest();
  std::vector<std::pair<std::string, double>> passMs;
  for (const auto& p : result.passTimes) passMs.emplace_back(p.pass, p.ms);
  auto images = [this, paths, started, channels = std::move(result.channels)] {
    writeImages_(paths, channels);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  };
  // Written in turn, the images are written here, as the record asks for them.
  const auto launch = writeAhead_ == 0 ? std::launch::deferred : std::launch::async;
  writing_.push_back({frame, time, std::move(passMs), std::move(result.solverFigures), std::move(paths),
                      std::async(launch, std::move(images))});
  if (writeAhead_ == 0) recordOldest();
}

void FrameWriter::finish() {
  while (!writing_.empty()) recordOldest();
}

void FrameWriter::recordOldest() {
  Writing w = std::move(writing_.front());
  writing_.pop_front();
  sidecar_.addFrame(w.frame, w.time, w.passMs, w.wallMs.get(), w.paths, w.solverFigures);
  if (recording_) recording_();
  sidecar_.write();
}

}  // namespace ivgi::cli

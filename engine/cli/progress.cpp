#include "engine/cli/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace ivgi::cli {

Progress::Progress(std::string label, size_t total, std::string unit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      terminal_(isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {}

void Progress::advance(size_t count, bool skipped) {
  done_ += count;
  if (!skipped) rendered_ += count;
  auto now = std::chrono::steady_clock::now();
  if (terminal_ || now - lastDraw_ >= std::chrono::seconds(1) || done_ == total_) draw();
}

void Progress::finish() {
  if (terminal_)
    std::fputc('\n', stderr);
  else if (drawnDone_ != done_)
    draw();
  std::fflush(stderr);
}

void Progress::draw() {
  auto now = std::chrono::steady_clock::now();
  lastDraw_ = now;
  drawnDone_ = done_;
  double seconds = std::chrono::duration<double>(now - start_).count();
  double rate = seconds > 0 ? rendered_ / seconds : 0;
  size_t left = total_ - done_;
  char eta[32] = "--";
  if (rate > 0) {
    long s = std::lround(left / rate);
    std::snprintf(eta, sizeof eta, "%ld:%02ld", s / 60, s % 60);
  }
  std::fprintf(stderr, "%s%s: %s %zu/%zu (%3.0f%%), %.2f %ss/s, ETA %s%s", terminal_ ? "\r\033[K" : "", label_.c_str(),
               unit_.c_str(), done_, total_, total_ ? 100.0 * done_ / total_ : 100.0, rate, unit_.c_str(), eta,
               terminal_ ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace ivgi::cli

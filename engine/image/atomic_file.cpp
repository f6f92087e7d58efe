#include "engine/image/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace ivgi::image {

namespace {

// One slot per file being written at once; the signal handler only reads them.
constexpr int kSlots = 4;
char tempPaths[kSlots][4096];
std::atomic<bool> inUse[kSlots];

extern "C" void onInterrupt(int sig) {
  for (int i = 0; i < kSlots; ++i)
    if (inUse[i].load()) unlink(tempPaths[i]);
  _exit(128 + sig);
}

}  // namespace

void installInterruptCleanup() {
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  namespace fs = std::filesystem;
  fs::path final(path);
  fs::path temp = final.parent_path() / (".ivgi-tmp-" + std::to_string(getpid()) + "-" + final.filename().string());
  std::string tempName = temp.string();
  int slot = -1;
  for (int i = 0; i < kSlots && slot < 0; ++i) {
    bool expected = false;
    if (tempName.size() < sizeof(tempPaths[i]) && inUse[i].compare_exchange_strong(expected, true)) slot = i;
  }
  if (slot >= 0) std::strcpy(tempPaths[slot], tempName.c_str());
  auto release = [&] {
    if (slot >= 0) inUse[slot].store(false);
  };
  try {
    write(tempName);
    std::error_code ec;
    fs::rename(temp, final, ec);
    if (ec) throw std::runtime_error(path + ": cannot rename the finished file into place: " + ec.message());
  } catch (...) {
    std::error_code ignore;
    fs::remove(temp, ignore);
    release();
    throw;
  }
  release();
}

}  // namespace ivgi::image

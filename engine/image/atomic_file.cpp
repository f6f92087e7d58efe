#include "engine/image/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <vector>

namespace ivgi::image {

namespace {

namespace fs = std::filesystem;

// One slot per file being written (or run lock held) at once; the signal handler only reads them.
constexpr int kSlots = 8;
char tempPaths[kSlots][4096];
std::atomic<bool> inUse[kSlots];

extern "C" void onInterrupt(int sig) {
  for (int i = 0; i < kSlots; ++i)
    if (inUse[i].load()) unlink(tempPaths[i]);
  _exit(128 + sig);
}

int claimSlot(const std::string& path) {
  for (int i = 0; i < kSlots; ++i) {
    bool expected = false;
    if (path.size() < sizeof(tempPaths[i]) && inUse[i].compare_exchange_strong(expected, true)) {
      std::strcpy(tempPaths[i], path.c_str());
      return i;
    }
  }
  return -1;
}
void releaseSlot(int slot) {
  if (slot >= 0) inUse[slot].store(false);
}

// "HOST~PID": who writes a temporary or holds a run lock. Host names have no '~'.
const std::string& owner() {
  static const std::string self = [] {
    char host[256] = {};
    gethostname(host, sizeof host - 1);
    return std::string(host) + "~" + std::to_string(getpid());
  }();
  return self;
}
const std::string& hostName() {
  static const std::string host = owner().substr(0, owner().find('~'));
  return host;
}

constexpr const char* kTempPrefix = ".ivgi-tmp~";
constexpr const char* kLockPrefix = ".ivgi-run~";

// Whether the run `host~pid` is over: its lock file exists and nobody holds the lock, or it has no
// lock file and is a process of this host that no longer exists.
bool runIsOver(const fs::path& folder, const std::string& runOwner) {
  const fs::path lock = folder / (kLockPrefix + runOwner + ".lock");
  const int fd = open(lock.c_str(), O_RDWR | O_CLOEXEC);
  if (fd >= 0) {
    const bool over = flock(fd, LOCK_EX | LOCK_NB) == 0;
    close(fd);  // releases the lock if we took it
    return over;
  }
  const size_t tilde = runOwner.find('~');
  if (tilde == std::string::npos || runOwner.substr(0, tilde) != hostName()) return false;  // cannot tell: keep
  const pid_t pid = pid_t(std::atoll(runOwner.c_str() + tilde + 1));
  return pid > 0 && kill(pid, 0) != 0 && errno == ESRCH;
}

// Where writeAtomically writes `final` before renaming it.
fs::path temporaryOf(const fs::path& final) {
  return final.parent_path() / (kTempPrefix + owner() + "~" + final.filename().string());
}

}  // namespace

void prepareToWrite(const std::string& path) {
  const fs::path final(path);
  std::error_code ec;
  if (fs::is_directory(final, ec)) throw std::runtime_error(path + ": is a directory");
  if (const fs::path folder = final.parent_path(); !folder.empty()) {
    fs::create_directories(folder, ec);
    if (ec) throw std::runtime_error(path + ": cannot make its folder " + folder.string() + ": " + ec.message());
  }
  const fs::path temp = temporaryOf(final);
  const int fd = open(temp.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(path + ": cannot be written: " + std::strerror(errno));
  close(fd);
  unlink(temp.c_str());
}

void installInterruptCleanup() {
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const fs::path final(path), temp = temporaryOf(final);
  const std::string tempName = temp.string();
  const int slot = claimSlot(tempName);
  try {
    write(tempName);
    std::error_code ec;
    fs::rename(temp, final, ec);
    if (ec) throw std::runtime_error(path + ": cannot rename the finished file into place: " + ec.message());
  } catch (...) {
    std::error_code ignore;
    fs::remove(temp, ignore);
    releaseSlot(slot);
    throw;
  }
  releaseSlot(slot);
}

RunLock::RunLock(const std::string& folder) : path_((fs::path(folder) / (kLockPrefix + owner() + ".lock")).string()) {
  fd_ = open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0 || flock(fd_, LOCK_EX | LOCK_NB) != 0)
    throw std::runtime_error(path_ + ": cannot lock: " + std::strerror(errno));
  slot_ = claimSlot(path_);
}

RunLock::~RunLock() {
  unlink(path_.c_str());
  if (fd_ >= 0) close(fd_);
  releaseSlot(slot_);
}

size_t removeDeadTemporaries(const std::string& folder) {
  // Whose each temporary and lock file is, judged before anything is removed.
  std::vector<std::pair<fs::path, std::string>> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(kTempPrefix, 0) == 0) {  // .ivgi-tmp~HOST~PID~NAME
      const size_t start = std::strlen(kTempPrefix), pid = name.find('~', start);
      const size_t end = pid == std::string::npos ? pid : name.find('~', pid + 1);
      if (end != std::string::npos) files.emplace_back(entry.path(), name.substr(start, end - start));
    } else if (name.rfind(kLockPrefix, 0) == 0 && name.ends_with(".lock")) {
      const size_t start = std::strlen(kLockPrefix);
      files.emplace_back(entry.path(), name.substr(start, name.size() - start - std::strlen(".lock")));
    } else if (name.rfind(".ivgi-tmp-", 0) == 0) {  // .ivgi-tmp-PID-NAME, written by ivgi before run locks
      const size_t end = name.find('-', std::strlen(".ivgi-tmp-"));
      if (end != std::string::npos)
        files.emplace_back(entry.path(),
                           hostName() + "~" + name.substr(std::strlen(".ivgi-tmp-"), end - std::strlen(".ivgi-tmp-")));
    }
  }
  std::map<std::string, bool> over;
  for (const auto& [path, runOwner] : files)
    if (!over.count(runOwner)) over[runOwner] = runOwner != owner() && runIsOver(fs::path(folder), runOwner);
  size_t removed = 0;
  for (const auto& [path, runOwner] : files) {
    std::error_code ignore;
    if (over[runOwner]) removed += fs::remove(path, ignore) ? 1 : 0;
  }
  return removed;
}

}  // namespace ivgi::image

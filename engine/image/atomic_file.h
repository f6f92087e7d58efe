#pragma once
// Nothing half-written ever carries a final name: a file is written to a hidden temporary name in
// the same folder, .ivgi-tmp~HOST~PID~NAME, and renamed when complete. On SIGINT/SIGTERM the
// temporaries in flight are removed; a process killed outright (kill -9, a node lost) leaves them,
// and a later run removes those of runs that are over (RunLock tells them from those still alive,
// on any host that shares the folder).
#include <functional>
#include <string>

namespace ivgi::image {

// Writes `path` through `write(tempPath)`; the temporary keeps the extension so that format
// detection by name still works. Throws std::runtime_error naming `path` on failure.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

// Makes `path`'s folder where it is missing and checks that the file can be written there, by
// creating and removing the temporary writeAtomically would write; throws std::runtime_error naming
// `path` and what stands in the way. For what a long run writes at its end, checked at its start.
void prepareToWrite(const std::string& path);

// Installs the SIGINT/SIGTERM handler that removes temporaries (and run locks) and exits with
// 128 + signal.
void installInterruptCleanup();

// While it lives, this process holds an exclusive lock on FOLDER/.ivgi-run~HOST~PID.lock: the
// sign, to any process on any host that shares the folder, that its temporaries there are in use.
class RunLock {
 public:
  explicit RunLock(const std::string& folder);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  std::string path_;
  int fd_ = -1;
  int slot_ = -1;  // for the interrupt handler, which removes the lock file too
};

// Removes from `folder` the temporaries of runs that are over, and their lock files: a run whose
// lock nobody holds, or, without a lock file, a process of this host that no longer exists. Never
// those of a run still alive; those of another host without a lock file are kept. Returns how many
// files it removed.
size_t removeDeadTemporaries(const std::string& folder);

}  // namespace ivgi::image

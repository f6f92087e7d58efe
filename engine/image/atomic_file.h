#pragma once
// Nothing half-written ever carries a final name: a file is written to a hidden temporary name in
// the same folder and renamed when complete. On SIGINT/SIGTERM the temporaries in flight are removed.
#include <functional>
#include <string>

namespace ivgi::image {

// Writes `path` through `write(tempPath)`; the temporary keeps the extension so that format
// detection by name still works. Throws std::runtime_error naming `path` on failure.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

// Installs the SIGINT/SIGTERM handler that removes temporaries and exits with 128 + signal.
void installInterruptCleanup();

}  // namespace ivgi::image

#pragma once
// Notes to the user on stderr that one command says once, however often its work meets them (a
// sweep or a bench makes many solvers): each distinct line once until the next command
// (cli::run starts one).
#include <cstdio>
#include <mutex>
#include <set>
#include <string>

namespace ivgi {

namespace detail {
struct Notes {
  std::mutex mutex;
  std::set<std::string> said;
};
inline Notes& notes() {
  static Notes n;
  return n;
}
}  // namespace detail

// Prints `line` (ending in a newline) unless this command said it already.
inline void noteOnce(const std::string& line) {
  detail::Notes& n = detail::notes();
  const std::lock_guard lock(n.mutex);
  if (n.said.insert(line).second) std::fputs(line.c_str(), stderr);
}

// A new command: every note may be said again.
inline void forgetNotes() {
  detail::Notes& n = detail::notes();
  const std::lock_guard lock(n.mutex);
  n.said.clear();
}

}  // namespace ivgi

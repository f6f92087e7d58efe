#pragma once
// Independent pieces of host work spread over the cores: the path tracer's rows, the loader's rays
// behind faces, the tables integrated at start-up.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace ivgi {

// Calls body(i) once for each i in [0, count), on up to `threads` threads (0: one per core), the
// calling thread among them; each thread takes the next i as it finishes one. `body` must be safe to
// run concurrently for different i. The first exception a call throws is rethrown here, after the
// calls already started have ended; no i is started after it.
template <class Body>
void parallelFor(size_t count, const Body& body, unsigned threads = 0) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first;
  std::mutex mutex;
  auto worker = [&] {
    for (size_t i; !failed.load(std::memory_order_relaxed) && (i = next.fetch_add(1)) < count;) {
      try {
        body(i);
      } catch (...) {
        const std::lock_guard lock(mutex);
        if (!first) first = std::current_exception();
        failed = true;
      }
    }
  };
  std::vector<std::thread> pool;
  for (size_t k = 1; k < std::min<size_t>(threads, count); ++k) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (first) std::rethrow_exception(first);
}

}  // namespace ivgi

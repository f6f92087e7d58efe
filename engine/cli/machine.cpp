#include "engine/cli/machine.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <thread>

namespace ivgi::cli {

namespace {

std::string lpThreads() {
  const char* t = std::getenv("LP_NUM_THREADS");
  return t ? t : "unset";
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  return "unknown CPU";
}

}  // namespace

nlohmann::json deviceJson(const vk::Context& ctx) {
  const char* t = std::getenv("LP_NUM_THREADS");
  return {{"name", ctx.info().name},
          {"type", ctx.info().type},
          {"driver", ctx.info().driverName},
          {"driverInfo", ctx.info().driverInfo},
          {"LP_NUM_THREADS", t ? nlohmann::json(t) : nlohmann::json(nullptr)}};
}

std::string deviceLine(const vk::Context& ctx) {
  return ctx.info().name + " (" + ctx.info().type + "), driver " + ctx.info().driverName + " " + ctx.info().driverInfo +
         ", LP_NUM_THREADS=" + lpThreads();
}

unsigned cpuThreads(unsigned requested) {
  return requested ? requested : std::max(1u, std::thread::hardware_concurrency());
}

nlohmann::json cpuJson(unsigned requestedThreads) {
  return {{"name", cpuModel()}, {"type", "cpu"}, {"driver", "Embree 3"}, {"threads", cpuThreads(requestedThreads)}};
}

std::string cpuLine(unsigned requestedThreads) {
  return cpuModel() + ", " + std::to_string(cpuThreads(requestedThreads)) + " threads (Embree 3)";
}

double hostPeakMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace ivgi::cli

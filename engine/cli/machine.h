#pragma once
// What a measurement ran on, for the sidecars and the printed reports: the Vulkan device and driver
// with LP_NUM_THREADS, or the CPU and thread count of the path tracer.
#include <nlohmann/json.hpp>

#include <string>

#include "engine/vk/context.h"

namespace ivgi::cli {

nlohmann::json deviceJson(const vk::Context& ctx);
std::string deviceLine(const vk::Context& ctx);  // "NAME (TYPE), driver D INFO, LP_NUM_THREADS=N"

unsigned cpuThreads(unsigned requested);  // 0: every core
nlohmann::json cpuJson(unsigned requestedThreads);
std::string cpuLine(unsigned requestedThreads);  // "CPU MODEL, N threads"

// The most resident host memory this process has held so far, in MiB (getrusage's ru_maxrss): a
// frame's record takes it after the frame, so it covers the scene's set-up and every frame before.
double hostPeakMiB();

}  // namespace ivgi::cli

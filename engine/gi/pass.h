#pragma once
// What every pass record uses: its program from the embedded shaders, timestamps around it, and
// the walk over the hierarchy's levels that refit and pull-up dispatch one level at a time.
#include <string>

#include "engine/gi/hierarchy.h"
#include "engine/vk/program.h"
#include "engine/vk/timer.h"
#include "shaders/registry.h"

namespace ivgi::gi {

// The program of shaders/NAME.comp.
inline vk::Program shaderProgram(const vk::Context& ctx, const std::string& name,
                                 const vk::Specialization& specialization = {}) {
  return vk::Program(ctx, name, shaderCode(name), specialization);
}

// Records one timed pass: timestamps around `body`, then a barrier that publishes its writes.
template <class Body>
void timedPass(VkCommandBuffer cmd, vk::PassTimer& timer, const char* name, Body&& body) {
  timer.begin(cmd, name);
  body();
  timer.end(cmd);
  vk::barrier(cmd);
}

// The nodes of the trees' levels in batches of `perBatch` levels, deepest first.
inline std::vector<gpu::LevelPush> levelBatchesBottomUp(const Hierarchy& h, uint32_t perBatch = 1) {
  std::vector<gpu::LevelPush> batches;
  const auto& levels = h.levelStart;
  for (size_t end = levels.size() - 1; end > 0;) {
    const size_t first = end > perBatch ? end - perBatch : 0;
    batches.push_back({levels[first], levels[end] - levels[first]});
    end = first;
  }
  return batches;
}

// `body(level)` for each level of the trees (or batch of `perBatch` levels), deepest first, with a
// barrier after each.
template <class Body>
void forEachLevelBottomUp(VkCommandBuffer cmd, const Hierarchy& h, Body&& body, uint32_t perBatch = 1) {
  for (const gpu::LevelPush& level : levelBatchesBottomUp(h, perBatch)) {
    body(level);
    vk::barrier(cmd);
  }
}

}  // namespace ivgi::gi

#pragma once
// What every pass record uses: its program from the embedded shaders, timestamps around it, and
// the hierarchy's levels, deepest first.
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

// The nodes of each of the trees' levels, deepest first.
inline std::vector<gpu::LevelPush> levelsBottomUp(const Hierarchy& h) {
  std::vector<gpu::LevelPush> levels;
  for (size_t end = h.levelStart.size() - 1; end > 0; --end)
    levels.push_back({h.levelStart[end - 1], h.levelStart[end] - h.levelStart[end - 1]});
  return levels;
}

}  // namespace ivgi::gi

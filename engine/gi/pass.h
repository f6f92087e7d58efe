#pragma once
// What every pass record uses: its program from the embedded shaders, timestamps around it, and
// the hierarchy's levels, deepest first.
#include <string>

#include "engine/gi/hierarchy.h"
#include "engine/vk/program.h"
#include "engine/vk/timer.h"
#include "shaders/registry.h"

namespace ivgi::gi {

// The program of the embedded shader NAME (shaders/…/NAME.comp).
inline vk::Program shaderProgram(const vk::Context& ctx, const std::string& name,
                                 const vk::Specialization& specialization = {}) {
  return vk::Program(ctx, name, shaderCode(name), specialization);
}

// Records one timed pass: timestamps around `body`, whose dispatches and transfers each end with
// their barrier (engine/vk/program.h).
template <class Body>
void timedPass(VkCommandBuffer cmd, vk::PassTimer& timer, const char* name, Body&& body) {
  timer.begin(cmd, name);
  body();
  timer.end(cmd);
}

// A run of consecutive nodes: one level of the trees, or of their inner nodes.
struct NodeRange {
  uint32_t first, count;
};

// The nodes of each of the trees' levels, deepest first.
inline std::vector<NodeRange> levelsBottomUp(const Hierarchy& h) {
  std::vector<NodeRange> levels;
  for (size_t end = h.levelStart.size() - 1; end > 0; --end)
    levels.push_back({h.levelStart[end - 1], h.levelStart[end] - h.levelStart[end - 1]});
  return levels;
}

}  // namespace ivgi::gi

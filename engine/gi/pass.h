#pragma once
// Records one timed pass: timestamps around `body`, then a barrier that publishes its writes.
#include "engine/vk/program.h"
#include "engine/vk/timer.h"

namespace ivgi::gi {

template <class Body>
void timedPass(VkCommandBuffer cmd, vk::PassTimer& timer, const char* name, Body&& body) {
  timer.begin(cmd, name);
  body();
  timer.end(cmd);
  vk::barrier(cmd);
}

}  // namespace ivgi::gi

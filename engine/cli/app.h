#pragma once
// The command line: its options, and the subcommand they name run to its exit status.
#include <string>
#include <vector>

#include "engine/vk/context.h"

namespace ivgi::cli {

// Runs the command line `args` (args[0]: the program's name) and returns the exit status; errors are
// one line on stderr. `device`, where given, is lent to the commands that run on the device
// default one (no --device): a program running many command lines keeps one device and its
// compiled pipelines.
int run(const std::vector<std::string>& args, vk::Context* device = nullptr);

}  // namespace ivgi::cli

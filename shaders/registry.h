#pragma once
// The SPIR-V of shaders/NAME.comp, compiled at build time and embedded in the binary
// (cmake/Shaders.cmake), so that ivgi finds its shaders from any folder.
#include <cstdint>
#include <span>
#include <string>

namespace ivgi {

// Throws std::runtime_error for a name no shader has.
std::span<const uint32_t> shaderCode(const std::string& name);

}  // namespace ivgi

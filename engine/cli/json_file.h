#pragma once
// JSON results written whole or not at all (through a temporary name).
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "engine/image/atomic_file.h"

namespace ivgi::cli {

inline void writeJson(const std::string& path, const nlohmann::json& j) {
  image::writeAtomically(path, [&](const std::string& temp) {
    std::ofstream out(temp);
    out << j.dump(2) << "\n";
    if (!out) throw std::runtime_error(path + ": cannot write");
  });
}

}  // namespace ivgi::cli

// libFuzzer target: a glTF file (.gltf text or .glb binary, told apart by its magic) through the
// loader and the scene build (geometry, tessellation at the default 16, surfels). A refusal
// (LoadError, SettingsError) is an answer; any other exception, a crash, a leak or a sanitizer's
// report is a finding. Built and run by tools/fuzz.sh.
#include <unistd.h>
#include <cstdint>
#include <fstream>
#include <string>

#include "engine/core/errors.h"
#include "engine/scene/geometry.h"
#include "engine/scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The loader reads files (a .gltf names its buffers beside it): the input goes to a file of this
  // process's own.
  static const std::string path = "/tmp/ivgi-fuzz-" + std::to_string(getpid()) + ".gltf";
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  try {
    const ivgi::scene::Scene scene = ivgi::scene::loadGltf(path);
    ivgi::scene::buildGeometry(scene, 16);
  } catch (const ivgi::scene::LoadError&) {
  } catch (const ivgi::SettingsError&) {
  }
  return 0;
}

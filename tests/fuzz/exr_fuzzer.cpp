// libFuzzer target: an EXR file through the readers behind `--env` (an equirectangular environment)
// and `ivgi compare` (every layer, against itself). A refusal (LoadError, compare's runtime_error)
// is an answer; a crash, a leak or a sanitizer's report is a finding. Built and run by
// tools/fuzz.sh.
#include <unistd.h>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>

#include "engine/image/compare.h"
#include "engine/scene/environment.h"
#include "engine/scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/ivgi-fuzz-" + std::to_string(getpid()) + ".exr";
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  try {
    const auto sky = ivgi::scene::Environment::parse(path);
    sky.bins(4);
    sky.sampleDirections(64);
  } catch (const ivgi::scene::LoadError&) {
  }
  try {
    ivgi::image::compareLayers(path, path, ivgi::image::goldenTolerances());
  } catch (const std::runtime_error&) {
  }
  return 0;
}

#pragma once
// Reading an image file whole as 32-bit float, straight from the file. OpenImageIO's
// ImageBuf(path) reads through its shared ImageCache, which takes a file rewritten within the same
// second of modification time for the one it cached and reads the new pixels with the old header:
// a heap overflow where the new image is larger (found by tests/fuzz/exr_fuzzer).
#include <OpenImageIO/imagebuf.h>

#include <string>

namespace ivgi::image {

// Every channel of the first subimage of `path`, as float, with the file's channel names;
// `fileFormat`, where given, receives the format the file stores. Throws std::runtime_error
// "PATH: cannot read[ WHAT]: WHY" (`what`: "the mask", say).
OIIO::ImageBuf readFloatImage(const std::string& path, const std::string& what = "",
                              OIIO::TypeDesc* fileFormat = nullptr);

}  // namespace ivgi::image

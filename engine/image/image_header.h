#pragma once
// What an image file's first bytes say, read before any decoder sees it: which of the formats ivgi
// reads it is, and how many pixels a PNG or JPEG declares. The decoders allocate what a header
// declares, and a few hostile bytes can declare gigabytes.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace ivgi::image {

enum class ImageFormat { Unknown, OpenExr, Png, Jpeg };

// The format by its magic number (the first four bytes are enough).
ImageFormat formatOf(std::span<const unsigned char> bytes);

struct DeclaredSize {
  uint32_t width = 0, height = 0;
};

// The size a PNG's IHDR or a JPEG's start of frame declares, without decoding: stb_image cannot tell
// it past a gigabyte of pixels, and OpenImageIO's PNG reader has libpng print its complaints to
// stderr. nullopt where the bytes are neither, or end before the size.
std::optional<DeclaredSize> declaredSize(std::span<const unsigned char> bytes);

}  // namespace ivgi::image

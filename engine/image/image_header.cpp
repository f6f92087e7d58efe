#include "engine/image/image_header.h"

#include <algorithm>
#include <array>

namespace ivgi::image {

namespace {

bool startsWith(std::span<const unsigned char> bytes, std::span<const unsigned char> magic) {
  return bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin());
}

constexpr std::array<unsigned char, 4> kExrMagic = {0x76, 0x2f, 0x31, 0x01};
constexpr std::array<unsigned char, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::array<unsigned char, 3> kJpegStart = {0xFF, 0xD8, 0xFF};  // start of image, then a marker

uint32_t bigEndian(std::span<const unsigned char> bytes, size_t at, int count) {
  uint32_t v = 0;
  for (int k = 0; k < count; ++k) v = v << 8 | bytes[at + size_t(k)];
  return v;
}

}  // namespace

ImageFormat formatOf(std::span<const unsigned char> bytes) {
  if (startsWith(bytes, kExrMagic)) return ImageFormat::OpenExr;
  if (startsWith(bytes, std::span(kPngSignature).first(4))) return ImageFormat::Png;
  if (startsWith(bytes, kJpegStart)) return ImageFormat::Jpeg;
  return ImageFormat::Unknown;
}

std::optional<DeclaredSize> declaredSize(std::span<const unsigned char> bytes) {
  const size_t size = bytes.size();
  const unsigned char ihdr[] = {'I', 'H', 'D', 'R'};
  if (startsWith(bytes, kPngSignature) && size >= 24 && startsWith(bytes.subspan(12), ihdr))
    return DeclaredSize{bigEndian(bytes, 16, 4), bigEndian(bytes, 20, 4)};
  if (!startsWith(bytes, std::span(kJpegStart).first(2))) return std::nullopt;
  // JPEG: the segments after the start of image, each FF, its marker, and a length that counts
  // itself, up to a start of frame (C0 to CF but for C4, C8 and CC), which holds height and width.
  for (size_t at = 2; at + 4 <= size && bytes[at] == 0xFF;) {
    const unsigned marker = bytes[at + 1];
    if (marker == 0xFF) {  // fill bytes
      ++at;
      continue;
    }
    const bool frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame)
      return at + 9 <= size ? std::optional(DeclaredSize{bigEndian(bytes, at + 7, 2), bigEndian(bytes, at + 5, 2)})
                            : std::nullopt;
    at += 2 + bigEndian(bytes, at + 2, 2);
  }
  return std::nullopt;
}

}  // namespace ivgi::image

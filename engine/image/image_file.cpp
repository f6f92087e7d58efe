#include "engine/image/image_file.h"

#include "engine/image/image_header.h"

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace ivgi::image {

namespace {

// Why the file's header must not reach OpenImageIO, or "", from one read of its start:
// - Formats: ivgi reads images in OpenEXR, PNG and JPEG alone, told by their first bytes. OpenImageIO
//   would otherwise try every reader it has on a file its name's reader refuses, and some decode at
//   open (its WebP reader took 21 bytes for a 12143×8261 image and allocated 400 MB before it failed).
// - An EXR header's attributes (name, type, a 32-bit size, the value) each declare their value's
//   size, and OpenEXR 3.1 allocates a string attribute's declared size before reading it: a file of
//   a few hundred bytes can claim gigabytes. The headers are walked (every part's, for a multi-part
//   file) for an attribute's size that cannot be.
std::string headerProblem(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char start[8] = {};
  in.read(reinterpret_cast<char*>(start), 8);
  const ImageFormat format = formatOf(std::span<const unsigned char>(start, size_t(in.gcount())));
  if (format == ImageFormat::Unknown) return "not an OpenEXR, PNG or JPEG image";
  std::error_code ec;
  const uint64_t fileSize = std::filesystem::file_size(path, ec);
  if (format != ImageFormat::OpenExr || !in || ec) return "";  // OpenEXR's reader judges a short one
  const bool multiPart = (start[5] & 0x10) != 0;               // version field bit 12
  auto readString = [&](std::string& s) {
    s.clear();
    for (char c; in.get(c);) {
      if (c == '\0') return true;
      if (s.size() == 255) return false;
      s += c;
    }
    return false;
  };
  for (bool headerEmpty = false; !headerEmpty;) {
    headerEmpty = true;
    for (std::string name, type; readString(name) && !name.empty(); headerEmpty = false) {
      unsigned char size[4];
      if (!readString(type) || !in.read(reinterpret_cast<char*>(size), 4)) return "";
      const int64_t declared =
          int32_t(uint32_t(size[0]) | uint32_t(size[1]) << 8 | uint32_t(size[2]) << 16 | uint32_t(size[3]) << 24);
      const int64_t left = int64_t(fileSize) - int64_t(in.tellg());
      if (declared < 0 || declared > left)
        return "EXR header attribute '" + name + "' (" + type + ") declares " + std::to_string(declared) +
               " bytes, and the file has " + std::to_string(left) + " left";
      in.seekg(declared, std::ios::cur);
    }
    if (!in || !multiPart) break;  // a single part's header ends at its first empty name
  }
  return "";
}

// The most values (pixels × channels) an image may declare: 2^28, a gigabyte as float. ivgi's own
// 4K EXR, with every layer, holds about 160 M.
constexpr uint64_t kMostValues = uint64_t(1) << 28;

}  // namespace

OIIO::ImageBuf readFloatImage(const std::string& path, const std::string& what, OIIO::TypeDesc* fileFormat) {
  auto fail = [&](const std::string& why) {
    throw std::runtime_error(path + ": cannot read" + (what.empty() ? "" : " " + what) + ": " + why);
  };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))  // a device or a pipe has no end to read to
    fail(std::filesystem::exists(path, ec) ? "not a regular file" : "no such file");
  if (const std::string problem = headerProblem(path); !problem.empty()) fail(problem);
  auto in = OIIO::ImageInput::open(path);
  if (!in) fail(OIIO::geterror());
  OIIO::ImageSpec spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.depth != 1 || spec.nchannels < 1) fail("not a 2D image");
  if (uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(spec.nchannels) > kMostValues)
    fail("it declares " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " pixels of " +
         std::to_string(spec.nchannels) + " channels, more than the 2^28 values ivgi reads");
  if (fileFormat) *fileFormat = spec.format;
  spec.set_format(OIIO::TypeDesc::FLOAT);
  spec.channelformats.clear();
  OIIO::ImageBuf image(spec);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.localpixels())) fail(in->geterror());
  return image;
}

}  // namespace ivgi::image

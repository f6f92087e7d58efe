#include "engine/image/image_file.h"

#include <OpenImageIO/imageio.h>

#include <stdexcept>

namespace ivgi::image {

OIIO::ImageBuf readFloatImage(const std::string& path, const std::string& what, OIIO::TypeDesc* fileFormat) {
  auto fail = [&](const std::string& why) {
    throw std::runtime_error(path + ": cannot read" + (what.empty() ? "" : " " + what) + ": " + why);
  };
  auto in = OIIO::ImageInput::open(path);
  if (!in) fail(OIIO::geterror());
  OIIO::ImageSpec spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.depth != 1 || spec.nchannels < 1) fail("not a 2D image");
  if (fileFormat) *fileFormat = spec.format;
  spec.set_format(OIIO::TypeDesc::FLOAT);
  spec.channelformats.clear();
  OIIO::ImageBuf image(spec);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.localpixels())) fail(in->geterror());
  return image;
}

}  // namespace ivgi::image

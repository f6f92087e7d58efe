// The image metrics on constructed pairs whose answers are known.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "engine/image/frame_image.h"
#include "engine/image/image_file.h"
#include "engine/image/metrics.h"
#include "tests/test_support.h"

using namespace ivgi;

namespace {

image::RgbImage uniform(uint32_t w, uint32_t h, glm::vec3 c) {
  return {w, h, std::vector<glm::vec3>(size_t(w) * h, c)};
}

double meanFlip(const image::RgbImage& a, const image::RgbImage& b) {
  auto map = image::flipErrorMap(a, b);
  double s = 0;
  for (float v : map) s += v;
  return s / double(map.size());
}

// A grey image with a bright square in the middle: edges for the feature pipeline.
image::RgbImage squareImage(float background, float square, int offset = 0) {
  auto img = uniform(48, 48, glm::vec3(background));
  for (int y = 16; y < 32; ++y)
    for (int x = 16 + offset; x < 32 + offset; ++x) img.pixels[size_t(y) * 48 + x] = glm::vec3(square);
  return img;
}

}  // namespace

// Reference 1 everywhere, test 1.1: relMSE = 0.01/1.01, RMSE 0.1, PSNR 20 dB, max error 0.1.
TEST(Metrics, ConstantOffsetHasKnownErrors) {
  auto ref = uniform(16, 8, glm::vec3(1.0f)), test = uniform(16, 8, glm::vec3(1.1f));
  auto m = image::measureError(test, ref);
  EXPECT_NEAR(m.relMse, 0.01 / 1.01, 1e-6);
  EXPECT_NEAR(m.rmse, 0.1, 1e-6);
  EXPECT_NEAR(m.psnr, 20.0, 1e-4);
  EXPECT_NEAR(m.maxError, 0.1, 1e-6);
  EXPECT_EQ(m.pixels, 128u);
  // relMSE is relative: the same offset on a reference ten times brighter weighs 100× less.
  auto bright = image::measureError(uniform(16, 8, glm::vec3(10.1f)), uniform(16, 8, glm::vec3(10.0f)));
  EXPECT_NEAR(bright.relMse, 0.01 / 100.01, 1e-7);
}

TEST(Metrics, IdenticalImagesScoreZero) {
  auto img = squareImage(0.2f, 0.8f);
  auto m = image::measureError(img, img);
  EXPECT_EQ(m.relMse, 0.0);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_TRUE(std::isinf(m.psnr));
  EXPECT_EQ(m.flip, 0.0);
}

// Ignored pixels count for nothing: a wildly wrong half masked out leaves the other half's errors.
TEST(Metrics, MaskLeavesPixelsOut) {
  auto ref = uniform(8, 8, glm::vec3(1.0f)), test = uniform(8, 8, glm::vec3(1.1f));
  std::vector<uint8_t> ignore(64, 0);
  for (int i = 0; i < 32; ++i) test.pixels[i] = glm::vec3(50.0f), ignore[i] = 1;
  auto m = image::measureError(test, ref, ignore);
  EXPECT_EQ(m.pixels, 32u);
  EXPECT_NEAR(m.relMse, 0.01 / 1.01, 1e-6);
  EXPECT_NEAR(m.rmse, 0.1, 1e-5);
  EXPECT_NEAR(m.maxError, 0.1, 1e-5);
  EXPECT_THROW(image::measureError(test, ref, std::vector<uint8_t>(64, 1)), std::invalid_argument);
  EXPECT_THROW(image::measureError(uniform(8, 4, glm::vec3(1)), ref), std::invalid_argument);
}

// Uniform black against uniform white: no features, and the colour term follows from the paper's
// constants alone. CIELAB of white (100, 0, 0), of sRGB green (87.737, −86.185, 83.181) and blue
// (32.303, 79.197, −107.864); Hunt: a, b × L/100; HyAB(white, black) = 100;
// c_max = HyAB(green, blue)^0.7; error = p_t + (100^0.7 − p_c·c_max)/(c_max − p_c·c_max)·(1 − p_t).
TEST(Flip, BlackAgainstWhiteFollowsThePaper) {
  const double gL = 87.737, ga = -86.185 * gL / 100, gb = 83.181 * gL / 100, bL = 32.303, ba = 79.197 * bL / 100,
               bb = -107.864 * bL / 100;
  const double cmax = std::pow(std::abs(gL - bL) + std::hypot(ga - ba, gb - bb), 0.7), e = std::pow(100.0, 0.7);
  const double expected = 0.95 + (e - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
  double got = meanFlip(uniform(24, 24, glm::vec3(0.0f)), uniform(24, 24, glm::vec3(1.0f)));
  std::printf("[ flip ] black vs white: %.5f (from the paper's constants %.5f)\n", got, expected);
  EXPECT_NEAR(got, expected, 2e-3);
}

// Both pipelines are symmetric in the two images.
TEST(Flip, IsSymmetric) {
  auto a = squareImage(0.2f, 0.8f), b = squareImage(0.3f, 0.6f, 2);
  EXPECT_NEAR(meanFlip(a, b), meanFlip(b, a), 1e-6);
}

// Larger perturbations score higher: a brightness offset, noise, and a displaced edge.
TEST(Flip, GrowsWithThePerturbation) {
  auto ref = squareImage(0.3f, 0.7f);
  double last = 0;
  for (float d : {0.02f, 0.05f, 0.1f, 0.2f}) {
    double f = meanFlip(squareImage(0.3f + d, 0.7f + d), ref);
    EXPECT_GT(f, last) << "offset " << d;
    last = f;
  }
  last = 0;
  for (float sigma : {0.01f, 0.03f, 0.1f}) {
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, sigma);
    auto test = ref;
    for (auto& p : test.pixels) p = glm::clamp(p + glm::vec3(noise(rng)), 0.0f, 1.0f);
    double f = meanFlip(test, ref);
    EXPECT_GT(f, last) << "noise " << sigma;
    last = f;
  }
  last = 0;
  for (int shift : {1, 2, 4}) {
    double f = meanFlip(squareImage(0.3f, 0.7f, shift), ref);
    EXPECT_GT(f, last) << "shift " << shift;
    last = f;
  }
}

// Found by tests/fuzz/exr_fuzzer: an EXR rewritten within the same second at a larger size was read
// with the header OpenImageIO's ImageCache had kept of the first (a heap overflow, and the old
// size). Every reader (compare, the metrics, the temporal measure, --env, masks) reads the file as
// it is now.
TEST(ImageFiles, AFileRewrittenWithinTheSecondIsReadAsItIsNow) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("ivgi-rewritten-" + std::to_string(getpid()) + ".exr");
  auto frame = [](uint32_t w, uint32_t h, float value) {
    image::FrameChannels f{w, h, {}, {}, {}, {}, {}};
    for (auto* channel : {&f.radiance, &f.albedo, &f.normalDepth, &f.emission, &f.roughnessMetallic})
      channel->assign(size_t(w) * h, glm::vec4(value, value, value, 1.0f));
    return f;
  };
  image::writeExr(path.string(), frame(8, 6, 0.25f));
  EXPECT_EQ(image::readLinearRgb(path.string()).width, 8u);
  image::writeExr(path.string(), frame(40, 30, 0.5f));  // the same second, in all likelihood
  const image::RgbImage now = image::readLinearRgb(path.string());
  ASSERT_EQ(now.width, 40u);
  ASSERT_EQ(now.height, 30u);
  EXPECT_EQ(now.pixels.back(), glm::vec3(0.5f));
  const OIIO::ImageBuf all = image::readFloatImage(path.string());
  EXPECT_EQ(all.spec().width, 40);
  EXPECT_EQ(all.spec().nchannels, 16);
  std::filesystem::remove(path);
}

// An EXR whose string attribute declares more bytes than the file holds (its size field set to
// 10⁹, as the EXR fuzzer found) is refused in one line naming the attribute, before OpenEXR would
// allocate the declared size.
TEST(ImageFiles, AnExrAttributeLargerThanItsFileIsRefused) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("ivgi-attribute-" + std::to_string(getpid()) + ".exr");
  OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::FLOAT);
  spec.attribute("Software", "ivgi test");
  const float pixels[12] = {};
  {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out && out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels));
    out->close();
  }
  EXPECT_EQ(image::readFloatImage(path.string()).spec().width, 2);  // as written, it reads
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string key = std::string("Software") + '\0' + "string" + '\0';
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const uint32_t huge = 1000000000u;
  for (int k = 0; k < 4; ++k) bytes[at + key.size() + k] = char((huge >> (8 * k)) & 0xff);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  EXPECT_THAT([&] { image::readFloatImage(path.string()); },
              testing::ThrowsMessage<std::runtime_error>(testing::AllOf(
                  testing::HasSubstr(path.string() + ": cannot read: EXR header attribute 'Software'"),
                  testing::HasSubstr("declares 1000000000 bytes"), testing::Not(testing::HasSubstr("\n")))));
  std::filesystem::remove(path);
}

// Found by the EXR fuzzer (build-fuzz/oom-c013e586…): 21 bytes that OpenImageIO's WebP reader took
// for a 12143×8261 image, allocating 400 MB at open and 1.6 GB of floats after it, 2 GB before it
// failed. The readers take OpenEXR, PNG and JPEG alone, by their first bytes, and refuse an image
// that declares more than 2^28 values before allocating it.
TEST(ImageFiles, AnotherFormatOrAnImageDeclaringTooMuchIsRefusedBeforeItIsRead) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("ivgi-format-" + std::to_string(getpid()) + ".exr");
  const unsigned char found[21] = {0x2f, 0x6e, 0x2f, 0x11, 0x18, 0x23, 0x75, 0x31, 0x6c, 0x6c, 0x11,
                                   0x11, 0x11, 0x1b, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00};
  using test::bigEndian;
  auto crc32 = [](const std::string& data) {  // PNG's chunk CRC (libpng checks the header's)
    uint32_t c = 0xFFFFFFFFu;
    for (unsigned char byte : data) {
      c ^= byte;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return c ^ 0xFFFFFFFFu;
  };
  auto chunk = [&](const std::string& typeAndData) {
    return bigEndian(uint32_t(typeAndData.size() - 4)) + typeAndData + bigEndian(crc32(typeAndData));
  };
  // Its header, and an empty IDAT for libpng's reading of the header to stop at.
  const std::string png =
      "\x89PNG\r\n\x1a\n" +
      chunk("IHDR" + bigEndian(100000) + bigEndian(100000) + std::string("\x08\x02\x00\x00\x00", 5)) + chunk("IDAT") +
      chunk("IEND");
  for (const auto& [bytes, why] :
       {std::pair{std::string(reinterpret_cast<const char*>(found), sizeof found), "not an OpenEXR, PNG or JPEG image"},
        std::pair{png, "declares 100000x100000 pixels of 3 channels"}}) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    EXPECT_THAT([&] { image::readFloatImage(path.string()); },
                testing::ThrowsMessage<std::runtime_error>(testing::HasSubstr(why)));
  }
  std::filesystem::remove(path);
}

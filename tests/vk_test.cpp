// The device layer: programs whose layout mixes storage buffers and imageBuffers read the bytes the
// host wrote, whatever the view's format.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>

#include "engine/vk/program.h"
#include "shaders/interface.h"
#include "shaders/registry.h"
#include "tests/test_support.h"

namespace ivgi {
std::span<const uint32_t> testShaderCode(const std::string& name);
}

namespace ivgi {
namespace {

TEST(Program, ImageBuffersReadWhatTheHostWrote) {
  vk::Context& ctx = test::gpu();
  const uint32_t count = 96;  // vec4s; a multiple of 3 so that it is whole NodeStates too
  std::vector<float> data(4 * count);
  for (size_t i = 0; i < data.size(); ++i) data[i] = 0.25f * float(i) - 7.0f;
  vk::Buffer input = vk::makeBuffer(ctx, data), output(ctx, count * 4 * 16, vk::Memory::Host);
  vk::Program program(ctx, "texel_cases", testShaderCode("texel_cases"));
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    program.dispatchItems(
        cmd, count, {{"asVec4", input}, {"asUvec2", input}, {"asUint", input}, {"nodes", input}, {"results", output}},
        gpu::CountPush{.count = count});
  });
  auto got = output.read<float>(count * 16);
  for (uint32_t i = 0; i < count; ++i) {
    const float* r = &got[16 * i];
    for (int c = 0; c < 4; ++c) EXPECT_EQ(r[c], data[4 * i + c]) << "rgba32f element " << i;
    for (int c = 0; c < 2; ++c) EXPECT_EQ(r[4 + c], data[2 * i + c]) << "rg32ui element " << i;
    EXPECT_EQ(r[8], data[i]) << "r32ui element " << i;
    // NodeState: position and area, normal and cone, shape: one texel each.
    for (int c = 0; c < 4; ++c) EXPECT_EQ(r[12 + c], data[4 * i + c]) << "NodeState texel " << i;
  }
}

// A dispatch names each of the shader's bindings once: a name it lacks, one left out or one given
// twice is refused with the name, before anything is recorded.
TEST(Program, BindsEveryBindingByItsNameOnce) {
  vk::Context& ctx = test::gpu();
  vk::Buffer buffer(ctx, 1024, vk::Memory::Host);
  vk::Program program(ctx, "texel_cases", testShaderCode("texel_cases"));
  auto refusal = [&](vk::Bindings bindings) -> std::string {
    try {
      ctx.submitAndWait(
          [&](VkCommandBuffer cmd) { program.dispatchItems(cmd, 1, bindings, gpu::CountPush{.count = 1}); });
    } catch (const vk::VulkanError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(
      refusal({{"asVec4", buffer}, {"asUvec2", buffer}, {"asUint", buffer}, {"nodes", buffer}, {"results", buffer}}),
      "");
  EXPECT_NE(refusal({{"asVec4", buffer}, {"asUvec2", buffer}, {"asUint", buffer}, {"nodes", buffer}}).find("'results'"),
            std::string::npos);
  EXPECT_NE(refusal({{"asVec4", buffer},
                     {"asUvec2", buffer},
                     {"asUint", buffer},
                     {"nodes", buffer},
                     {"results", buffer},
                     {"output", buffer}})
                .find("no binding named 'output'"),
            std::string::npos);
  EXPECT_NE(
      refusal({{"asVec4", buffer}, {"asVec4", buffer}, {"asUint", buffer}, {"nodes", buffer}, {"results", buffer}})
          .find("twice"),
      std::string::npos);
  EXPECT_THROW(vk::Program(ctx, "texel_cases", testShaderCode("texel_cases"), {.constants = {{"kMissing", 1}}}),
               vk::VulkanError);
  EXPECT_THAT(
      [&] {
        vk::Program(ctx, "ar_local", shaderCode("ar_local"), {.constants = {{"kDirs", 4}, {"kDirs", 4}}});
      },
      testing::ThrowsMessage<vk::VulkanError>(testing::HasSubstr("'kDirs' given twice")));
}

}  // namespace
}  // namespace ivgi

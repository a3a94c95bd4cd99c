#include "gpu/buffer.h"
#include "gpu/commands.h"
#include "gpu/descriptors.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "gpu_fixture.h"

#include <gtest/gtest.h>

#include <cstring>
#include <numeric>
#include <random>

namespace stsv::test {
namespace {

using ResourcesTest = GpuTest;

std::vector<uint32_t> randomWords(std::size_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<uint32_t> words(count);
    for (uint32_t& w : words) w = uint32_t(rng());
    return words;
}

TEST_F(ResourcesTest, BufferRoundTripIsExact) {
    for (MemoryUsage memory :
         {MemoryUsage::DeviceLocal, MemoryUsage::HostToDevice, MemoryUsage::DeviceToHost}) {
        const std::vector<uint32_t> words = randomWords(1000, 7);
        Buffer buffer = createBuffer(device(), std::span<const uint32_t>(words),
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, memory);
        EXPECT_EQ(buffer.hostVisible(), memory != MemoryUsage::DeviceLocal);
        EXPECT_EQ(buffer.size(), words.size() * sizeof(uint32_t));
        EXPECT_EQ(buffer.download<uint32_t>(), words) << "memory usage " << int(memory);

        // Partial update at an offset, then partial read.
        const std::vector<uint32_t> patch = {1u, 2u, 3u};
        buffer.upload(std::span<const uint32_t>(patch), 10 * sizeof(uint32_t));
        std::vector<uint32_t> middle(5);
        buffer.download(middle.data(), middle.size() * sizeof(uint32_t), 9 * sizeof(uint32_t));
        EXPECT_EQ(middle, (std::vector<uint32_t>{words[9], 1u, 2u, 3u, words[13]}));
    }
}

TEST_F(ResourcesTest, BufferRejectsBadSizes) {
    EXPECT_THROW(Buffer(device(), 0, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::DeviceLocal),
                 UsageError);
    Buffer buffer(device(), 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::HostToDevice);
    uint32_t data[8] = {};
    EXPECT_THROW(buffer.upload(data, sizeof(data)), UsageError);
    EXPECT_THROW(buffer.download(data, 4, 16), UsageError);
    Buffer moved = std::move(buffer);
    EXPECT_EQ(moved.size(), 16u);
    // Using the moved-from buffer is the point of this check.
    EXPECT_THROW(buffer.upload(data, 4), UsageError); // NOLINT(bugprone-use-after-move)
}

TEST_F(ResourcesTest, GpuCopyBetweenBuffers) {
    // Device-side work in between: copy a → b on the GPU, read b back.
    const std::vector<uint32_t> words = randomWords(256, 11);
    Buffer a = createBuffer(device(), std::span<const uint32_t>(words), VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
    Buffer b(device(), a.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::DeviceToHost);
    submitOnce(device(), [&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, a.size()};
        vkCmdCopyBuffer(cmd, a.handle(), b.handle(), 1, &region);
        hostReadBarrier(cmd);
    });
    EXPECT_EQ(b.download<uint32_t>(), words);
}

TEST_F(ResourcesTest, ImageRoundTripIsExactForEveryFormat) {
    struct Case {
        VkFormat format;
        VkImageUsageFlags usage;
    };
    const Case cases[] = {
        {VK_FORMAT_R32G32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT},
        {VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT},
        {VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT},
        {VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT},
        {VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT},
    };
    const uint32_t width = 13, height = 7; // odd sizes: rows must stay tightly packed
    for (const Case& c : cases) {
        Image image(device(), {width, height, c.format, c.usage});
        const std::size_t bytes = std::size_t(width) * height * texelSize(c.format);
        ASSERT_EQ(image.byteSize(), bytes);
        std::vector<uint32_t> words = randomWords(bytes / 4, 3);
        if (c.format == VK_FORMAT_D32_SFLOAT || c.format == VK_FORMAT_R32_SFLOAT ||
            c.format == VK_FORMAT_R32G32B32A32_SFLOAT) {
            // Finite floats in [0, 1] (depth must be), compared bit for bit.
            for (uint32_t& w : words) {
                const float f = float(w % 1000003u) / 1000003.0f;
                std::memcpy(&w, &f, 4);
            }
        }
        image.upload(words.data(), bytes, VK_IMAGE_LAYOUT_GENERAL);
        EXPECT_EQ(image.layout(), VK_IMAGE_LAYOUT_GENERAL);
        const std::vector<uint32_t> back = image.readback<uint32_t>();
        EXPECT_EQ(back, words) << "format " << int(c.format);
    }
}

TEST_F(ResourcesTest, ImageClearAndReadbackRowOrder) {
    // Rows come back top (y = 0) first: write row index into each texel by clearing row by row.
    const uint32_t width = 5, height = 4;
    Image image(device(), {width, height, VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_STORAGE_BIT});
    std::vector<uint32_t> texels(std::size_t(width) * height);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) texels[y * width + x] = y * 100 + x;
    image.upload(texels.data(), texels.size() * 4, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_EQ(image.readback<uint32_t>(), texels);
}

TEST_F(ResourcesTest, ImageRejectsBadInput) {
    EXPECT_THROW(Image(device(), {0, 4, VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_STORAGE_BIT}), UsageError);
    EXPECT_THROW(Image(device(), {4, 4, VK_FORMAT_BC1_RGB_UNORM_BLOCK, VK_IMAGE_USAGE_SAMPLED_BIT}),
                 UsageError);
    Image image(device(), {4, 4, VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_STORAGE_BIT});
    uint32_t data[4] = {};
    EXPECT_THROW(image.upload(data, sizeof(data), VK_IMAGE_LAYOUT_GENERAL), UsageError);
}

TEST_F(ResourcesTest, ComputeReadsSampledTextureAndWritesStorageImage) {
    // texelFetch from an RGBA8 texture (combined image sampler) into an R32G32_UINT storage
    // image: the descriptor and layout paths an alpha-texture lookup and a bitmask clear use.
    const char* source = R"(#version 450
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D alphaTexture;
layout(binding = 1, rg32ui) uniform writeonly uimage2D result;
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    vec4 texel = texelFetch(alphaTexture, p, 0);
    imageStore(result, p, uvec4(uint(round(texel.a * 255.0)), uint(round(texel.r * 255.0)), 0u, 0u));
}
)";
    const uint32_t size = 8;
    DescriptorSetLayout setLayout(
        device(), {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_COMPUTE_BIT},
                   {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT}});
    PipelineLayout layout(device(), {setLayout.handle()});
    Pipeline pipeline = createComputePipeline(
        device(), layout, compiler().compileSource(source, VK_SHADER_STAGE_COMPUTE_BIT, "fetch.comp"));

    std::vector<uint8_t> rgba(std::size_t(size) * size * 4);
    for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t((i * 37u + 11u) % 256u);
    Image texture(device(), {size, size, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT});
    texture.upload(rgba.data(), rgba.size(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    Sampler sampler(device(), VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_REPEAT);
    Image result(device(), {size, size, VK_FORMAT_R32G32_UINT, VK_IMAGE_USAGE_STORAGE_BIT});
    DescriptorSet set(device(), setLayout);
    set.writeSampledImage(0, texture.view(), sampler.handle());
    set.writeStorageImage(1, result);
    submitOnce(device(), [&](VkCommandBuffer cmd) {
        result.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
        pipeline.bind(cmd);
        VkDescriptorSet handle = set.handle();
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.handle(), 0, 1, &handle, 0,
                                nullptr);
        vkCmdDispatch(cmd, 1, 1, 1);
    });
    const std::vector<uint32_t> words = result.readback<uint32_t>();
    for (uint32_t i = 0; i < size * size; ++i) {
        ASSERT_EQ(words[2 * std::size_t(i)], rgba[4 * std::size_t(i) + 3]) << "alpha of texel " << i;
        ASSERT_EQ(words[2 * std::size_t(i) + 1], rgba[4 * std::size_t(i) + 0]) << "red of texel " << i;
    }
}

} // namespace
} // namespace stsv::test

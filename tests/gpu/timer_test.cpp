#include "gpu/buffer.h"
#include "gpu/commands.h"
#include "gpu/descriptors.h"
#include "gpu/pipeline.h"
#include "gpu/timer.h"
#include "gpu_fixture.h"

#include <gtest/gtest.h>

#include <cmath>

namespace stsv::test {
namespace {

using TimerTest = GpuTest;

TEST_F(TimerTest, NamedScopesGiveNonNegativeMilliseconds) {
    // A small compute workload inside nested scopes, so there is something to time.
    const char* source = R"(#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Data { float values[]; };
void main() {
    float x = float(gl_GlobalInvocationID.x);
    for (int i = 0; i < 200; ++i) x = sin(x) * 1.0001 + 0.5;
    values[gl_GlobalInvocationID.x] = x;
}
)";
    DescriptorSetLayout setLayout(device(),
                                  {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_COMPUTE_BIT}});
    PipelineLayout layout(device(), {setLayout.handle()});
    Pipeline pipeline = createComputePipeline(
        device(), layout, compiler().compileSource(source, VK_SHADER_STAGE_COMPUTE_BIT, "timed.comp"));
    Buffer data(device(), 64 * 64 * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryUsage::DeviceLocal);
    DescriptorSet set(device(), setLayout);
    set.writeBuffer(0, data);

    GpuTimer timer(device(), 8);
    CommandBuffer cmdBuffer(device());
    for (int frame = 0; frame < 2; ++frame) { // reuse across frames
        VkCommandBuffer cmd = cmdBuffer.begin();
        timer.reset(cmd);
        timer.begin(cmd, "frame");
        timer.begin(cmd, "dispatch");
        pipeline.bind(cmd);
        VkDescriptorSet handle = set.handle();
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.handle(), 0, 1, &handle, 0,
                                nullptr);
        vkCmdDispatch(cmd, 64, 1, 1);
        timer.end(cmd);
        timer.begin(cmd, "empty");
        timer.end(cmd);
        timer.end(cmd);
        cmdBuffer.submitAndWait();

        const std::vector<GpuTiming> timings = timer.results();
        ASSERT_EQ(timings.size(), 3u);
        EXPECT_EQ(timings[0].name, "frame");
        EXPECT_EQ(timings[1].name, "dispatch");
        EXPECT_EQ(timings[2].name, "empty");
        for (const GpuTiming& t : timings) {
            EXPECT_TRUE(std::isfinite(t.milliseconds)) << t.name;
            EXPECT_GE(t.milliseconds, 0.0) << t.name;
            EXPECT_LT(t.milliseconds, 60'000.0) << t.name << ": absurd duration";
        }
        // The outer scope contains the inner ones (same timeline).
        EXPECT_GE(timings[0].milliseconds, timings[1].milliseconds);
    }
}

TEST_F(TimerTest, MisuseThrows) {
    GpuTimer timer(device(), 1);
    CommandBuffer cmdBuffer(device());
    VkCommandBuffer cmd = cmdBuffer.begin();
    timer.reset(cmd);
    EXPECT_THROW(timer.end(cmd), UsageError);
    timer.begin(cmd, "one");
    EXPECT_THROW(timer.begin(cmd, "two"), UsageError); // only one scope fits
    EXPECT_THROW(timer.results(), UsageError);         // "one" not ended
    timer.end(cmd);
    cmdBuffer.submitAndWait();
    EXPECT_EQ(timer.results().size(), 1u);
}

} // namespace
} // namespace stsv::test

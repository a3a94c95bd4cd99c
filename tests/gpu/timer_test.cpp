#include "gpu/buffer.h"
#include "gpu/commands.h"
#include "gpu/descriptors.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "gpu/rendering.h"
#include "gpu/timer.h"
#include "gpu_fixture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace stsv::test {
namespace {

using TimerTest = GpuTest;

TEST_F(TimerTest, ScopesMeasureTheirOwnPasses) {
    // A draw, then a compute dispatch, then an empty scope, inside one frame scope. Each
    // heavy scope must measure its own work: on lavapipe, without GpuTimer's waits, the
    // dispatch after a draw read ~0 ms and its time landed in the enclosing scope.
    const char* compute = R"(#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Data { float values[]; };
void main() {
    float x = float(gl_GlobalInvocationID.x);
    for (int i = 0; i < 2000; ++i) x = sin(x) * 1.0001 + 0.5;
    values[gl_GlobalInvocationID.x] = x;
}
)";
    const char* vert = R"(#version 450
void main() { gl_Position = vec4(float((gl_VertexIndex & 1) * 4 - 1), float((gl_VertexIndex & 2) * 2 - 1), 0.5, 1.0); }
)";
    const char* frag = R"(#version 450
layout(location = 0) out float value;
void main() {
    float x = gl_FragCoord.x;
    for (int i = 0; i < 1000; ++i) x = sin(x) * 1.0001 + 0.5;
    value = x;
}
)";
    DescriptorSetLayout setLayout(device(),
                                  {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_COMPUTE_BIT}});
    PipelineLayout computeLayout(device(), {setLayout.handle()});
    Pipeline computePipeline =
        createComputePipeline(device(), computeLayout,
                              compiler().compileSource(compute, VK_SHADER_STAGE_COMPUTE_BIT, "timed.comp"));
    PipelineLayout drawLayout(device(), {});
    GraphicsPipelineDesc desc;
    desc.stages = {
        {VK_SHADER_STAGE_VERTEX_BIT, compiler().compileSource(vert, VK_SHADER_STAGE_VERTEX_BIT, "t.vert")},
        {VK_SHADER_STAGE_FRAGMENT_BIT,
         compiler().compileSource(frag, VK_SHADER_STAGE_FRAGMENT_BIT, "t.frag")}};
    desc.colorFormats = {VK_FORMAT_R32_SFLOAT};
    Pipeline drawPipeline = createGraphicsPipeline(device(), drawLayout, desc);
    Image target(device(), {64, 64, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    Buffer data(device(), sizeof(float) * 64 * 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryUsage::DeviceLocal);
    DescriptorSet set(device(), setLayout);
    set.writeBuffer(0, data);

    GpuTimer timer(device(), 8);
    CommandBuffer cmdBuffer(device());
    for (int frame = 0; frame < 2; ++frame) { // the timer is reused across frames
        VkCommandBuffer cmd = cmdBuffer.begin();
        timer.reset(cmd);
        timer.begin(cmd, "frame");
        timer.begin(cmd, "draw");
        const ColorTarget color{&target, true, {}};
        beginRendering(cmd, std::span(&color, 1));
        drawPipeline.bind(cmd);
        vkCmdDraw(cmd, 3, 1, 0, 0);
        endRendering(cmd);
        timer.end(cmd);
        timer.begin(cmd, "dispatch");
        computePipeline.bind(cmd);
        VkDescriptorSet handle = set.handle();
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, computeLayout.handle(), 0, 1, &handle, 0,
                                nullptr);
        vkCmdDispatch(cmd, 64, 1, 1);
        timer.end(cmd);
        timer.begin(cmd, "empty");
        timer.end(cmd);
        timer.end(cmd);
        cmdBuffer.submitAndWait();

        const std::vector<GpuTiming> timings = timer.results();
        ASSERT_EQ(timings.size(), 4u);
        EXPECT_EQ(timings[0].name, "frame");
        EXPECT_EQ(timings[1].name, "draw");
        EXPECT_EQ(timings[2].name, "dispatch");
        EXPECT_EQ(timings[3].name, "empty");
        for (const GpuTiming& t : timings) {
            EXPECT_TRUE(std::isfinite(t.milliseconds)) << t.name;
            EXPECT_GE(t.milliseconds, 0.0) << t.name;
            EXPECT_LT(t.milliseconds, 60'000.0) << t.name << ": absurd duration";
        }
        const double frameMs = timings[0].milliseconds, drawMs = timings[1].milliseconds,
                     dispatchMs = timings[2].milliseconds, emptyMs = timings[3].milliseconds;
        std::cout << "timings: frame " << frameMs << " ms, draw " << drawMs << " ms, dispatch " << dispatchMs
                  << " ms, empty " << emptyMs << " ms\n";
        // Nested scopes on one timeline: the frame's begin and end timestamps enclose the
        // others, which follow one another. Scopes that did work read more than zero. How long
        // things take is stsv bench's business, not a unit test's.
        EXPECT_GE(frameMs, drawMs + dispatchMs + emptyMs);
        EXPECT_GT(drawMs, 0.0);
        EXPECT_GT(dispatchMs, 0.0);
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

// Barrier derivation of gpu/pass_recorder.h from declared accesses, without a device: default
// Images and Buffers serve as resource identities (the tracker makes no Vulkan calls). The
// Vulkan frame's passes check the same derivation under the synchronisation validation layer
// (tests/gpu_render).
#include "gpu/buffer.h"
#include "gpu/image.h"
#include "gpu/pass_recorder.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace stsv::test {
namespace {

constexpr VkPipelineStageFlags2 FRAGMENT = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

std::string describe(const std::vector<ResourceBarrier>& barriers) {
    std::string text;
    for (const ResourceBarrier& b : barriers)
        text += "\n  " + std::string(b.image ? "image" : "buffer") + " src " + std::to_string(b.srcStages) +
                "/" + std::to_string(b.srcAccess) + " dst " + std::to_string(b.dstStages) + "/" +
                std::to_string(b.dstAccess) + " layout " + std::to_string(b.oldLayout) + "->" +
                std::to_string(b.newLayout);
    return text;
}

TEST(PassRecorderTest, AttachmentWriteThenStorageReadTransitionsAndMakesTheWriteVisible) {
    // The G-buffer pass writes the position attachment; the STSV pass loads it in its fragment
    // shader as a storage image.
    Image position;
    Image depth;
    AccessTracker tracker;
    PassAccesses gbuffer;
    gbuffer.use(position, ResourceUse::colorAttachment()).use(depth, ResourceUse::depthAttachment());
    const std::vector<ResourceBarrier> first = tracker.enter(gbuffer.list());
    ASSERT_EQ(first.size(), 2u) << describe(first);
    // Fresh images: only the transitions out of UNDEFINED, after nothing.
    EXPECT_EQ(first[0].srcStages, VK_PIPELINE_STAGE_2_NONE);
    EXPECT_EQ(first[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(first[0].newLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(first[1].newLayout, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);

    PassAccesses stsv;
    stsv.use(position, ResourceUse::storageRead(FRAGMENT)).use(depth, ResourceUse::depthTest());
    const std::vector<ResourceBarrier> second = tracker.enter(stsv.list());
    ASSERT_EQ(second.size(), 2u) << describe(second);
    const ResourceBarrier& p = second[0];
    EXPECT_EQ(p.image, &position);
    EXPECT_EQ(p.srcStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_EQ(p.srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT); // only the write is made available
    EXPECT_EQ(p.dstStages, FRAGMENT);
    EXPECT_EQ(p.dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    EXPECT_EQ(p.oldLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(p.newLayout, VK_IMAGE_LAYOUT_GENERAL);
    const ResourceBarrier& d = second[1];
    EXPECT_EQ(d.image, &depth);
    EXPECT_EQ(d.srcStages,
              VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT);
    EXPECT_EQ(d.srcAccess, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    EXPECT_EQ(d.oldLayout, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(d.newLayout, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);

    // The resolve loads the position in a compute shader: after the attachment write and the
    // transition, made visible to compute now.
    PassAccesses resolve;
    resolve.use(position, ResourceUse::storageRead(COMPUTE));
    const std::vector<ResourceBarrier> third = tracker.enter(resolve.list());
    ASSERT_EQ(third.size(), 1u) << describe(third);
    EXPECT_EQ(third[0].srcStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | FRAGMENT);
    EXPECT_EQ(third[0].srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    EXPECT_EQ(third[0].dstStages, COMPUTE);
    EXPECT_EQ(third[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(third[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
}

TEST(PassRecorderTest, ConsecutiveReadersShareOneBarrier) {
    Image depth;
    AccessTracker tracker;
    PassAccesses write;
    write.use(depth, ResourceUse::depthAttachment());
    tracker.enter(write.list());
    PassAccesses test;
    test.use(depth, ResourceUse::depthTest());
    EXPECT_EQ(tracker.enter(test.list()).size(), 1u); // the transition to read-only
    const std::vector<ResourceBarrier> again = tracker.enter(test.list());
    EXPECT_TRUE(again.empty()) << describe(again);
}

TEST(PassRecorderTest, ReadInANewStageWaitsForTheWriteAgain) {
    // Storage atomics in a fragment shader, then loads in the fragment shader (one barrier), again
    // in the fragment shader (none), then in a compute shader (a second barrier: the first one's
    // destination scope did not include compute).
    Buffer counters;
    AccessTracker tracker;
    PassAccesses atomics;
    atomics.use(counters, ResourceUse::storageReadWrite(FRAGMENT));
    EXPECT_TRUE(tracker.enter(atomics.list()).empty()); // first write, no layout: nothing before it
    PassAccesses fragmentRead;
    fragmentRead.use(counters, ResourceUse::storageRead(FRAGMENT));
    const std::vector<ResourceBarrier> raw = tracker.enter(fragmentRead.list());
    ASSERT_EQ(raw.size(), 1u);
    EXPECT_EQ(raw[0].buffer, &counters);
    EXPECT_EQ(raw[0].srcStages, FRAGMENT);
    EXPECT_EQ(raw[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(raw[0].dstStages, FRAGMENT);
    EXPECT_TRUE(tracker.enter(fragmentRead.list()).empty());
    PassAccesses computeRead;
    computeRead.use(counters, ResourceUse::storageRead(COMPUTE));
    const std::vector<ResourceBarrier> rawCompute = tracker.enter(computeRead.list());
    ASSERT_EQ(rawCompute.size(), 1u);
    EXPECT_EQ(rawCompute[0].srcStages, FRAGMENT);
    EXPECT_EQ(rawCompute[0].dstStages, COMPUTE);
}

TEST(PassRecorderTest, WriteAfterReadsWaitsForEveryReader) {
    // The centre count image: atomics in a fragment shader, loads in the fold (compute), then
    // the next light's clear: it must wait for the fold's reads (WAR) and the atomics (WAW).
    Image center;
    AccessTracker tracker;
    PassAccesses count;
    count.use(center, ResourceUse::storageReadWrite(FRAGMENT));
    tracker.enter(count.list());
    PassAccesses fold;
    fold.use(center, ResourceUse::storageRead(COMPUTE));
    ASSERT_EQ(tracker.enter(fold.list()).size(), 1u);
    PassAccesses clear;
    clear.use(center, ResourceUse::transferWrite());
    const std::vector<ResourceBarrier> war = tracker.enter(clear.list());
    ASSERT_EQ(war.size(), 1u);
    EXPECT_EQ(war[0].srcStages, FRAGMENT | COMPUTE);
    EXPECT_EQ(war[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(war[0].dstStages, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT);
    EXPECT_EQ(war[0].dstAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    EXPECT_EQ(war[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(war[0].newLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
}

TEST(PassRecorderTest, HostReadEndsTheHazards) {
    Buffer staging;
    AccessTracker tracker;
    PassAccesses copy;
    copy.use(staging, ResourceUse::transferWrite());
    tracker.enter(copy.list());
    PassAccesses host;
    host.use(staging, ResourceUse::hostRead());
    const std::vector<ResourceBarrier> toHost = tracker.enter(host.list());
    ASSERT_EQ(toHost.size(), 1u);
    EXPECT_EQ(toHost[0].srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    EXPECT_EQ(toHost[0].dstStages, VK_PIPELINE_STAGE_2_HOST_BIT);
    EXPECT_EQ(toHost[0].dstAccess, VK_ACCESS_2_HOST_READ_BIT);
    // The next frame's copy is submitted after the host read: nothing to wait for.
    EXPECT_TRUE(tracker.enter(copy.list()).empty());
}

TEST(PassRecorderTest, DeclaringAResourceTwiceMergesTheUses) {
    Image mask;
    PassAccesses accesses;
    accesses.use(mask, ResourceUse::storageRead(FRAGMENT)).use(mask, ResourceUse::storageRead(COMPUTE));
    ASSERT_EQ(accesses.list().size(), 1u);
    EXPECT_EQ(accesses.list()[0].use.stages, FRAGMENT | COMPUTE);
    EXPECT_THROW(accesses.use(mask, ResourceUse::colorAttachment()), std::exception);
}

} // namespace
} // namespace stsv::test

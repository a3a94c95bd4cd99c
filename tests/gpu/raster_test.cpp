// Rasterisation mechanisms the STSV passes build on: integer attachments with logic-op OR
// (the light-sample bitmask, DESIGN §4.4), geometry shaders, mesh shaders.
#include "gpu/buffer.h"
#include "gpu/commands.h"
#include "gpu/descriptors.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "gpu/rendering.h"
#include "gpu_fixture.h"

#include <cstdlib>
#include <gtest/gtest.h>

#include <array>

namespace stsv::test {
namespace {

constexpr uint32_t SIDE = 16; // attachment width and height, pixels

/// A rectangle in pixels [x0, x1) × [y0, y1) (y down, as the Vulkan viewport) and the bits
/// its fragments write. Edges lie on pixel boundaries, so coverage of the pixel centres is
/// unambiguous.
struct Rect {
    uint32_t x0, y0, x1, y1;
    std::array<uint32_t, 2> bits;
    bool covers(uint32_t x, uint32_t y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    std::array<float, 4> ndc() const {
        auto toNdc = [](uint32_t v) { return -1.0f + 2.0f * float(v) / float(SIDE); };
        return {toNdc(x0), toNdc(y0), toNdc(x1), toNdc(y1)};
    }
};

struct RectPush {
    std::array<float, 4> ndc; ///< x0, y0, x1, y1 in normalised device coordinates
    std::array<uint32_t, 2> bits;
    float z = 0.5f; ///< clip-space depth of the rectangle (w = 1)
    uint32_t pad = 0;
};

const char* const RECT_VERT = R"(#version 450
layout(push_constant) uniform Push { vec4 rect; uvec2 bits; float z; } pc;
void main() {
    // Triangle strip over the rectangle: (x0,y0) (x1,y0) (x0,y1) (x1,y1).
    float x = (gl_VertexIndex & 1) != 0 ? pc.rect.z : pc.rect.x;
    float y = (gl_VertexIndex & 2) != 0 ? pc.rect.w : pc.rect.y;
    gl_Position = vec4(x, y, pc.z, 1.0);
}
)";

const char* const BITS_FRAG = R"(#version 450
layout(push_constant) uniform Push { vec4 rect; uvec2 bits; } pc;
layout(location = 0) out uvec2 outBits;
void main() { outBits = pc.bits; }
)";

/// Expected OR of the bits of every rect covering each pixel, computed on the CPU.
std::vector<uint32_t> expectedBits(const std::vector<Rect>& rects) {
    std::vector<uint32_t> expected(std::size_t(SIDE) * SIDE * 2, 0u);
    for (uint32_t y = 0; y < SIDE; ++y)
        for (uint32_t x = 0; x < SIDE; ++x)
            for (const Rect& r : rects)
                if (r.covers(x, y)) {
                    expected[(y * SIDE + x) * 2 + 0] |= r.bits[0];
                    expected[(y * SIDE + x) * 2 + 1] |= r.bits[1];
                }
    return expected;
}

void expectSameBits(const std::vector<uint32_t>& actual, const std::vector<uint32_t>& expected) {
    ASSERT_EQ(actual.size(), expected.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < actual.size(); ++i) {
        if (actual[i] == expected[i]) continue;
        if (++wrong <= 5)
            ADD_FAILURE() << "pixel (" << (i / 2) % SIDE << ", " << (i / 2) / SIDE << ") word " << i % 2
                          << ": got 0x" << std::hex << actual[i] << " expected 0x" << expected[i];
    }
    EXPECT_EQ(wrong, 0u);
}

using RasterTest = GpuTest;

TEST_F(RasterTest, LogicOpOrAccumulatesBitsInRG32UintAttachment) {
    PipelineLayout layout(device(), {}, sizeof(RectPush));
    GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT,
                    compiler().compileSource(RECT_VERT, VK_SHADER_STAGE_VERTEX_BIT, "rect.vert")},
                   {VK_SHADER_STAGE_FRAGMENT_BIT,
                    compiler().compileSource(BITS_FRAG, VK_SHADER_STAGE_FRAGMENT_BIT, "bits.frag")}};
    desc.colorFormats = {VK_FORMAT_R32G32_UINT};
    desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
    desc.logicOpEnable = true;
    desc.logicOp = VK_LOGIC_OP_OR;
    Pipeline pipeline = createGraphicsPipeline(device(), layout, desc);

    Image bits(device(), {SIDE, SIDE, VK_FORMAT_R32G32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    // Overlapping rects with disjoint and shared bits (bit 31 in both), and A drawn twice:
    // OR is idempotent, so the repeat must change nothing.
    const Rect a{0, 0, 10, 16, {0x00000001u, 0x80000000u}};
    const Rect b{6, 4, 16, 12, {0x00000100u, 0x80000001u}};
    const Rect c{2, 10, 5, 14, {0x40000000u, 0x00000000u}};
    const std::vector<Rect> rects = {a, b, c, a};
    submitOnce(device(), [&](VkCommandBuffer cmd) {
        const ColorTarget target{&bits, true, {}};
        beginRendering(cmd, std::span(&target, 1));
        pipeline.bind(cmd);
        for (const Rect& r : rects) {
            const RectPush push{r.ndc(), r.bits};
            layout.push(cmd, &push, sizeof(push));
            vkCmdDraw(cmd, 4, 1, 0, 0);
        }
        endRendering(cmd);
    });
    expectSameBits(bits.readback<uint32_t>(), expectedBits(rects));
}

TEST_F(RasterTest, LoadKeepsBitsOfAnEarlierPass) {
    // Two render passes on the same attachment, the second with LOAD: bits survive.
    PipelineLayout layout(device(), {}, sizeof(RectPush));
    GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT,
                    compiler().compileSource(RECT_VERT, VK_SHADER_STAGE_VERTEX_BIT, "rect.vert")},
                   {VK_SHADER_STAGE_FRAGMENT_BIT,
                    compiler().compileSource(BITS_FRAG, VK_SHADER_STAGE_FRAGMENT_BIT, "bits.frag")}};
    desc.colorFormats = {VK_FORMAT_R32G32_UINT};
    desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
    desc.logicOpEnable = true;
    desc.logicOp = VK_LOGIC_OP_OR;
    Pipeline pipeline = createGraphicsPipeline(device(), layout, desc);
    Image bits(device(), {SIDE, SIDE, VK_FORMAT_R32G32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    const Rect a{0, 0, 8, 8, {0x2u, 0x0u}};
    const Rect b{4, 4, 12, 12, {0x0u, 0x4u}};
    CommandBuffer cmdBuffer(device());
    for (int pass = 0; pass < 2; ++pass) {
        VkCommandBuffer cmd = cmdBuffer.begin();
        const ColorTarget target{&bits, pass == 0, {}};
        beginRendering(cmd, std::span(&target, 1));
        pipeline.bind(cmd);
        const Rect& r = pass == 0 ? a : b;
        const RectPush push{r.ndc(), r.bits};
        layout.push(cmd, &push, sizeof(push));
        vkCmdDraw(cmd, 4, 1, 0, 0);
        endRendering(cmd);
        cmdBuffer.submitAndWait();
    }
    expectSameBits(bits.readback<uint32_t>(), expectedBits({a, b}));
}

TEST_F(RasterTest, DepthClampedVolumeBehindVisiblePointPassesOnlyThere) {
    // The STSV pass's depth set-up (DESIGN §4.2): a G-buffer depth is written first; then a
    // far face at z = 1.5 (beyond the far plane, so clipped without depth clamp) is drawn
    // with depth clamp, test GREATER ("behind the visible point") and no depth write.
    ASSERT_TRUE(device().info().depthClamp);
    const std::vector<uint32_t> vert =
        compiler().compileSource(RECT_VERT, VK_SHADER_STAGE_VERTEX_BIT, "rect.vert");
    const std::vector<uint32_t> frag =
        compiler().compileSource(BITS_FRAG, VK_SHADER_STAGE_FRAGMENT_BIT, "bits.frag");
    PipelineLayout layout(device(), {}, sizeof(RectPush));
    GraphicsPipelineDesc gbufferDesc;
    gbufferDesc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, vert}, {VK_SHADER_STAGE_FRAGMENT_BIT, frag}};
    gbufferDesc.colorFormats = {VK_FORMAT_R32G32_UINT};
    gbufferDesc.depthFormat = VK_FORMAT_D32_SFLOAT;
    gbufferDesc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
    gbufferDesc.depthTest = true;
    gbufferDesc.depthWrite = true;
    gbufferDesc.depthCompare = VK_COMPARE_OP_LESS;
    Pipeline gbuffer = createGraphicsPipeline(device(), layout, gbufferDesc);
    GraphicsPipelineDesc volumeDesc = gbufferDesc;
    volumeDesc.depthWrite = false;
    volumeDesc.depthCompare = VK_COMPARE_OP_GREATER;
    volumeDesc.depthClamp = true;
    volumeDesc.logicOpEnable = true;
    volumeDesc.logicOp = VK_LOGIC_OP_OR;
    Pipeline volume = createGraphicsPipeline(device(), layout, volumeDesc);

    Image bits(device(), {SIDE, SIDE, VK_FORMAT_R32G32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    Image depth(device(), {SIDE, SIDE, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT});
    const Rect surface{0, 0, 9, SIDE, {0x0u, 0x0u}}; // visible points at depth 0.25 on the left
    const Rect far{2, 3, 14, 12, {0x8u, 0x100u}};    // the volume's far face, z = 1.5 → clamped to 1
    submitOnce(device(), [&](VkCommandBuffer cmd) {
        const ColorTarget target{&bits, true, {}};
        beginRendering(cmd, std::span(&target, 1), DepthTarget{&depth, true, 1.0f, false});
        gbuffer.bind(cmd);
        const RectPush surfacePush{surface.ndc(), surface.bits, 0.25f};
        layout.push(cmd, &surfacePush, sizeof(surfacePush));
        vkCmdDraw(cmd, 4, 1, 0, 0);
        endRendering(cmd);

        const ColorTarget load{&bits, false, {}};
        beginRendering(cmd, std::span(&load, 1), DepthTarget{&depth, false, 1.0f, true});
        volume.bind(cmd);
        const RectPush farPush{far.ndc(), far.bits, 1.5f};
        layout.push(cmd, &farPush, sizeof(farPush));
        vkCmdDraw(cmd, 4, 1, 0, 0);
        endRendering(cmd);
    });
    // Passes where the far face covers a visible point of the surface (1 > 0.25); fails on
    // the cleared background (1 > 1 is false).
    const Rect expectedArea{2, 3, 9, 12, far.bits};
    expectSameBits(bits.readback<uint32_t>(), expectedBits({expectedArea}));
    const std::vector<float> depths = depth.readback<float>();
    for (uint32_t y = 0; y < SIDE; ++y)
        for (uint32_t x = 0; x < SIDE; ++x)
            ASSERT_EQ(depths[y * SIDE + x], surface.covers(x, y) ? 0.25f : 1.0f)
                << "depth at " << x << "," << y;
}

TEST_F(RasterTest, FragmentAtomicsWithEarlyTestsCountOnlyPassingFragments) {
    // The depth-complexity counter mechanism (DESIGN §4.4): storage-buffer atomics in the
    // fragment shader, with early fragment tests so depth-failing fragments do not count.
    ASSERT_TRUE(device().info().fragmentStoresAndAtomics);
    const char* frag = R"(#version 450
layout(early_fragment_tests) in;
layout(std430, binding = 0) buffer Counters { uint counters[]; };
layout(push_constant) uniform Push { vec4 rect; uvec2 bits; float z; } pc;
void main() {
    uint pixel = uint(gl_FragCoord.y) * 16u + uint(gl_FragCoord.x);
    atomicAdd(counters[pixel], pc.bits.x);
}
)";
    DescriptorSetLayout setLayout(device(),
                                  {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT}});
    PipelineLayout layout(device(), {setLayout.handle()}, sizeof(RectPush));
    GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT,
                    compiler().compileSource(RECT_VERT, VK_SHADER_STAGE_VERTEX_BIT, "rect.vert")},
                   {VK_SHADER_STAGE_FRAGMENT_BIT,
                    compiler().compileSource(frag, VK_SHADER_STAGE_FRAGMENT_BIT, "count.frag")}};
    desc.depthFormat = VK_FORMAT_D32_SFLOAT;
    desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
    desc.depthTest = true;
    desc.depthCompare = VK_COMPARE_OP_GREATER;
    Pipeline pipeline = createGraphicsPipeline(device(), layout, desc);

    const std::vector<uint32_t> zeros(std::size_t(SIDE) * SIDE, 0u);
    Buffer counters =
        createBuffer(device(), std::span<const uint32_t>(zeros), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    DescriptorSet set(device(), setLayout);
    set.writeBuffer(0, counters);
    Image depth(device(), {SIDE, SIDE, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT});
    // Depth cleared to 0.5; rects at z 0.75 pass GREATER, rects at z 0.25 fail it. The
    // "count" of each rect goes in bits.x: 1 for passing rects, 100 for failing ones, so any
    // failing fragment that counted shows up as ≥ 100.
    const std::vector<std::pair<Rect, float>> rects = {{{0, 0, 10, 10, {1u, 0u}}, 0.75f},
                                                       {{5, 5, 16, 16, {1u, 0u}}, 0.75f},
                                                       {{0, 0, 16, 16, {100u, 0u}}, 0.25f},
                                                       {{3, 3, 8, 8, {1u, 0u}}, 0.75f}};
    submitOnce(device(), [&](VkCommandBuffer cmd) {
        beginRendering(cmd, {}, DepthTarget{&depth, true, 0.5f, false});
        pipeline.bind(cmd);
        VkDescriptorSet handle = set.handle();
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout.handle(), 0, 1, &handle, 0,
                                nullptr);
        for (const auto& [rect, z] : rects) {
            const RectPush push{rect.ndc(), rect.bits, z};
            layout.push(cmd, &push, sizeof(push));
            vkCmdDraw(cmd, 4, 1, 0, 0);
        }
        endRendering(cmd);
    });
    const std::vector<uint32_t> counts = counters.download<uint32_t>();
    for (uint32_t y = 0; y < SIDE; ++y)
        for (uint32_t x = 0; x < SIDE; ++x) {
            uint32_t expected = 0;
            for (const auto& [rect, z] : rects)
                if (z > 0.5f && rect.covers(x, y)) expected += rect.bits[0];
            ASSERT_EQ(counts[y * SIDE + x], expected) << "pixel " << x << "," << y;
        }
}

TEST_F(RasterTest, GeometryShaderPassesTrianglesThroughWithPrimitiveIds) {
    ASSERT_TRUE(device().info().geometryShader);
    const char* vert = R"(#version 450
layout(location = 0) in vec2 position;
void main() { gl_Position = vec4(position, 0.5, 1.0); }
)";
    const char* geom = R"(#version 450
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
layout(location = 0) flat out uint rectBit;
void main() {
    // Two triangles per rectangle: rectangle k = primitive / 2 writes bit k.
    for (int i = 0; i < 3; ++i) {
        gl_Position = gl_in[i].gl_Position;
        rectBit = 1u << uint(gl_PrimitiveIDIn / 2);
        EmitVertex();
    }
    EndPrimitive();
}
)";
    const char* frag = R"(#version 450
layout(location = 0) flat in uint rectBit;
layout(location = 0) out uvec2 outBits;
void main() { outBits = uvec2(rectBit, rectBit << 16); }
)";
    PipelineLayout layout(device(), {});
    GraphicsPipelineDesc desc;
    desc.stages = {
        {VK_SHADER_STAGE_VERTEX_BIT, compiler().compileSource(vert, VK_SHADER_STAGE_VERTEX_BIT, "p.vert")},
        {VK_SHADER_STAGE_GEOMETRY_BIT,
         compiler().compileSource(geom, VK_SHADER_STAGE_GEOMETRY_BIT, "pass.geom")},
        {VK_SHADER_STAGE_FRAGMENT_BIT,
         compiler().compileSource(frag, VK_SHADER_STAGE_FRAGMENT_BIT, "p.frag")}};
    desc.colorFormats = {VK_FORMAT_R32G32_UINT};
    desc.vertexBindings = {{0, 2 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX}};
    desc.vertexAttributes = {{0, 0, VK_FORMAT_R32G32_SFLOAT, 0}};
    desc.logicOpEnable = true;
    desc.logicOp = VK_LOGIC_OP_OR;
    Pipeline pipeline = createGraphicsPipeline(device(), layout, desc);

    const std::vector<Rect> rects = {{1, 2, 9, 13, {0x1u, 0x10000u}}, {5, 0, 15, 7, {0x2u, 0x20000u}}};
    std::vector<float> vertices;
    for (const Rect& r : rects) {
        const std::array<float, 4> q = r.ndc();
        for (float v : {q[0], q[1], q[2], q[1], q[0], q[3], q[2], q[1], q[2], q[3], q[0], q[3]})
            vertices.push_back(v);
    }
    Buffer vertexBuffer =
        createBuffer(device(), std::span<const float>(vertices), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    Image bits(device(), {SIDE, SIDE, VK_FORMAT_R32G32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    submitOnce(device(), [&](VkCommandBuffer cmd) {
        const ColorTarget target{&bits, true, {}};
        beginRendering(cmd, std::span(&target, 1));
        pipeline.bind(cmd);
        VkBuffer vb = vertexBuffer.handle();
        VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdDraw(cmd, uint32_t(vertices.size() / 2), 1, 0, 0);
        endRendering(cmd);
    });
    expectSameBits(bits.readback<uint32_t>(), expectedBits(rects));
}

TEST_F(RasterTest, MeshShaderDrawsRectangleOrSkips) {
    const char* mesh = R"(#version 450
#extension GL_EXT_mesh_shader : require
layout(local_size_x = 1) in;
layout(triangles, max_vertices = 4, max_primitives = 2) out;
layout(push_constant) uniform Push { vec4 rect; uvec2 bits; } pc;
void main() {
    SetMeshOutputsEXT(4, 2);
    for (uint i = 0u; i < 4u; ++i) {
        float x = (i & 1u) != 0u ? pc.rect.z : pc.rect.x;
        float y = (i & 2u) != 0u ? pc.rect.w : pc.rect.y;
        gl_MeshVerticesEXT[i].gl_Position = vec4(x, y, 0.5, 1.0);
    }
    gl_PrimitiveTriangleIndicesEXT[0] = uvec3(0, 1, 2);
    gl_PrimitiveTriangleIndicesEXT[1] = uvec3(2, 1, 3);
}
)";
    // Compiled on every device, so the mesh path is at least checked by glslang here.
    std::vector<uint32_t> meshSpirv =
        compiler().compileSource(mesh, VK_SHADER_STAGE_MESH_BIT_EXT, "rect.mesh");
    ASSERT_FALSE(meshSpirv.empty());
    if (!device().info().meshShader) {
        // ctest mesh_shaders.lavapipe_backports runs this on a driver that has them.
        if (std::getenv("STSV_REQUIRE_MESH_SHADERS"))
            FAIL() << device().info().name
                   << " lacks VK_EXT_mesh_shader, which STSV_REQUIRE_MESH_SHADERS requires";
        GTEST_SKIP() << device().info().name << " lacks VK_EXT_mesh_shader; mesh shader path not run";
    }

    PipelineLayout layout(device(), {}, sizeof(RectPush));
    GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_MESH_BIT_EXT, std::move(meshSpirv)},
                   {VK_SHADER_STAGE_FRAGMENT_BIT,
                    compiler().compileSource(BITS_FRAG, VK_SHADER_STAGE_FRAGMENT_BIT, "bits.frag")}};
    desc.colorFormats = {VK_FORMAT_R32G32_UINT};
    desc.logicOpEnable = true;
    desc.logicOp = VK_LOGIC_OP_OR;
    Pipeline pipeline = createGraphicsPipeline(device(), layout, desc);
    Image bits(device(), {SIDE, SIDE, VK_FORMAT_R32G32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    const std::vector<Rect> rects = {{3, 1, 11, 9, {0x5u, 0x6u}}, {7, 5, 14, 15, {0x10u, 0x0u}}};
    submitOnce(device(), [&](VkCommandBuffer cmd) {
        const ColorTarget target{&bits, true, {}};
        beginRendering(cmd, std::span(&target, 1));
        pipeline.bind(cmd);
        for (const Rect& r : rects) {
            const RectPush push{r.ndc(), r.bits};
            layout.push(cmd, &push, sizeof(push));
            device().cmdDrawMeshTasks()(cmd, 1, 1, 1);
        }
        endRendering(cmd);
    });
    expectSameBits(bits.readback<uint32_t>(), expectedBits(rects));
}

} // namespace
} // namespace stsv::test

// GPU vs CPU on the STSV math of volumes/stsv_dh.h (DESIGN §3): tests/gpu/shaders/stsv_math_check.comp
// and this file call the same runMathCheck() (tests/gpu/shaders/math_check_dh.h) on the same cases.
// The shader is the test's, not part of the shipped set: it is compiled from the checkout.
// This proves the device/host header path end to end: glslang include callback, std430
// layouts matching the C++ structs, and the functions agreeing on both sides.
#include "gpu/buffer.h"
#include "gpu/commands.h"
#include "gpu/descriptors.h"
#include "gpu/pipeline.h"
#include "gpu_fixture.h"
#include "tests/gpu/shaders/math_check_dh.h"
#include "tests/support/extreme_floats.h"

#include <gtest/gtest.h>

#include <filesystem>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>
#include <sstream>

namespace stsv::test {
namespace {

constexpr uint32_t CASE_COUNT = 1u << 17;

/// Random configurations around a triangle near z = 0: points below it (one in ten above), the
/// light frame above, so about a third of the segments cross the triangle; every 97th
/// triangle is degenerate (collinear vertices).
std::vector<MathCheckCase> makeCases(uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    auto uniform = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
    auto point = [&](float xy, float zLo, float zHi) {
        return vec4(uniform(-xy, xy), uniform(-xy, xy), uniform(zLo, zHi), 1.0f);
    };
    std::vector<MathCheckCase> cases(count);
    for (uint32_t i = 0; i < count; ++i) {
        MathCheckCase& k = cases[i];
        k.v0 = point(1.0f, -0.3f, 0.3f);
        k.v1 = point(1.0f, -0.3f, 0.3f);
        k.v2 = i % 97 == 0 ? k.v0 + 0.5f * (k.v1 - k.v0) : point(1.0f, -0.3f, 0.3f);
        k.uv01 = vec4(uniform(-2, 3), uniform(-2, 3), uniform(-2, 3), uniform(-2, 3));
        k.uv2ab = vec4(uniform(-2, 3), uniform(-2, 3), uniform(-1, 1), uniform(-1, 1));
        k.p = i % 10 == 0 ? point(0.6f, 0.4f, 1.0f) : point(0.6f, -2.0f, -0.4f);
        k.c = point(0.6f, 1.0f, 3.0f);
        k.tangent = vec4(uniform(-0.3f, 0.3f), uniform(-0.3f, 0.3f), uniform(-0.1f, 0.1f), 0.0f);
        k.bitangent = vec4(uniform(-0.3f, 0.3f), uniform(-0.3f, 0.3f), uniform(-0.1f, 0.1f), 0.0f);
        k.texture = uvec4(1u + uint(rng() % 64u), 1u + uint(rng() % 64u), uint(rng() % 2u), 0u);
    }
    return cases;
}

/// Runs the test shader `shader` (beside this file) once per case: binding
/// MATH_CHECK_BINDING_CASES holds the cases, MATH_CHECK_BINDING_RESULTS gets one Result each.
template <typename Result, typename Case>
std::vector<Result> runOnGpu(Device& device, const std::string& shader, const std::vector<Case>& cases) {
    // The checkout: its headers are the ones the shipped set embeds, and the test's own shaders
    // sit in tests/gpu/shaders beside this file.
    const ShaderCompiler compiler{std::filesystem::path(STSV_SOURCE_DIR)};
    DescriptorSetLayout setLayout(
        device,
        {{MATH_CHECK_BINDING_CASES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_COMPUTE_BIT},
         {MATH_CHECK_BINDING_RESULTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_COMPUTE_BIT}});
    PipelineLayout layout(device, {setLayout.handle()}, sizeof(uint32_t), VK_SHADER_STAGE_COMPUTE_BIT);
    Pipeline pipeline =
        createComputePipeline(device, layout, compiler.compileFile("tests/gpu/shaders/" + shader));
    Buffer caseBuffer =
        createBuffer(device, std::span<const Case>(cases), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    Buffer resultBuffer(device, cases.size() * sizeof(Result), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        MemoryUsage::DeviceLocal);
    DescriptorSet set(device, setLayout);
    set.writeBuffer(MATH_CHECK_BINDING_CASES, caseBuffer);
    set.writeBuffer(MATH_CHECK_BINDING_RESULTS, resultBuffer);
    const uint32_t count = uint32_t(cases.size());
    submitOnce(device, [&](VkCommandBuffer cmd) {
        pipeline.bind(cmd);
        VkDescriptorSet handle = set.handle();
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.handle(), 0, 1, &handle, 0,
                                nullptr);
        layout.push(cmd, &count, sizeof(count));
        vkCmdDispatch(cmd, (count + MATH_CHECK_GROUP_SIZE - 1) / MATH_CHECK_GROUP_SIZE, 1, 1);
    });
    return resultBuffer.download<Result>(cases.size());
}

std::vector<MathCheckResult> runOnGpu(Device& device, const std::vector<MathCheckCase>& cases) {
    return runOnGpu<MathCheckResult>(device, "stsv_math_check.comp", cases);
}

/// How close the CPU's decision came to flipping: the smallest of the margins of the tests in
/// stsvSegmentHitsTriangle (h'.x ≥ 0, h'.y ≥ 0, h'.x + h'.y ≤ h'.z, t_min·h'.z < e' < h'.z)
/// relative to the size of the numbers compared.
/// Degenerate triangles (h = 0, e = 0) are decided by stsvSetupTriangle's area test, far from
/// its threshold here, and count as infinitely far from a tie.
float relativeMargin(const MathCheckResult& r) {
    if (r.he == vec4(0.0f)) return INFINITY;
    const float sgn = r.he.z < 0.0f ? -1.0f : 1.0f;
    const vec3 hs = vec3(r.he) * sgn;
    const float es = r.he.w * sgn;
    const float scale = std::max({std::abs(hs.x), std::abs(hs.y), std::abs(hs.z), std::abs(es), 1e-30f});
    const float margin = std::min({std::abs(hs.x), std::abs(hs.y), std::abs(hs.z - hs.x - hs.y),
                                   std::abs(es - SHADOW_T_MIN * hs.z), std::abs(hs.z - es), std::abs(hs.z)});
    return margin / scale;
}

/// Distance (in texels) of uv·size from the nearest texel boundary, over both axes.
float texelBoundaryDistance(const MathCheckResult& r, const MathCheckCase& k) {
    const float u = r.baryUv.z * float(k.texture.x);
    const float v = r.baryUv.w * float(k.texture.y);
    return std::min(std::abs(u - std::round(u)), std::abs(v - std::round(v)));
}

std::string describeCase(const MathCheckCase& k, const MathCheckResult& cpu, const MathCheckResult& gpu) {
    std::ostringstream out;
    auto v4 = [&](const vec4& v) {
        std::ostringstream s;
        s.precision(9);
        s << "(" << v.x << ", " << v.y << ", " << v.z << ", " << v.w << ")";
        return s.str();
    };
    out << "v0=" << v4(k.v0) << " v1=" << v4(k.v1) << " v2=" << v4(k.v2) << " p=" << v4(k.p)
        << " c=" << v4(k.c) << " T=" << v4(k.tangent) << " B=" << v4(k.bitangent) << " uv2ab=" << v4(k.uv2ab)
        << "\n  cpu: hit=" << cpu.hit << " he=" << v4(cpu.he) << " baryUv=" << v4(cpu.baryUv) << " texel=("
        << cpu.texel.x << "," << cpu.texel.y << ")\n  gpu: hit=" << gpu.hit << " he=" << v4(gpu.he)
        << " baryUv=" << v4(gpu.baryUv) << " texel=(" << gpu.texel.x << "," << gpu.texel.y << ")";
    return out.str();
}

/// texelAt of each (u bits, v bits, width | height << 16, wrap) case on the device
/// (tests/gpu/shaders/texel_check.comp).
std::vector<ivec2> texelsOnGpu(Device& device, const std::vector<uvec4>& cases) {
    return runOnGpu<ivec2>(device, "texel_check.comp", cases);
}

using MathCheckTest = GpuTest;

TEST_F(MathCheckTest, GpuPicksTheCpusTexelForEveryFloat) {
    // The texel rule is total and the same on both sides: NaNs of either sign and any payload,
    // infinities, finite coordinates whose product with the size overflows, subnormals, ±0 and
    // random bit patterns, on textures of 1 to 8192 texels, repeat and clamp. Exact: the float
    // product is correctly rounded on both sides and the rest is integer arithmetic.
    std::vector<float> values = extremeFloats();
    const std::vector<float> random = randomBitFloats(20000, 5);
    values.insert(values.end(), random.begin(), random.end());
    std::vector<uvec4> cases;
    for (uint32_t size : {1u, 3u, 16u, 100u, 256u, 1000u, 8192u})
        for (uint32_t wrap : {WRAP_REPEAT, WRAP_CLAMP})
            for (std::size_t i = 0; i < values.size(); ++i)
                cases.push_back(uvec4(std::bit_cast<uint32_t>(values[i]),
                                      std::bit_cast<uint32_t>(values[values.size() - 1 - i]),
                                      size | (std::min(size + 1u, 8192u) << 16), wrap));
    const std::vector<ivec2> gpu = texelsOnGpu(device(), cases);
    std::size_t failures = 0;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const uvec4 k = cases[i];
        const ivec2 size(int(k.z & 0xffffu), int(k.z >> 16));
        const ivec2 cpu = texelAt(vec2(std::bit_cast<float>(k.x), std::bit_cast<float>(k.y)), size, k.w);
        if (gpu[i] != cpu && ++failures <= 5)
            ADD_FAILURE() << "uv bits " << std::hex << k.x << "," << k.y << std::dec << " size " << size.x
                          << "x" << size.y << " wrap " << k.w << ": cpu (" << cpu.x << "," << cpu.y
                          << ") gpu (" << gpu[i].x << "," << gpu[i].y << ")";
    }
    EXPECT_EQ(failures, 0u) << "of " << cases.size() << " cases";
}

TEST_F(MathCheckTest, GpuAgreesWithCpuOnStsvHeader) {
    const std::vector<MathCheckCase> cases = makeCases(CASE_COUNT, 20240611u);
    const std::vector<MathCheckResult> gpu = runOnGpu(device(), cases);
    ASSERT_EQ(gpu.size(), cases.size());

    // Float ties. The GPU may contract a·b + c into FMAs and evaluates inverse(mat3) with its
    // own formula, so h and e differ from the CPU's in the last few ulps, amplified by the
    // triangle's conditioning. A hit decision may therefore differ only where the CPU's
    // margin is below 1e-4 of the magnitudes compared (≈ 800 float ulps of headroom), and a
    // texel only where uv·size lies within 1e-3 texel of a texel boundary.
    constexpr float kTieMargin = 1e-4f;
    constexpr float kTexelTie = 1e-3f;

    std::size_t hits = 0, ties = 0, hitMismatch = 0, texelTies = 0, texelMismatch = 0, failures = 0;
    float maxBaryDiff = 0.0f;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const MathCheckResult cpu = runMathCheck(cases[i]);
        const bool tie = relativeMargin(cpu) < kTieMargin;
        hits += cpu.hit;
        ties += tie;
        if (cpu.hit != gpu[i].hit) {
            ++hitMismatch;
            if (!tie && ++failures <= 5)
                ADD_FAILURE() << "hit flag differs away from a tie (margin " << relativeMargin(cpu)
                              << "), case " << i << ":\n  " << describeCase(cases[i], cpu, gpu[i]);
            continue;
        }
        if (!cpu.hit) continue;
        maxBaryDiff = std::max({maxBaryDiff, std::abs(cpu.baryUv.x - gpu[i].baryUv.x),
                                std::abs(cpu.baryUv.y - gpu[i].baryUv.y)});
        const bool texelTie = texelBoundaryDistance(cpu, cases[i]) < kTexelTie;
        texelTies += texelTie;
        if (cpu.texel != gpu[i].texel) {
            ++texelMismatch;
            if (!texelTie && ++failures <= 5)
                ADD_FAILURE() << "texel differs away from a texel boundary (distance "
                              << texelBoundaryDistance(cpu, cases[i]) << " texel), case " << i << ":\n  "
                              << describeCase(cases[i], cpu, gpu[i]);
        }
    }
    std::cout << "stsv math check: " << cases.size() << " cases, " << hits << " hits, " << ties
              << " near-ties, " << hitMismatch << " hit-flag differences, " << texelTies
              << " near texel boundaries, " << texelMismatch << " texel differences, max |Δbary| "
              << maxBaryDiff << "\n";
    EXPECT_EQ(failures, 0u);
    // The cases must exercise both outcomes, and ties must stay rare or the test proves little.
    EXPECT_GT(hits, cases.size() / 10);
    EXPECT_LT(hits, cases.size() * 9 / 10);
    EXPECT_LT(ties, cases.size() / 100);
    EXPECT_LT(texelTies, hits / 100);
}

TEST_F(MathCheckTest, DegenerateTrianglesNeverHitOnEitherSide) {
    std::vector<MathCheckCase> cases = makeCases(256, 7u);
    for (MathCheckCase& k : cases) k.v2 = k.v1; // zero area
    const std::vector<MathCheckResult> gpu = runOnGpu(device(), cases);
    for (std::size_t i = 0; i < cases.size(); ++i) {
        EXPECT_EQ(runMathCheck(cases[i]).hit, 0u) << "case " << i;
        EXPECT_EQ(gpu[i].hit, 0u) << "case " << i;
    }
}

} // namespace
} // namespace stsv::test

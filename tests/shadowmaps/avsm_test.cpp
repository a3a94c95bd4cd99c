// The transmittance functions of adaptive volumetric shadow maps (shadowmaps/avsm_dh.h): built
// from surfaces in depth order, exact while they fit, the node whose removal loses the least area
// dropped on overflow, never increasing with depth; and both AVSM headers compile as GLSL 4.50.
#include "shadowmaps/avsm.h"
#include "tests/support/glsl.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace stsv {
namespace {

std::uint32_t unitsOf(double alpha) {
    return opticalDepthUnits(alpha);
}

TEST(Avsm, SurfacesThatFitAreKeptWithTheirSummedOpticalDepth) {
    const std::vector<AvsmSurface> surfaces = {
        {1.0f, unitsOf(0.5)}, {2.0f, unitsOf(0.25)}, {3.0f, unitsOf(0.1)}};
    const AvsmFunction f = buildAvsmTexel(surfaces, 3);
    ASSERT_EQ(f.count, 3u);
    EXPECT_EQ(f.overflowed, 0u);
    std::uint32_t sum = 0;
    for (uint j = 0; j < 3; ++j) {
        sum += surfaces[j].units;
        EXPECT_EQ(f.depth[j], surfaces[j].depth);
        EXPECT_EQ(f.units[j], sum) << j;
    }
    // T = Π (1 − α): 0.5 · 0.75 · 0.9, to the fixed point's relative 2^-17 per crossing.
    EXPECT_NEAR(avsmTransmittance(f.units[2]), 0.5 * 0.75 * 0.9, 3 * 0.3375 / 131072.0 + 1e-7);
}

TEST(Avsm, NothingChangesBehindAnOpaqueSurfaceOrForAnOpenOne) {
    const AvsmFunction f = buildAvsmTexel(
        {{1.0f, 0u}, {2.0f, unitsOf(0.5)}, {3.0f, OPTICAL_DEPTH_OPAQUE}, {4.0f, unitsOf(0.5)}}, 8);
    ASSERT_EQ(f.count, 2u);
    EXPECT_EQ(f.depth[0], 2.0f);
    EXPECT_EQ(f.depth[1], 3.0f);
    EXPECT_EQ(f.units[1], OPTICAL_DEPTH_OPAQUE);
    EXPECT_EQ(avsmTransmittance(f.units[1]), 0.0f);
    // A sum that reaches 2^32 − 1 units is opaque too, as the reference's.
    const AvsmFunction g = buildAvsmTexel({{1.0f, 0xc0000000u}, {2.0f, 0x40000000u}}, 8);
    EXPECT_EQ(g.units[1], OPTICAL_DEPTH_OPAQUE);
}

TEST(Avsm, OverflowDropsTheNodeWhoseRemovalLosesTheLeastArea) {
    // Three halves at depths 1, 1.1 and 3 into two nodes. T steps to 1/2, 1/4, 1/8. The areas a
    // removal changes: node 0's step moved to 1.1: 0.5 · 0.1 = 0.05; node 1 merged into node 0:
    // 0.25 · 0.1 = 0.025; node 1's step moved to 3: 0.25 · 1.9; node 2 merged into node 1:
    // 0.125 · 1.9. The cheapest merges node 1 into node 0: T drops to 1/4 at depth 1.
    const std::uint32_t half = unitsOf(0.5);
    const AvsmFunction f = buildAvsmTexel({{1.0f, half}, {1.1f, half}, {3.0f, half}}, 2);
    ASSERT_EQ(f.count, 2u);
    EXPECT_EQ(f.overflowed, 1u);
    EXPECT_EQ(f.depth[0], 1.0f);
    EXPECT_EQ(f.units[0], 2 * half);
    EXPECT_EQ(f.depth[1], 3.0f);
    EXPECT_EQ(f.units[1], 3 * half);
    // Far apart first, close together last (depths 1, 2.9, 3): node 0's step moved costs
    // 0.5 · 1.9, node 1 merged 0.25 · 1.9, node 1's step moved 0.25 · 0.1, node 2 merged into
    // node 1 0.125 · 0.1, the least: T drops to 1/8 at depth 2.9.
    const AvsmFunction g = buildAvsmTexel({{1.0f, half}, {2.9f, half}, {3.0f, half}}, 2);
    ASSERT_EQ(g.count, 2u);
    EXPECT_EQ(g.depth[1], 2.9f);
    EXPECT_EQ(g.units[1], 3 * half);
}

TEST(Avsm, FunctionsNeverIncreaseWithDepthAndStartAtOne) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> depth(0.5f, 20.0f);
    std::uniform_real_distribution<double> alpha(0.0, 1.0);
    for (int trial = 0; trial < 500; ++trial) {
        const uint nodes = 1 + uint(trial % int(AVSM_MAX_NODES));
        std::vector<AvsmSurface> surfaces(std::size_t(1 + trial % 40));
        for (AvsmSurface& s : surfaces) {
            const double a = alpha(rng);
            s = {depth(rng), a > 0.97 ? OPTICAL_DEPTH_OPAQUE : unitsOf(a * 0.9)};
        }
        std::sort(surfaces.begin(), surfaces.end(),
                  [](const AvsmSurface& a, const AvsmSurface& b) { return a.depth < b.depth; });
        const AvsmFunction f = buildAvsmTexel(surfaces, nodes);
        ASSERT_LE(f.count, nodes);
        ASSERT_GE(f.count, 1u);
        EXPECT_GE(f.depth[0], surfaces.front().depth) << "trial " << trial;
        EXPECT_LT(avsmTransmittance(f.units[0]), 1.0f) << "trial " << trial;
        for (uint j = 1; j < f.count; ++j) {
            EXPECT_GE(f.depth[j], f.depth[j - 1]) << "trial " << trial;
            EXPECT_GT(f.units[j], f.units[j - 1]) << "trial " << trial; // T strictly falls
        }
        // The whole attenuation survives every removal: the last node is the product of all.
        std::uint32_t total = 0;
        for (const AvsmSurface& s : surfaces) total = avsmAddUnits(total, s.units);
        EXPECT_EQ(f.units[f.count - 1], total) << "trial " << trial;
    }
}

const char* const COMPUTE_SHADER = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmaps/shadow_map_dh.h"
#include "shadowmaps/avsm_dh.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 1) readonly buffer Nodes { vec2 nodes[]; };
layout(std430, binding = 2) readonly buffer Taps { vec2 taps[]; };
layout(std430, binding = 3) readonly buffer View { ShadowMapView view; };
layout(std430, binding = 4) writeonly buffer Result { vec4 result[]; };
struct AvsmSource { uint size; uint nodes; };
uint avsmTexelIndex(AvsmSource s, uint face, ivec2 texel) { return (face * s.size + uint(texel.y)) * s.size + uint(texel.x); }
uint avsmSourceCount(AvsmSource s, uint face, ivec2 texel) { return counts[avsmTexelIndex(s, face, texel)]; }
float avsmSourceDepth(AvsmSource s, uint face, ivec2 texel, uint j) { return nodes[avsmTexelIndex(s, face, texel) * s.nodes + j].x; }
uint avsmSourceUnits(AvsmSource s, uint face, ivec2 texel, uint j) { return floatBitsToUint(nodes[avsmTexelIndex(s, face, texel) * s.nodes + j].y); }
vec2 avsmSourceTap(AvsmSource s, uint i) { return taps[i]; }
#define AVSM_SOURCE
#include "shadowmaps/avsm_filter_dh.h"
void main() {
    AvsmFunction f = avsmEmpty();
    for (uint i = 0u; i < 12u; ++i) avsmAppend(f, float(i), 1000u * i, 8u);
    ShadowMapView v = view;
    AvsmSource src;
    src.size = v.size;
    src.nodes = 8u;
    vec3 p = vec3(gl_GlobalInvocationID) * 0.01f;
    ShadowReceiver r = shadowReceiver(v, p, vec3(0.0f, 1.0f, 0.0f), 1.0f, 0.5f,
                                      shadowTapRotation(gl_GlobalInvocationID.xy, 7u, true));
    float hard = avsmVisibility(v, src, r);
    float blocker = vpcssAverageBlocker(v, src, r, 25u, 64.0f);
    float soft = blocker < 0.0f ? 1.0f : vpcssFilter(v, src, r, pcssFilterRadius(v, r, blocker, 64.0f), 25u, 25u);
    result[gl_GlobalInvocationID.x] = vec4(hard, soft, avsmTransmittance(f.units[f.count - 1u]), float(f.overflowed));
}
)";

TEST(Avsm, HeadersCompileInAComputeShader) {
    EXPECT_EQ(test::glslCompileErrors("avsm.comp", COMPUTE_SHADER), "");
}

} // namespace
} // namespace stsv

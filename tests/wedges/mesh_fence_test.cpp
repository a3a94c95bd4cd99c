// The fence-mesh generator (scene/mesh_fence): closed after welding, 10^5+ triangles at the
// default repeat, and a shadow that matches the perforated `fence` under the Embree reference.
#include "core/progress.h"
#include "core/timer.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "sampling/light_bounds.h"
#include "scene/load.h"
#include "scene/mesh_fence.h"
#include "wedges/adjacency.h"
#include "wedges/cpu/cpu_wedges.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace stsv {
namespace {

const Mesh& meshNamed(const Scene& scene, const std::string& name) {
    for (const Mesh& m : scene.meshes)
        if (m.name == name) return m;
    throw std::runtime_error("no mesh " + name);
}

TEST(FenceMesh, ClosedAfterWelding) {
    FenceParams params;
    params.repeat = 3; // odd: a partial tile row at the bottom (repeat/2 = 1.5 tiles high)
    params.textureSize = 32;
    const Scene scene = makeFenceMeshScene(params);
    const Mesh& fence = meshNamed(scene, "fence-mesh");
    ASSERT_GT(fence.triangleCount, 1000u);
    const EdgeAdjacency adj = buildEdgeAdjacency(scene, [&](std::size_t t) {
        return t >= fence.firstTriangle && t < fence.firstTriangle + fence.triangleCount;
    });
    EXPECT_EQ(adj.degenerateSkipped, 0u);
    EXPECT_EQ(adj.openEdges, 0u);
    EXPECT_EQ(adj.nonManifoldEdges, 0u);
    EXPECT_EQ(adj.inconsistentEdges, 0u) << "boxes must be wound consistently";
    EXPECT_EQ(adj.manifoldEdges, adj.edges.size());
    // Boxes are disjoint closed surfaces: 8 vertices, 18 edges, 12 triangles each (Euler: V − E + F = 2).
    EXPECT_EQ(adj.positions.size() * 12, std::size_t(fence.triangleCount) * 8);
    EXPECT_EQ(adj.edges.size() * 12, std::size_t(fence.triangleCount) * 18);
    // Same camera and light as `fence`.
    const Scene perforated = makeFenceScene(params);
    EXPECT_EQ(scene.camera.eye, perforated.camera.eye);
    EXPECT_EQ(scene.lights[0].position, perforated.lights[0].position);
    EXPECT_EQ(scene.lights[0].axisU, perforated.lights[0].axisU);
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) EXPECT_FALSE(scene.perforated(t));
}

TEST(FenceMesh, DefaultHasOver100kTriangles) {
    Timer timer;
    const Scene scene = loadScene("fence-mesh");
    const Mesh& fence = meshNamed(scene, "fence-mesh");
    std::printf("fence-mesh at the defaults: %u triangles (%zu boxes), generated in %.0f ms\n",
                fence.triangleCount, std::size_t(fence.triangleCount / 12), timer.milliseconds());
    EXPECT_GE(fence.triangleCount, 100000u);
}

TEST(FenceMesh, ShadowMatchesPerforatedFence) {
    Progress::setEnabled(false);
    FenceParams params;
    params.repeat = 4;
    params.textureSize = 64;
    const Scene quad = makeFenceScene(params);
    const Scene mesh = makeFenceMeshScene(params);
    const int size = 96, samples = 64;
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, samples, 9);
    const EmbreeScene quadRt(quad), meshRt(mesh);
    const GBuffer gq = quadRt.traceGBuffer(size, size), gm = meshRt.traceGBuffer(size, size);
    LightSampleBuffer bq(size, size, samples, BufferKind::Bitmask),
        bm(size, size, samples, BufferKind::Bitmask);
    traceReferenceSamples(quadRt, gq, quad.lights[0], plan, farDistanceFor(quad.bounds()), bq);
    traceReferenceSamples(meshRt, gm, mesh.lights[0], plan, farDistanceFor(mesh.bounds()), bm);
    double sum = 0.0, maxDiff = 0.0, shadow = 0.0;
    std::size_t pixels = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const std::size_t i = gq.index(x, y);
            // Ground pixels in both (the ground is triangles 0 and 1 of both scenes).
            if (gq.triangle[i] > 1 || gm.triangle[i] > 1) continue;
            const double d = std::abs(double(bq.visibleFraction(x, y)) - double(bm.visibleFraction(x, y)));
            sum += d;
            maxDiff = std::max(maxDiff, d);
            shadow += 1.0 - bq.visibleFraction(x, y);
            ++pixels;
        }
    ASSERT_GT(pixels, 1000u);
    std::printf(
        "fence vs fence-mesh (repeat 4, 64² texels, %zu triangles): mean |dv| %.4f, max %.3f over %zu ground "
        "pixels (mean occlusion %.3f)\n",
        mesh.triangleCount(), sum / double(pixels), maxDiff, pixels, shadow / double(pixels));
    EXPECT_GT(shadow / double(pixels), 0.02) << "the fence's shadow must be in view";
    // Same samples, same texels: only the boxes' 0.5 mm depth differs (oblique rays graze a box
    // side over about thickness·tanθ ≈ 0.5 mm beside each 16 mm texel: ~3 % of a wire's width).
    EXPECT_LT(sum / double(pixels), 0.01);
}

} // namespace
} // namespace stsv

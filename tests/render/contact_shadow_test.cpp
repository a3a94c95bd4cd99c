// Contact shadows from directional lights: the frame centre of a directional light sits
// farDistance = 100 scene diameters from p, so a segment start of t = SHADOW_T_MIN would lie 1 %
// of the scene diameter above the receiver and miss an occluder closer than that. shadowTMin
// (volumes/stsv_dh.h) keeps the start within SHADOW_T_MIN·D of p in every method.
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/geometry.h"
#include "volumes/cpu/cpu_stsv.h"
#include "volumes/stsv_dh.h"

#include <gtest/gtest.h>

#include <cmath>

namespace stsv {
namespace {

/// Horizontal opaque quad at height y over [x0, x1] × [z0, z1].
void addHorizontalQuad(Scene& s, float y, float x0, float x1, float z0, float z1, std::uint32_t material) {
    const vec3 a(x0, y, z0), b(x1, y, z0), c(x1, y, z1), d(x0, y, z1);
    s.addTriangle(a, b, c, vec2(0, 0), vec2(1, 0), vec2(1, 1), material);
    s.addTriangle(a, c, d, vec2(0, 0), vec2(1, 1), vec2(0, 1), material);
}

TEST(ShadowTMin, KeepsTheStartWithinOneThousandthOfTheSceneDiameter) {
    const vec3 p(1.0f, 2.0f, 3.0f);
    // Light centre within one diameter: the fraction is unchanged.
    EXPECT_EQ(shadowTMin(p, p + vec3(0.0f, 5.0f, 0.0f), 10.0f), SHADOW_T_MIN);
    EXPECT_EQ(shadowTMin(p, p + vec3(0.0f, 10.0f, 0.0f), 10.0f), SHADOW_T_MIN);
    // 1000 away, diameter 10: 1e-4 · 10 / 1000 = 1e-6 (float rounding of the distance: 1e-6 relative).
    EXPECT_NEAR(shadowTMin(p, p + vec3(0.0f, 0.0f, 1000.0f), 10.0f), 1e-6f, 1e-12f);
}

TEST(ContactShadow, DirectionalLightShadowsAReceiverJustBelowAnOccluder) {
    // Ground y = 0 over [−5, 5]², occluder plate at h = 0.05 over [−1, 1]²: D = √(10² + 10² + h²)
    // ≈ 14.14, so SHADOW_T_MIN·D ≈ 0.0014 < h < 1 % of D ≈ 0.14. Light straight overhead.
    constexpr float h = 0.05f;
    Scene scene;
    scene.source = "contact";
    scene.materials.push_back({"ground", vec3(0.8f), -1, WrapMode::Repeat, false});
    scene.materials.push_back({"plate", vec3(0.5f), -1, WrapMode::Repeat, false});
    addHorizontalQuad(scene, 0.0f, -5.0f, 5.0f, -5.0f, 5.0f, 0);
    addHorizontalQuad(scene, h, -1.0f, 1.0f, -1.0f, 1.0f, 1);
    scene.lights.push_back(makeDirectionalLight(vec3(0.0f, 1.0f, 0.0f), 0.01f, vec3(1.0f)));
    // Eye below the plate, looking at the ground beneath it at a grazing angle.
    scene.camera.eye = vec3(0.0f, 0.04f, 3.0f);
    scene.camera.target = vec3(0.0f, 0.0f, 0.0f);
    scene.camera.up = vec3(0.0f, 1.0f, 0.0f);
    scene.camera.fovY = 20.0f;
    const Bounds bounds = scene.bounds();
    const float diameter = length(bounds.hi - bounds.lo);
    const float far = farDistanceFor(bounds);
    ASSERT_GT(h, SHADOW_T_MIN * diameter);
    ASSERT_LT(h, SHADOW_T_MIN * far) << "the old fixed start would lie above the plate";

    constexpr int W = 64, H = 48, N = 32;
    const EmbreeScene embree(scene);
    const GBuffer g = embree.traceGBuffer(W, H);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, N, 7u, 1, true);
    LightSampleBuffer reference(W, H, N, BufferKind::Bitmask);
    LightSampleBuffer mirror(W, H, N, BufferKind::Bitmask);
    traceReferenceSamples(embree, g, scene.lights[0], plan, far, reference);
    stsvCpuSamples(scene, g, scene.lights[0], plan, far, mirror);

    std::size_t under = 0, failures = 0, oldRuleShadowed = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = g.index(x, y);
            if (!g.covered(i)) continue;
            const vec3 p = g.position[i];
            // Every pixel, everywhere: the mirror agrees with Embree bit for bit (no edges are
            // grazed: the plate's penumbra is 2·0.01·h wide, far from the sampled region's ends).
            for (int k = 0; k < N; ++k)
                EXPECT_EQ(reference.occluded(x, y, k), mirror.occluded(x, y, k))
                    << "pixel (" << x << "," << y << ") k=" << k << " p=(" << p.x << "," << p.y << "," << p.z
                    << ")";
            // Ground points under the plate, 0.1 inside its edges (the penumbra is 2·0.01·h wide).
            if (g.triangle[i] >= 2 || std::abs(p.x) > 0.9f || std::abs(p.z) > 0.9f) continue;
            ++under;
            const LightFrame frame = lightFrame(scene.lights[0], p, far);
            for (int k = 0; k < N; ++k) {
                if (!reference.occluded(x, y, k) || !mirror.occluded(x, y, k)) {
                    if (++failures <= 5)
                        ADD_FAILURE()
                            << "lit under the plate: pixel (" << x << "," << y << ") k=" << k << " p=(" << p.x
                            << "," << p.y << "," << p.z << ") reference=" << reference.occluded(x, y, k)
                            << " mirror=" << mirror.occluded(x, y, k);
                }
                // The old rule (start at SHADOW_T_MIN of p→s) would have missed the plate.
                const vec3 s = lightSamplePosition(frame, pixelSamplePoint(plan, x, y, k, frame.domain));
                oldRuleShadowed += embree.occluded(p, s, SHADOW_T_MIN, g.triangle[i]) ? 1 : 0;
            }
        }
    EXPECT_GT(under, 50u) << "too few ground pixels under the plate in view";
    EXPECT_EQ(failures, 0u);
    EXPECT_EQ(oldRuleShadowed, 0u) << "the scene does not exercise the directional-light start";
}

} // namespace
} // namespace stsv

// Analytic checks of both CPU methods (DESIGN §6): the penumbra under a straight edge, and a
// finely perforated canopy whose light footprint spans many texture periods.
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "sampling/light_bounds.h"
#include "scene/procedural.h"
#include "volumes/cpu/cpu_stsv.h"

#include <gtest/gtest.h>

#include <cmath>

namespace stsv {
namespace {

/// Horizontal quad at height y over [x0, x1] × [z0, z1], uv = repeat × unit square.
void addHorizontalQuad(Scene& s, float y, float x0, float x1, float z0, float z1, float repeat,
                       std::uint32_t material) {
    const vec3 a(x0, y, z0), b(x1, y, z0), c(x1, y, z1), d(x0, y, z1);
    const vec2 ta(0, 0), tb(repeat, 0), tc(repeat, repeat), td(0, repeat);
    s.addTriangle(a, b, c, ta, tb, tc, material);
    s.addTriangle(a, c, d, ta, tc, td, material);
}

/// Ground at y = 0 seen from below an occluder layer at height 1, rectangular light of
/// `lightSize` at height 4 facing down, centred above the origin.
Scene baseScene(float lightSize, float fovY) {
    Scene s;
    s.source = "analytic";
    s.materials.push_back({"ground", vec3(0.8f), -1, WrapMode::Repeat, false});
    addHorizontalQuad(s, 0.0f, -20.0f, 20.0f, -20.0f, 20.0f, 1.0f, 0);
    Light light{};
    light.type = LIGHT_RECTANGLE;
    light.position = vec3(0.0f, 4.0f, 0.0f);
    light.normal = vec3(0.0f, -1.0f, 0.0f);
    light.axisU = vec3(0.5f * lightSize, 0.0f, 0.0f);
    light.axisV = vec3(0.0f, 0.0f, 0.5f * lightSize);
    light.radius = length(light.axisU + light.axisV);
    light.radiance = vec3(1.0f);
    s.lights.push_back(light);
    // Camera between ground and occluders, looking straight down.
    s.camera.eye = vec3(0.0f, 0.8f, 0.0f);
    s.camera.target = vec3(0.0f);
    s.camera.up = vec3(0.0f, 0.0f, -1.0f);
    s.camera.fovY = fovY;
    return s;
}

struct Buffers {
    GBuffer g;
    LightSampleBuffer reference;
    LightSampleBuffer mirror;
};

Buffers renderBoth(const Scene& scene, int w, int h, const SamplePlan& plan) {
    const EmbreeScene embree(scene);
    Buffers b{embree.traceGBuffer(w, h), LightSampleBuffer(w, h, plan.count, BufferKind::Bitmask),
              LightSampleBuffer(w, h, plan.count, BufferKind::Bitmask)};
    const float far = farDistanceFor(scene.bounds());
    traceReferenceSamples(embree, b.g, scene.lights[0], plan, far, b.reference);
    stsvCpuSamples(scene, b.g, scene.lights[0], plan, far, b.mirror);
    return b;
}

TEST(Analytic, PenumbraWidthUnderStraightEdge) {
    // Opaque half-plane x < 0 at h_o = 1, light of width w = 1 at h_l = 4: the penumbra on the
    // ground spans w·h_o/(h_l − h_o) = 1/3, centred on x = 0; with light coordinate l uniform in
    // [−½, ½], the point x sees l ≥ −3x, so v(x) = clamp(½ + 3x, 0, 1).
    // fovY 9° at 0.8 m with aspect 8: the row spans ±0.8·tan(4.5°)·8 ≈ ±0.504 m, 3.9 mm a pixel.
    Scene scene = baseScene(1.0f, 9.0f);
    scene.materials.push_back({"edge", vec3(0.5f), -1, WrapMode::Repeat, false});
    addHorizontalQuad(scene, 1.0f, -20.0f, 0.0f, -20.0f, 20.0f, 1.0f, 1);
    // A uniform 16×16 grid without decorrelation: v(x) is the analytic fraction quantised to
    // sixteenths of the light's width, so it may differ from it by at most 1/16.
    const SamplePlan plan = makeSamplePlan(PatternKind::Uniform, 256, 1u, 1, false);
    const int W = 256, H = 32;
    const Buffers b = renderBoth(scene, W, H, plan);
    const float hw = 1.0f / 3.0f;
    float firstLit = 1e9f, lastShadowed = -1e9f;
    for (int x = 0; x < W; ++x) {
        const std::size_t i = b.g.index(x, H / 2);
        ASSERT_TRUE(b.g.covered(i));
        const vec3 p = b.g.position[i];
        const float expected = std::clamp(0.5f + 3.0f * p.x, 0.0f, 1.0f);
        const float vRef = b.reference.visibleFraction(x, H / 2), vStsv = b.mirror.visibleFraction(x, H / 2);
        EXPECT_NEAR(vRef, expected, 1.0f / 16.0f + 1e-4f) << "reference at x=" << p.x;
        EXPECT_NEAR(vStsv, expected, 1.0f / 16.0f + 1e-4f) << "stsv at x=" << p.x;
        if (vStsv > 0.0f) firstLit = std::min(firstLit, p.x);
        if (vStsv < 1.0f) lastShadowed = std::max(lastShadowed, p.x);
    }
    // Measured penumbra extent against [−w·h_o/(2(h_l − h_o)), +…], within a pixel's footprint
    // (3.9 mm) and a sixteenth of the width (the outermost grid columns sit 1/32 of the light's
    // width inside its edges, so the sampled penumbra is 15/16 of the analytic one).
    const float slack = 0.0040f + hw / 16.0f;
    EXPECT_NEAR(firstLit, -hw / 2.0f, slack);
    EXPECT_NEAR(lastShadowed, hw / 2.0f, slack);
    EXPECT_NEAR(lastShadowed - firstLit, hw, 2.0f * slack);
}

TEST(Analytic, FineFenceConvergesToOpenFraction) {
    // A chain-link canopy repeated 100 times per metre: the light (2 m at 4 m) covers a 0.5 m
    // footprint on it from the ground, ≈ 50 periods, so the visible fraction of every receiver
    // converges to the texture's open fraction.
    Scene scene = baseScene(2.0f, 60.0f);
    scene.textures.push_back(makeChainLinkTexture(64));
    scene.materials.push_back({"fence", vec3(0.5f), 0, WrapMode::Repeat, true});
    addHorizontalQuad(scene, 1.0f, -20.0f, 20.0f, -20.0f, 20.0f, 4000.0f, 1);
    const double open = openFraction(scene.textures[0]);
    const SamplePlan plan = makeSamplePlan(PatternKind::Stratified, 256, 5u, 1, true);
    const int W = 48, H = 48;
    const Buffers b = renderBoth(scene, W, H, plan);
    double sumRef = 0.0, sumStsv = 0.0;
    int n = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            sumRef += b.reference.visibleFraction(x, y);
            sumStsv += b.mirror.visibleFraction(x, y);
            ++n;
        }
    // 2304 receivers × 256 stratified samples: the Monte-Carlo error of the mean is far below
    // 0.01; the remaining tolerance covers the finite number of periods in the footprint.
    EXPECT_NEAR(sumRef / n, open, 0.01) << "open fraction " << open;
    EXPECT_NEAR(sumStsv / n, open, 0.01) << "open fraction " << open;
}

} // namespace
} // namespace stsv

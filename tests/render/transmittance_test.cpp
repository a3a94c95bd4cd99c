// Fractional transmittance (--buffer transmittance) on the CPU: translucent (Blend) quads over a
// ground under a small square light. The expected values come from the definition, not from the
// code: one quad of α = 0.5 lets half the light through, two stacked ones a quarter, a texel of
// alpha byte a lets 1 − a/255 through. STSV (the CPU mirror) and the Embree reference accumulate
// the same integer optical depths, so they are compared exactly, and so are two triangle orders.
#include "core/error.h"
#include "core/image.h"
#include "render/cpu/cpu_renderer.h"
#include "render/options.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/geometry.h"
#include "scene/occlusion_rules_dh.h"
#include "tests/support/boundary.h"
#include "tests/support/translucent_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace stsv {
namespace {

using test::addBlend;
using test::addVeil;
using test::groundScene;

constexpr int WIDTH = 48, HEIGHT = 48;

Frame render(const Scene& scene, Method method, BufferKind buffer = BufferKind::Transmittance) {
    RenderOptions o;
    o.method = method;
    o.backend = Backend::Cpu;
    o.width = WIDTH;
    o.height = HEIGHT;
    o.samples = 64;
    o.buffer = buffer;
    return makeCpuRenderer(scene, o)->render();
}

/// Pixels whose every sample's segment crosses the quad [−h, h]² at height y (the umbra), under
/// the light of side L at height 3: the ground point's x and z within h·3/(3 − y) − L·y/(2(3 − y))
/// of the centre, with a margin of one pixel's footprint.
bool inUmbra(const Frame& f, int x, int y, float quadY, float h, float lightSize) {
    const std::size_t i = f.gbuffer.index(x, y);
    if (!f.gbuffer.covered(i)) return false;
    const vec3 p = f.gbuffer.position[i];
    const float reach = (h * 3.0f - 0.5f * lightSize * quadY) / (3.0f - quadY) - 0.05f;
    return std::abs(p.x) < reach && std::abs(p.z) < reach;
}

/// Every sample of every umbra pixel has transmittance `expected` to the float16 step (the dump's
/// precision), and there are umbra pixels.
void expectUmbra(const Frame& f, float quadY, float h, float lightSize, float expected) {
    const LightSampleBuffer& b = f.lightSamples[0];
    ASSERT_EQ(b.kind(), BufferKind::Transmittance);
    int pixels = 0;
    for (int y = 0; y < HEIGHT; ++y)
        for (int x = 0; x < WIDTH; ++x) {
            if (!inUmbra(f, x, y, quadY, h, lightSize)) continue;
            ++pixels;
            for (int k = 0; k < b.samples(); ++k)
                ASSERT_EQ(halfBits(b.transmittance(x, y, k)), halfBits(expected))
                    << "pixel (" << x << "," << y << ") sample " << k << ": " << b.transmittance(x, y, k);
        }
    EXPECT_GT(pixels, 100);
}

/// The two frames' buffers hold the same optical depth for every sample, and some are
/// fractional. `atBoundaries`: except where the sample's segment passes within float round-off of
/// a triangle edge or a texel boundary (tests/support/boundary.h), where the reference and the mirror round
/// differently, as with bits (tests/render/mirror_vs_reference_test.cpp).
void expectSameDepths(const Scene& scene, const Frame& fa, const Frame& fb, bool atBoundaries = false) {
    const LightSampleBuffer& a = fa.lightSamples[0];
    const LightSampleBuffer& b = fb.lightSamples[0];
    RenderOptions o;
    o.samples = a.samples();
    const SamplePlan plan = samplePlanOf(o);
    const float far = farDistanceFor(scene.bounds());
    std::size_t fractional = 0, differing = 0, total = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            for (int k = 0; k < a.samples(); ++k) {
                ++total;
                const std::uint32_t d = a.opticalDepth(x, y, k);
                fractional += d != 0u && d != OPTICAL_DEPTH_OPAQUE ? 1 : 0;
                if (d == b.opticalDepth(x, y, k)) continue;
                ++differing;
                const std::size_t i = fa.gbuffer.index(x, y);
                const LightFrame frame = lightFrame(scene.lights[0], fa.gbuffer.position[i], far);
                const vec3 s = lightSamplePosition(frame, pixelSamplePoint(plan, x, y, k, frame.domain));
                ASSERT_TRUE(atBoundaries && test::atBoundary(scene, fa.gbuffer, x, y, s, frame.center, true))
                    << "pixel (" << x << "," << y << ") sample " << k << ": " << d << " vs "
                    << b.opticalDepth(x, y, k);
            }
    EXPECT_GT(fractional, 1000u);
    EXPECT_LT(differing, total / 1000) << "differing samples";
}

TEST(Transmittance, OneHalfTransparentQuadLetsHalfThrough) {
    Scene s = groundScene(0.2f);
    addVeil(s, 1.0f, 0.6f, addBlend(s, 0.5f));
    s.validate();
    for (Method m : {Method::Reference, Method::Stsv}) {
        SCOPED_TRACE(toString(m));
        const Frame f = render(s, m);
        expectUmbra(f, 1.0f, 0.6f, 0.2f, 0.5f);
        // v_coef is the mean transmittance: 0.5 in the umbra (float16 rounding of exp(−depth)
        // is below 1e-6 here: the depth of α = 0.5 is ln 2 to 2^−17).
        const int c = WIDTH / 2;
        EXPECT_NEAR(f.visibility.at(c, c, 0), 0.5f, 1e-5f);
    }
    expectSameDepths(s, render(s, Method::Reference), render(s, Method::Stsv), true);
}

TEST(Transmittance, TwoStackedQuadsLetAQuarterThrough) {
    Scene s = groundScene(0.2f);
    const std::uint32_t veil = addBlend(s, 0.5f);
    addVeil(s, 1.0f, 0.6f, veil);
    addVeil(s, 1.5f, 0.6f, veil);
    s.validate();
    // The lower quad's umbra is the smaller one.
    for (Method m : {Method::Reference, Method::Stsv}) {
        SCOPED_TRACE(toString(m));
        expectUmbra(render(s, m), 1.0f, 0.6f, 0.2f, 0.25f);
    }
    expectSameDepths(s, render(s, Method::Reference), render(s, Method::Stsv), true);
}

TEST(Transmittance, GradientTextureGivesEachTexelsValue) {
    // 8 × 1 texels of alpha 0, 36, …, 252 across u, a light of 1 mm: each pixel's samples cross
    // the texel under the segment to the light centre (pixels within 2 % of a texel edge skipped).
    Scene s = groundScene(0.001f);
    Texture gradient;
    gradient.name = "gradient";
    gradient.width = 8;
    gradient.height = 1;
    for (int x = 0; x < 8; ++x) gradient.rgba.insert(gradient.rgba.end(), {0, 0, 0, std::uint8_t(36 * x)});
    const int texture = addTexture(s, gradient);
    addVeil(s, 1.0f, 0.8f, addBlend(s, 1.0f, texture));
    s.validate();
    for (Method m : {Method::Reference, Method::Stsv}) {
        SCOPED_TRACE(toString(m));
        const Frame f = render(s, m);
        const LightSampleBuffer& b = f.lightSamples[0];
        std::vector<int> seen(8, 0);
        for (int y = 0; y < HEIGHT; ++y)
            for (int x = 0; x < WIDTH; ++x) {
                const std::size_t i = f.gbuffer.index(x, y);
                if (!f.gbuffer.covered(i)) continue;
                const vec3 p = f.gbuffer.position[i];
                // The segment to (0, 3, 0) meets y = 1 at p + (c − p)/3.
                const vec3 q = p + (vec3(0.0f, 3.0f, 0.0f) - p) / 3.0f;
                if (std::abs(q.x) > 0.79f || std::abs(q.z) > 0.79f) continue;
                const float u = (q.x + 0.8f) / 1.6f * 8.0f;
                if (std::abs(u - std::round(u)) < 0.02f) continue;
                const int texel = int(u);
                const float expected = 1.0f - float(36 * texel) / 255.0f;
                for (int k = 0; k < b.samples(); ++k)
                    ASSERT_EQ(halfBits(b.transmittance(x, y, k)), halfBits(expected))
                        << "pixel (" << x << "," << y << ") texel " << texel << " sample " << k;
                ++seen[std::size_t(texel)];
            }
        for (int t = 0; t < 8; ++t) EXPECT_GT(seen[std::size_t(t)], 3) << "texel " << t;
    }
}

TEST(Transmittance, TriangleOrderChangesNoDepth) {
    // Many overlapping translucent quads of three alphas; the same scene with its triangles
    // shuffled. Optical depth is an integer sum, so the buffers agree exactly.
    Scene s = groundScene(0.5f);
    const std::uint32_t materials[3] = {addBlend(s, 0.2f), addBlend(s, 0.55f), addBlend(s, 0.9f)};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> offset(-0.8f, 0.8f), height(0.5f, 2.0f);
    for (int q = 0; q < 24; ++q) {
        const float cx = offset(rng), cz = offset(rng), y = height(rng), h = 0.3f;
        const vec3 a(cx - h, y, cz - h), b(cx + h, y, cz - h), c(cx + h, y, cz + h), d(cx - h, y, cz + h);
        s.addTriangle(a, b, c, vec2(0, 0), vec2(1, 0), vec2(1, 1), materials[q % 3]);
        s.addTriangle(a, c, d, vec2(0, 0), vec2(1, 1), vec2(0, 1), materials[q % 3]);
    }
    s.validate();
    Scene shuffled = s;
    std::vector<std::size_t> order(s.triangleCount());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin() + 2, order.end(), rng); // the ground stays first: same G-buffer ids
    for (std::size_t t = 0; t < order.size(); ++t) {
        shuffled.triangles[t] = s.triangles[order[t]];
        shuffled.triangleMaterial[t] = s.triangleMaterial[order[t]];
    }
    const Frame a = render(s, Method::Stsv), b = render(shuffled, Method::Stsv);
    expectSameDepths(s, a, b);
    expectSameDepths(s, a, render(s, Method::Reference), true);
}

/// A closed opaque box [lo, hi], faces outwards.
void addBox(Scene& s, vec3 lo, vec3 hi, std::uint32_t material) {
    const auto corner = [&](int i) {
        return vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    };
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : faces) {
        s.addTriangle(corner(f[0]), corner(f[1]), corner(f[2]), vec2(0), vec2(0), vec2(0), material);
        s.addTriangle(corner(f[0]), corner(f[2]), corner(f[3]), vec2(0), vec2(0), vec2(0), material);
    }
}

TEST(Transmittance, OpaqueMeshesThroughTheWedgesTranslucentOnesThroughStsv) {
    // A half-transparent veil and, above its right half, an opaque box: dcs+stsv per sample as
    // the reference (but where segments graze an edge); pw+stsv per pixel: 1/2 in the veil's umbra
    // outside the box's shadow (no wedge there, the centre sees no opaque layer).
    Scene s = groundScene(0.2f);
    addVeil(s, 1.0f, 0.6f, addBlend(s, 0.5f));
    addBox(s, vec3(0.3f, 1.4f, -0.3f), vec3(0.9f, 1.6f, 0.3f), 0);
    s.validate();
    const Frame reference = render(s, Method::Reference);
    const Frame dcs = render(s, Method::DcsStsv);
    ASSERT_EQ(dcs.lightSamples[0].kind(), BufferKind::Transmittance);
    expectSameDepths(s, reference, dcs, true);
    std::size_t opaque = 0;
    for (int y = 0; y < HEIGHT; ++y)
        for (int x = 0; x < WIDTH; ++x)
            for (int k = 0; k < 64; ++k) opaque += reference.lightSamples[0].occluded(x, y, k) ? 1 : 0;
    EXPECT_GT(opaque, 1000u) << "the box shadows part of the frame";
    const Frame pw = render(s, Method::PwStsv);
    int checked = 0;
    for (int y = 0; y < HEIGHT; ++y)
        for (int x = 0; x < WIDTH; ++x) {
            const std::size_t i = pw.gbuffer.index(x, y);
            const vec3 p = pw.gbuffer.position[i];
            if (!inUmbra(pw, x, y, 1.0f, 0.6f, 0.2f) || p.x > -0.1f) continue;
            EXPECT_NEAR(pw.visibility.at(x, y, 0), 0.5f, 1e-5f) << x << "," << y;
            ++checked;
        }
    EXPECT_GT(checked, 50);
}

TEST(Transmittance, BinaryBuffersSeeTheStandInAndTheGBufferSeesThrough) {
    // With bits, a translucent triangle counts by its stand-in α ≥ 0.5: α = 0.5 blocks, 0.4
    // does not. Primary rays never stop on it: every pixel sees the ground.
    for (float factor : {0.5f, 0.4f}) {
        Scene s = groundScene(0.2f);
        addVeil(s, 1.0f, 0.6f, addBlend(s, factor));
        s.validate();
        const Frame f = render(s, Method::Stsv, BufferKind::Bitmask);
        const Frame r = render(s, Method::Reference, BufferKind::Bitmask);
        const int c = WIDTH / 2;
        EXPECT_EQ(f.lightSamples[0].occluded(c, c, 0), factor >= 0.5f);
        EXPECT_EQ(compareLightSamples(f.lightSamples[0], r.lightSamples[0]).differingSamples, 0u);
        for (std::size_t i = 0; i < f.gbuffer.triangle.size(); ++i)
            if (f.gbuffer.covered(i)) {
                ASSERT_LT(f.gbuffer.triangle[i], 2u);
            }
    }
}

TEST(Transmittance, OnlyMethodsThatWriteItAcceptTheBuffer) {
    Scene s = groundScene(0.2f);
    addVeil(s, 1.0f, 0.6f, addBlend(s, 0.5f));
    s.validate();
    for (Method m : {Method::Pcf, Method::Dcs, Method::Pw, Method::Peel}) {
        try {
            render(s, m);
            ADD_FAILURE() << toString(m) << " accepted --buffer transmittance";
        } catch (const UsageError& e) {
            EXPECT_NE(std::string(e.what()).find("does not write fractional transmittance"),
                      std::string::npos)
                << e.what();
        }
    }
}

} // namespace
} // namespace stsv

// The Embree reference, the oracle every other method is compared with, checked against visibility
// worked out by hand: a half-plane between a point and a light, the texel rule on a texture made
// pixel by pixel, the segment's start gap, and layer counts through stacked occluders.
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "sampling/light_sampling.h"
#include "sampling/pattern.h"
#include "scene/occlusion_rules_dh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace stsv {
namespace {

/// A horizontal quad y = h over [x0, x1] × [z0, z1] (two triangles, uv = (x, z) mapped to [0, 1]²).
void addQuad(Scene& s, float h, float x0, float x1, float z0, float z1, std::uint32_t material) {
    const vec3 a(x0, h, z0), b(x1, h, z0), c(x1, h, z1), d(x0, h, z1);
    s.addTriangle(a, b, c, vec2(0, 0), vec2(1, 0), vec2(1, 1), material);
    s.addTriangle(a, c, d, vec2(0, 0), vec2(1, 1), vec2(0, 1), material);
}

Scene emptyScene() {
    Scene s;
    s.source = "hand-made";
    s.materials.push_back({"opaque", vec3(0.5f), -1, WrapMode::Repeat, true});
    return s;
}

TEST(EmbreeReference, HalfPlaneBlocksExactlyTheSegmentsThatCrossIt) {
    // An opaque half-plane x < 0 (out to 50 m) at height 1. A segment p → s with p below and s
    // above crosses the plane y = 1 at q = p + t(s − p), t = (1 − p.y)/(s.y − p.y): it is blocked
    // iff q.x < 0 (and q.z within the quad). Segments crossing within 1e-4 of the edge are left
    // out: there the float ray test and the real line may differ.
    Scene scene = emptyScene();
    addQuad(scene, 1.0f, -50.0f, 0.0f, -50.0f, 50.0f, 0);
    const EmbreeScene embree(scene);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> xz(-2.0f, 2.0f), below(0.0f, 0.9f), above(1.1f, 4.0f);
    int blocked = 0, tested = 0;
    for (int i = 0; i < 20000; ++i) {
        const vec3 p(xz(rng), below(rng), xz(rng)), s(xz(rng), above(rng), xz(rng));
        const float t = (1.0f - p.y) / (s.y - p.y);
        const double qx = double(p.x) + double(t) * (double(s.x) - double(p.x));
        if (std::abs(qx) < 1e-4) continue;
        const bool expected = qx < 0.0;
        EXPECT_EQ(embree.occluded(p, s, SHADOW_T_MIN, NO_TRIANGLE), expected)
            << "p (" << p.x << ", " << p.y << ", " << p.z << "), s (" << s.x << ", " << s.y << ", " << s.z
            << "), crossing x " << qx;
        blocked += expected ? 1 : 0;
        ++tested;
    }
    EXPECT_GT(tested, 19000);
    EXPECT_GT(blocked, 5000); // both outcomes well represented
    EXPECT_LT(blocked, tested - 5000);
}

TEST(EmbreeReference, TexelRuleOfAHandMadeTexture) {
    // A 4×2 texture on the unit quad y = 1, x, z in [0, 1]: texel (i, j) covers u in [i/4,
    // (i+1)/4), v in [j/2, (j+1)/2). Its alphas: 255 and 0 alternating, and 127 / 128 at the
    // threshold (alpha below one half is a hole). A vertical segment through a texel's centre is
    // blocked iff that texel's alpha is 128 or more.
    Scene scene = emptyScene();
    Texture texture;
    texture.name = "hand-made 4x2";
    texture.width = 4;
    texture.height = 2;
    const std::uint8_t alphas[2][4] = {{255, 0, 127, 128}, {0, 255, 128, 127}};
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i)
            for (int c = 0; c < 4; ++c) texture.rgba.push_back(c == 3 ? alphas[j][i] : 200);
    scene.textures.push_back(texture);
    scene.materials.push_back({"perforated", vec3(0.5f), 0, WrapMode::Clamp, true});
    addQuad(scene, 1.0f, 0.0f, 1.0f, 0.0f, 1.0f, 1);
    const EmbreeScene embree(scene);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i) {
            const float x = (float(i) + 0.5f) / 4.0f, z = (float(j) + 0.5f) / 2.0f;
            const bool expected = alphas[j][i] >= 128;
            EXPECT_EQ(embree.occluded(vec3(x, 0.0f, z), vec3(x, 2.0f, z), SHADOW_T_MIN, NO_TRIANGLE),
                      expected)
                << "texel (" << i << ", " << j << ") alpha " << int(alphas[j][i]);
            // The primary ray sees the same: through a hole to nothing, else the quad.
            Hit hit;
            EXPECT_EQ(embree.intersect(vec3(x, 3.0f, z), vec3(0.0f, -1.0f, 0.0f), 0.0f, 10.0f, hit), expected)
                << "texel (" << i << ", " << j << ")";
        }
}

TEST(EmbreeReference, SegmentsStartAfterTheirGapAndSkipTheVisibleTriangle) {
    // Occluder at y = 1. A segment from p (y = 0) to s (y = 2) meets it at t = 1/2. With the
    // occluder's triangle as the visible one it does not block (the self-shadowing rule). A
    // segment starting on the occluder (p.y = 1, t = 0) is not blocked: hits before tMin do not
    // count; one starting just before it, farther than tMin·|s − p|, is.
    Scene scene = emptyScene();
    addQuad(scene, 1.0f, -1.0f, 1.0f, -1.0f, 1.0f, 0);
    const EmbreeScene embree(scene);
    const vec3 s(0.1f, 2.0f, 0.2f);
    EXPECT_TRUE(embree.occluded(vec3(0.1f, 0.0f, 0.2f), s, SHADOW_T_MIN, NO_TRIANGLE));
    // (0.1, 0.2) lies in the quad's second triangle (z > x): ignoring it unblocks the segment,
    // ignoring the first does not.
    EXPECT_TRUE(embree.occluded(vec3(0.1f, 0.0f, 0.2f), s, SHADOW_T_MIN, 0u));
    EXPECT_FALSE(embree.occluded(vec3(0.1f, 0.0f, 0.2f), s, SHADOW_T_MIN, 1u));
    EXPECT_FALSE(embree.occluded(vec3(0.1f, 1.0f, 0.2f), s, SHADOW_T_MIN, NO_TRIANGLE)); // starts on it
    // 1 cm below the plane, the hit is at t = 0.01 / 1.01 ≈ 0.0099, beyond tMin = 1e-4.
    EXPECT_TRUE(embree.occluded(vec3(0.1f, 0.99f, 0.2f), s, SHADOW_T_MIN, NO_TRIANGLE));
    // 1e-6 below, the hit is at t ≈ 1e-6, inside the gap.
    EXPECT_FALSE(embree.occluded(vec3(0.1f, 1.0f - 1e-6f, 0.2f), s, SHADOW_T_MIN, NO_TRIANGLE));
    // A segment that ends before the occluder is not blocked.
    EXPECT_FALSE(embree.occluded(vec3(0.1f, 0.0f, 0.2f), vec3(0.1f, 0.9f, 0.2f), SHADOW_T_MIN, NO_TRIANGLE));
}

TEST(EmbreeReference, LayersCountEachBlockingTriangleOnce) {
    // Three stacked quads at y = 1, 2, 3; the middle one is a hole everywhere (alpha 0). A
    // vertical segment from y = 0 to y = 4 crosses two opaque layers; from above the first quad,
    // one. (A segment exactly on a quad's diagonal meets both of its triangles and counts two:
    // such ties at a shared edge are where the methods may differ from the reference.)
    Scene scene = emptyScene();
    Texture holes;
    holes.name = "all holes";
    holes.width = holes.height = 1;
    holes.rgba = {255, 255, 255, 0};
    scene.textures.push_back(holes);
    scene.materials.push_back({"holes", vec3(0.5f), 0, WrapMode::Repeat, true});
    addQuad(scene, 1.0f, -1.0f, 1.0f, -1.0f, 1.0f, 0);
    addQuad(scene, 2.0f, -1.0f, 1.0f, -1.0f, 1.0f, 1);
    addQuad(scene, 3.0f, -1.0f, 1.0f, -1.0f, 1.0f, 0);
    const EmbreeScene embree(scene);
    std::vector<std::uint32_t> scratch;
    EXPECT_EQ(embree.countLayers(vec3(0.3f, 0.0f, -0.4f), vec3(0.3f, 4.0f, -0.4f), SHADOW_T_MIN, NO_TRIANGLE,
                                 scratch),
              2u);
    // Through the other triangle of each quad (x < z): two layers again.
    EXPECT_EQ(embree.countLayers(vec3(-0.5f, 0.0f, 0.5f), vec3(-0.5f, 4.0f, 0.5f), SHADOW_T_MIN, NO_TRIANGLE,
                                 scratch),
              2u);
    EXPECT_EQ(embree.countLayers(vec3(0.3f, 1.5f, -0.4f), vec3(0.3f, 4.0f, -0.4f), SHADOW_T_MIN, NO_TRIANGLE,
                                 scratch),
              1u);
    EXPECT_EQ(embree.countLayers(vec3(3.0f, 0.0f, 0.0f), vec3(3.0f, 4.0f, 0.0f), SHADOW_T_MIN, NO_TRIANGLE,
                                 scratch),
              0u);
}

TEST(EmbreeReference, ReferenceSamplesOfADiskLightBehindAHalfPlane) {
    // A disk light of radius 1 at height 4 facing down, an opaque half-plane x < 0 at height 1,
    // and a ground point at x = +0.2 below: the samples blocked are those whose segment crosses
    // the plane at x < 0, i.e. (similar triangles, the point at height 0) the samples with
    // 0.2 + (s.x − 0.2)/4 < 0: s.x < −0.6. Every sample of the plan is checked against that.
    Scene scene = emptyScene();
    addQuad(scene, 1.0f, -50.0f, 0.0f, -50.0f, 50.0f, 0);
    addQuad(scene, 0.0f, -50.0f, 50.0f, -50.0f, 50.0f, 0);
    Light light{};
    light.type = LIGHT_DISK;
    light.position = vec3(0.0f, 4.0f, 0.0f);
    light.normal = vec3(0.0f, -1.0f, 0.0f);
    light.axisU = vec3(1.0f, 0.0f, 0.0f);
    light.axisV = vec3(0.0f, 0.0f, 1.0f);
    light.radius = 1.0f;
    light.radiance = vec3(1.0f);
    scene.lights.push_back(light);
    scene.camera.eye = vec3(0.2f, 0.5f, 0.0f);
    scene.camera.target = vec3(0.2f, 0.0f, 0.0f);
    scene.camera.up = vec3(0.0f, 0.0f, -1.0f);
    scene.camera.fovY = 1.0f;
    const EmbreeScene embree(scene);
    GBuffer g = embree.traceGBuffer(1, 1);
    ASSERT_TRUE(g.covered(0));
    const vec3 p = g.position[0];
    ASSERT_NEAR(p.x, 0.2f, 1e-4f);
    ASSERT_NEAR(p.y, 0.0f, 1e-6f);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, 256, 1u, 1, false);
    LightSampleBuffer bits(1, 1, plan.count, BufferKind::Bitmask);
    const float far = farDistanceFor(scene.bounds());
    traceReferenceSamples(embree, g, light, plan, far, bits);
    const LightFrame frame = lightFrame(light, p, far);
    int blocked = 0, checked = 0;
    for (int k = 0; k < plan.count; ++k) {
        const vec3 s = lightSamplePosition(frame, pixelSamplePoint(plan, 0, 0, k, frame.domain));
        // The segment meets y = 1 at x = p.x + (s.x − p.x)·(1 − p.y)/(s.y − p.y).
        const double qx =
            double(p.x) + (double(s.x) - double(p.x)) * (1.0 - double(p.y)) / (double(s.y) - double(p.y));
        if (std::abs(qx) < 1e-4) continue;
        EXPECT_EQ(bits.occluded(0, 0, k), qx < 0.0) << "sample " << k << " at x " << s.x;
        blocked += qx < 0.0 ? 1 : 0;
        ++checked;
    }
    EXPECT_GE(checked, plan.count - 2);
    // About the disk's area left of x = −0.6: (acos(0.6) − 0.6·0.8)/π ≈ 14.2 % of the samples.
    EXPECT_GT(blocked, 0);
}

TEST(EmbreeReference, DependsOnNoMethod) {
    // The oracle must not share code with the methods it checks beyond the rules they all follow
    // (scene/occlusion_rules_dh.h): none of its files includes a method's folder.
    int files = 0;
    for (const auto& e :
         std::filesystem::directory_iterator(std::filesystem::path(STSV_SOURCE_DIR) / "reference")) {
        if (e.path().extension() != ".h" && e.path().extension() != ".cpp") continue;
        std::ifstream in(e.path());
        std::stringstream text;
        text << in.rdbuf();
        for (const char* folder : {"\"volumes/", "\"wedges/", "\"shadowmaps/", "\"render/", "\"gpu/"})
            EXPECT_EQ(text.str().find(std::string("#include ") + folder), std::string::npos)
                << e.path() << " includes " << folder;
        ++files;
    }
    EXPECT_GE(files, 4);
}

} // namespace
} // namespace stsv

// pw+stsv and dcs+stsv (Algorithm 2 of the STSV paper): on a scene whose only occluders are
// perforated, both reduce exactly to STSV; with an opaque mesh behind a perforated quad, pw+stsv
// is compared with the reference (the two occlusions add, so overlaps over-darken).
#include "core/progress.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu/cpu_renderer.h"
#include "render/methods.h"
#include "sampling/light_bounds.h"
#include "scene/geometry.h"
#include "scene/procedural.h"
#include "tests/support/wedge_composition.h"
#include "volumes/stsv_dh.h"
#include "wedge_test_util.h"
#include "wedges/cpu/cpu_wedges.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

namespace stsv {
namespace {

TEST(Combined, PerforatedOnlySceneReducesToStsv) {
    Progress::setEnabled(false);
    FenceParams params;
    params.repeat = 4;
    params.textureSize = 64;
    const Scene scene = makeFenceScene(params);
    const EmbreeScene rt(scene);
    const int size = 64, samples = 32;
    const GBuffer g = rt.traceGBuffer(size, size);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, samples, 2);
    const float farDistance = farDistanceFor(scene.bounds());
    const WedgeOccluders occ(scene);

    LightSampleBuffer stsvOnly(size, size, samples, BufferKind::Counters);
    stsvCpuSamples(scene, g, scene.lights[0], plan, farDistance, stsvOnly);
    LightSampleBuffer combined(size, size, samples, BufferKind::Counters);
    dcsStsvCpuSamples(occ, g, scene.lights[0], plan, farDistance, combined);
    const LightSampleDiff diff = compareLightSamples(stsvOnly, combined, 4, true);
    EXPECT_EQ(diff.differingSamples, 0u);

    ImageF pw;
    LightSampleBuffer bits(size, size, samples, BufferKind::Bitmask);
    pwStsvCpuVisibility(occ, g, scene.lights[0], plan, farDistance, pw, bits);
    std::size_t shadowed = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            if (!g.covered(g.index(x, y))) continue;
            // The opaque ground casts nothing on itself: v_pw = 1, so v = the STSV fraction
            // (same float expression on both sides).
            EXPECT_EQ(pw.at(x, y, 0), stsvOnly.visibleFraction(x, y)) << "x=" << x << " y=" << y;
            shadowed += stsvOnly.visibleFraction(x, y) < 1.0f ? 1 : 0;
        }
    EXPECT_GT(shadowed, 100u);
}

TEST(Combined, NoOpaqueTriangleAtAll) {
    Progress::setEnabled(false);
    Scene scene;
    Material fence;
    fence.name = "chainlink";
    fence.alphaTexture = addTexture(scene, makeChainLinkTexture(16));
    fence.doubleSided = true;
    const std::uint32_t m = addMaterial(scene, fence);
    appendMesh(scene, makeQuad(vec2(2.0f), vec2(2.0f)), mat4(1.0f), "fence", int(m));
    scene.lights.push_back(makeSphereLight(vec3(0.0f, 0.0f, 3.0f), 0.5f, vec3(1.0f)));
    const WedgeOccluders occ(scene);
    EXPECT_EQ(occ.opaqueTriangles(), 0u);
    EXPECT_EQ(occ.adjacency().edges.size(), 0u);
    EXPECT_EQ(occ.layersCrossed(vec3(0.0f, 0.0f, -1.0f), vec3(0.0f, 0.0f, 3.0f), SHADOW_T_MIN, NO_TRIANGLE),
              0u);
}

TEST(Combined, PwStsvWithOpaqueMeshMeasured) {
    Progress::setEnabled(false);
    Scene scene = makeMeshScene(test::makeSphereMesh(32, 16), "sphere");
    Material fence;
    fence.name = "chainlink";
    fence.alphaTexture = addTexture(scene, makeChainLinkTexture(64));
    fence.doubleSided = true;
    const std::uint32_t m = addMaterial(scene, fence);
    // A fence quad beside the sphere, its shadow partly overlapping the sphere's.
    appendMesh(scene, makeQuad(vec2(1.5f), vec2(4.0f)),
               glm::translate(mat4(1.0f), vec3(1.2f, 0.8f, 0.0f)) *
                   glm::rotate(mat4(1.0f), 1.3f, vec3(0, 1, 0)),
               "fence", int(m));
    scene.validate();
    const EmbreeScene rt(scene);
    const int size = 80, samples = 64;
    const GBuffer g = rt.traceGBuffer(size, size);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, samples, 4);
    const float farDistance = farDistanceFor(scene.bounds());
    const WedgeOccluders occ(scene);
    ImageF pw;
    LightSampleBuffer bits(size, size, samples, BufferKind::Bitmask);
    pwStsvCpuVisibility(occ, g, scene.lights[0], plan, farDistance, pw, bits);
    LightSampleBuffer ref(size, size, samples, BufferKind::Bitmask);
    traceReferenceSamples(rt, g, scene.lights[0], plan, farDistance, ref);
    double sum = 0.0, signedSum = 0.0;
    std::size_t pixels = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const std::uint32_t tri = g.triangle[g.index(x, y)];
            if (tri == NO_TRIANGLE || scene.meshes[1].name != "ground" ||
                tri < scene.meshes[1].firstTriangle || tri >= scene.meshes[1].firstTriangle + 2)
                continue;
            const double vr = ref.visibleFraction(x, y), vp = pw.at(x, y, 0);
            if (vr > 0.995 && vp > 0.995) continue;
            sum += std::abs(vr - vp);
            signedSum += vr - vp;
            ++pixels;
        }
    ASSERT_GT(pixels, 200u);
    std::printf(
        "pw+stsv vs reference, sphere + chain-link quad: mean |dv| %.4f, mean (v_ref - v) %.4f over %zu "
        "shadowed ground pixels\n",
        sum / double(pixels), signedSum / double(pixels), pixels);
    // Where only one of the two casts a shadow, both parts are exact up to 64-sample noise; the
    // sum over-darkens where the two shadows overlap (the paper's Fig. 4(a) artifact).
    EXPECT_LT(sum / double(pixels), 0.05);
    EXPECT_GE(signedSum, 0.0);
}

// The CPU frame's per-pass counts under the names the Vulkan frame uses: "wedges" per light
// (fragments = bound tests, silhouette_fragments, DCS samples_tested ≤ silhouettes × N, only
// those in each edge's crossing region; the cluster tree's clusters, tests and rejections) and,
// for the combined methods, the STSV part under "stsv".
TEST(Combined, CpuFrameStatsCountEachPass) {
    Progress::setEnabled(false);
    FenceParams params;
    params.repeat = 4;
    params.textureSize = 64;
    const Scene fence = makeFenceScene(params);
    const Scene sphere = makeMeshScene(test::makeSphereMesh(24, 12), "sphere");
    for (Method method : {Method::Dcs, Method::DcsStsv, Method::PwStsv})
        for (const Scene* scene : {&fence, &sphere}) {
            RenderOptions o;
            o.backend = Backend::Cpu;
            o.method = method;
            o.width = 64;
            o.height = 48;
            o.samples = 32;
            o.buffer = methodInfo(method).output == MethodOutput::Visibility ? BufferKind::Bitmask
                                                                             : BufferKind::Counters;
            const Frame frame = makeCpuRenderer(*scene, o)->render();
            const std::string what = toString(method) + " on " + scene->source;
            ASSERT_TRUE(frame.stats.contains("wedges")) << what;
            const nlohmann::json& w = frame.stats["wedges"][0];
            const auto silhouettes = w["silhouette_fragments"].get<std::size_t>();
            EXPECT_LE(silhouettes, w["fragments"].get<std::size_t>() * w["edges"].get<std::size_t>()) << what;
            // The cluster tree: its leaves hold the potential silhouettes (32 at most each), the
            // tiles' and blocks' node tests reject some of it, and what is left for the blocks'
            // pixels is at most every potential silhouette per block.
            const auto potential = w["potential_silhouettes"].get<std::size_t>();
            const auto clusters = w["clusters"].get<std::size_t>();
            EXPECT_GE(clusters * 32u, potential) << what;
            EXPECT_LE(clusters, potential) << what;
            EXPECT_LE(w["clusters_rejected"].get<std::size_t>(), w["cluster_tests"].get<std::size_t>())
                << what;
            EXPECT_LE(w["block_edges"].get<std::size_t>(), potential * std::size_t(16 * 12)) << what;
            EXPECT_LE(silhouettes, w["fragments"].get<std::size_t>()) << what;
            if (scene == &sphere) {
                EXPECT_GT(silhouettes, 100u) << what;
                EXPECT_GT(clusters, 1u) << what;
                EXPECT_GT(w["clusters_rejected"].get<std::size_t>(), 0u)
                    << what << ": the tree culls nothing";
                EXPECT_GT(w["volumes"].get<std::size_t>(), 0u) << what;
            }
            if (method == Method::PwStsv) {
                EXPECT_FALSE(w.contains("samples_tested")) << what << ": PW integrates, it tests no samples";
            } else {
                EXPECT_LE(w["samples_tested"].get<std::size_t>(), silhouettes * 32u) << what;
                if (scene == &sphere) {
                    EXPECT_GT(w["samples_tested"].get<std::size_t>(), 0u) << what;
                }
            }
            const bool stsvPart = method != Method::Dcs;
            ASSERT_EQ(frame.stats.contains("stsv"), stsvPart) << what;
            if (!stsvPart) continue;
            const nlohmann::json& s = frame.stats["stsv"][0];
            const auto inside = s["inside_fragments"].get<std::size_t>();
            EXPECT_LE(inside, s["fragments"].get<std::size_t>()) << what;
            EXPECT_LE(s["samples_tested"].get<std::size_t>(), inside * 32u) << what;
            // The tiles walk the tree of the STSV triangles: the volumes they reach, less those
            // their boxes drop, are what the blocks test.
            EXPECT_LE(s["clusters_rejected"].get<std::size_t>(), s["cluster_tests"].get<std::size_t>())
                << what;
            EXPECT_LE(s["tile_entries_culled"].get<std::size_t>(), s["tile_entries"].get<std::size_t>())
                << what;
            EXPECT_LE(s["tile_entries"].get<std::size_t>(),
                      s["volumes"].get<std::size_t>() * std::size_t(4 * 3))
                << what;
            // The fence's quad shadows the ground; the sphere scene has no perforated triangle.
            if (scene == &fence) {
                EXPECT_GT(s["samples_tested"].get<std::size_t>(), 1000u) << what;
            } else {
                EXPECT_EQ(s["fragments"].get<std::size_t>(), 0u) << what;
            }
        }
}

} // namespace
} // namespace stsv

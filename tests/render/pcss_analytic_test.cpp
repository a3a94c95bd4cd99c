// PCF and PCSS (DESIGN §4.6) against the analytic check of DESIGN §6: a square light of width w
// at height h_l over an opaque ground, an opaque occluder parallel to both with a straight edge at
// height h_o. The ground's penumbra is w·h_o/(h_l − h_o) wide and, for a square light with an edge
// parallel to the occluder's, its visibility is a linear ramp across it. PCSS estimates that width
// from the blocker depth (contact hardening); PCF's kernel is fixed. Where a second occluder near
// the light joins the blocker search, PCSS's average blocker depth gives the wrong penumbra.
#include "scene/geometry.h"
#include "shadowmaps/cpu/cpu_shadowmaps.h"
#include "shadowmaps/shadow_map.h"
#include "tests/render/parallel_planes.h"
#include "tests/render/shadow_map_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace stsv {
namespace {

using namespace test;

/// World size of a map texel on the ground (the unit of the width tolerances).
float groundTexel(const Scene& scene) {
    const ShadowMapView view = fitShadowMap(scene.lights[0], scene.bounds(), MAP_SIZE);
    EXPECT_EQ(view.projection, SHADOW_MAP_PERSPECTIVE);
    return shadowMapTexelWorld(view, LIGHT_HEIGHT);
}

/// PCSS at 1024 texels; pcss_max_kernel and pcss_max_search 128 so that the widest penumbra here (0.6 m = 154
/// texels on the ground, a 79-texel search radius) is not clipped by the kernel limit. The map fitted to
/// the scene box (sm_fit=0): the texel sizes and limits here are worked out for that map (groundTexel).
const MethodParams PCSS_PARAMS = {
    {"sm_size", double(MAP_SIZE)}, {"sm_fit", 0.0}, {"pcss_max_kernel", 128.0}, {"pcss_max_search", 128.0}};
/// PCF with a kernel of 1.5 cm either side: about the 5 × 5 texels around the receiver's on the
/// ground of this 1024² scene-box map (texels of 5 to 6 mm).
const MethodParams PCF_PARAMS = {{"sm_size", double(MAP_SIZE)}, {"sm_fit", 0.0}, {"pcf_world_radius", 0.015}};

struct Measured {
    double width = 0.0;
    Profile profile;
};

Measured measure(const Scene& scene, Method method, const MethodParams& params, int samples = 64) {
    const Frame f = renderCpu(scene, method, WIDTH, HEIGHT, params, samples, 3u);
    Measured m;
    m.profile = columnProfile(f);
    m.width = measuredWidth(m.profile);
    return m;
}

// The default kernel limit clips no plausible penumbra: at h_o = 1.5 the 0.6 m penumbra needs a
// kernel radius of 32 to 64 map texels (1024² map); a 32-texel limit clamps most of its pixels
// (measured 81 %) and narrows it by a third. The stats count the clamped pixels, so a user sees
// when the limit, not the scene, shapes the picture.
TEST(PcssParallelPlanes, TheDefaultKernelLimitKeepsAWidePenumbraAndTheStatsCountTheClampedPixels) {
    const Scene scene = parallelPlanes(1.5f);
    const double W = penumbraWidth(1.5f);
    const double texel = groundTexel(scene);
    const MethodParams defaults = {
        {"sm_size", double(MAP_SIZE)}, {"sm_fit", 0.0}, {"pcss_max_search", 128.0}};
    MethodParams clamped = defaults;
    clamped["pcss_max_kernel"] = 32.0;
    const Frame fDefault = renderCpu(scene, Method::Pcss, WIDTH, HEIGHT, defaults, 64, 3u);
    const Frame fClamped = renderCpu(scene, Method::Pcss, WIDTH, HEIGHT, clamped, 64, 3u);
    const double widthDefault = measuredWidth(columnProfile(fDefault));
    const double widthClamped = measuredWidth(columnProfile(fClamped));
    const double fractionDefault = fDefault.stats["shadow_maps"][0]["kernel_clamped_fraction"].get<double>();
    const double fractionClamped = fClamped.stats["shadow_maps"][0]["kernel_clamped_fraction"].get<double>();
    std::printf("h_o=1.5, W=%.4f m: width %.4f with the default limit (%.2f %% clamped), %.4f at 32 texels "
                "(%.2f %% clamped); disk kernel of W: %.4f\n",
                W, widthDefault, 100.0 * fractionDefault, widthClamped, 100.0 * fractionClamped,
                diskLevelWidth(W));
    EXPECT_EQ(fDefault.stats["shadow_maps"][0]["kernel_clamped_pixels"].get<std::uint64_t>(), 0u);
    EXPECT_NEAR(widthDefault, diskLevelWidth(W), 2.0 * texel);
    // At 32 texels the penumbra is narrower than the analytic one by more than twice the
    // two-texel tolerance above (measured 0.32 m for 0.48 m).
    EXPECT_GT(fractionClamped, 0.01);
    EXPECT_LT(widthClamped, diskLevelWidth(W) - 4.0 * texel);
}

TEST(PcssParallelPlanes, PenumbraWidthAndRampMatchTheAnalyticPenumbra) {
    for (const float ho : {0.5f, 1.5f}) {
        const Scene scene = parallelPlanes(ho);
        const double W = penumbraWidth(ho);
        const double texel = groundTexel(scene);
        SCOPED_TRACE("h_o=" + std::to_string(ho) + " W=" + std::to_string(W) +
                     " texel=" + std::to_string(texel));

        // The reference, 256 samples a pixel, is the analytic ramp: 32 rows of 256 Poisson samples
        // leave a Monte-Carlo error of about 0.5/√(32·256) ≈ 0.003 per column; 0.02 allows for
        // the samples' unequal spread across the light's width.
        const Measured ref = measure(scene, Method::Reference, {}, 256);
        const double refRamp = maxDeviation(ref.profile, [&](double x) { return linearRamp(x, W); });
        EXPECT_LT(refRamp, 0.02);
        // Its 5 %…95 % width: 0.9·W within a column (3.5 mm) and the same 2 %.
        EXPECT_NEAR(ref.width, (HIGH - LOW) * W, 0.0035 + 0.02 * W);

        const Measured pcss = measure(scene, Method::Pcss, PCSS_PARAMS);
        const double expectedPcss = diskLevelWidth(W);
        std::printf(
            "h_o=%.2f: W=%.4f m, texel %.4f m; reference 5-95 %% width %.4f (0.9 W = %.4f, ramp dev %.4f); "
            "pcss %.4f (disk kernel of diameter W: %.4f)\n",
            ho, W, texel, ref.width, (HIGH - LOW) * W, refRamp, pcss.width, expectedPcss);
        ::testing::Test::RecordProperty("pcss_width_h" + std::to_string(int(ho * 10)),
                                        std::to_string(pcss.width));
        // PCSS's kernel has the analytic width W (blocker depth h_l − h_o exactly, similar
        // triangles); it filters with a disk, so its 5 %…95 % levels lie a·W apart (a ≈ 0.805,
        // not 0.9): within two map texels on the ground.
        EXPECT_NEAR(pcss.width, expectedPcss, 2.0 * texel);
        // The profile: the disk kernel's shape (the tap set is a Poisson-disk sample of it; 0.03
        // covers 64 taps and 32 rotations a column) …
        const double diskDev = maxDeviation(pcss.profile, [&](double x) { return diskRamp(x, W); });
        EXPECT_LT(diskDev, 0.03);
        // … which departs from the analytic linear ramp by at most 0.0577 (the two profiles'
        // largest difference, at x = ±0.31·W): within that + 0.03 of it.
        const double rampDev = maxDeviation(pcss.profile, [&](double x) { return linearRamp(x, W); });
        double shapeGap = 0.0;
        for (int k = -100; k <= 100; ++k) {
            const double x = 0.5 * W * k / 100.0;
            shapeGap = std::max(shapeGap, std::abs(diskRamp(x, W) - linearRamp(x, W)));
        }
        EXPECT_LT(shapeGap, 0.058);
        EXPECT_LT(rampDev, shapeGap + 0.03);
        std::printf(
            "  pcss profile: %.4f from the disk-kernel profile, %.4f from the linear ramp (shape gap %.4f)\n",
            diskDev, rampDev, shapeGap);
    }
}

TEST(PcssParallelPlanes, ContactHardeningWidthRatioMatchesTheFormula) {
    const float lowH = 0.5f, highH = 1.5f;
    const Measured low = measure(parallelPlanes(lowH), Method::Pcss, PCSS_PARAMS);
    const Measured high = measure(parallelPlanes(highH), Method::Pcss, PCSS_PARAMS);
    const double expected = penumbraWidth(highH) / penumbraWidth(lowH); // 0.6 / (1/7) = 4.2
    const double ratio = high.width / low.width;
    std::printf("pcss widths %.4f (h_o=%.1f), %.4f (h_o=%.1f): ratio %.3f, formula %.3f\n", low.width, lowH,
                high.width, highH, ratio, expected);
    ::testing::Test::RecordProperty("pcss_width_ratio", std::to_string(ratio));
    // Each width is good to two texels (3.9 mm here) on its own; the narrow one is 0.115 m wide, so
    // the ratio carries up to 2·3.9/115 + 2·3.9/483 ≈ 8.4 % of error: 10 %.
    EXPECT_NEAR(ratio, expected, 0.10 * expected);
}

TEST(PcfParallelPlanes, FixedKernelDoesNotHardenWithContact) {
    const float lowH = 0.5f, highH = 1.5f;
    const Scene lowScene = parallelPlanes(lowH), highScene = parallelPlanes(highH);
    // The map holds the scene box, whose top is the occluder's height: the higher occluder's map
    // has the coarser texels on the ground.
    const double texel = std::max(groundTexel(lowScene), groundTexel(highScene));
    const Measured low = measure(lowScene, Method::Pcf, PCF_PARAMS);
    const Measured high = measure(highScene, Method::Pcf, PCF_PARAMS);
    std::printf("pcf widths %.4f (h_o=%.1f), %.4f (h_o=%.1f); texel %.4f; formula 0.9 W = %.4f, %.4f\n",
                low.width, lowH, high.width, highH, texel, (HIGH - LOW) * penumbraWidth(lowH),
                (HIGH - LOW) * penumbraWidth(highH));
    ASSERT_FALSE(std::isnan(low.width) || std::isnan(high.width));
    // The fixed world kernel (1.5 cm either side, 5 to 6 texels across) makes the same ramp at
    // both heights: equal within two texels (the staircase of a texel grid sampled by 3.5 mm
    // columns).
    EXPECT_NEAR(high.width, low.width, 2.0 * texel);
    // … and misses the analytic width at h_o = 1.5 by far more than two texels.
    EXPECT_GT(std::abs(high.width - (HIGH - LOW) * penumbraWidth(highH)), 20.0 * texel);
}

TEST(PcssParallelPlanes, CubeMapOfALightInsideTheBoxKeepsThePenumbraWidthOffAxis) {
    // The light inside the scene box (a 5 m pole beside the ground lifts the box's top over it):
    // its map is the cube fallback, whose downward face sees the ground. The occluder (h_o = 1.5,
    // W = 0.6 m) has its edge at x = 1.875, so the penumbra is centred on x = 3 on the ground,
    // 37° off the face's axis: axial depth 4, distance 5 from the light. The parallel-planes
    // width holds there as it does on the axis.
    Scene s;
    s.source = "parallel-planes-cube";
    s.materials.push_back({"ground", vec3(0.8f), -1, WrapMode::Repeat, false});
    s.materials.push_back({"occluder", vec3(0.5f), -1, WrapMode::Repeat, false});
    addHorizontalQuad(s, 0.0f, -5.0f, 5.0f, -5.0f, 5.0f, 0);
    const float ho = 1.5f, edge = 3.0f * (LIGHT_HEIGHT - ho) / LIGHT_HEIGHT;
    addHorizontalQuad(s, ho, edge - 1.0f, edge, -1.0f, 1.0f, 1);
    const vec3 a(-4.5f, 0.0f, -0.1f), b(-4.5f, 0.0f, 0.1f), c(-4.5f, 5.0f, 0.1f), d(-4.5f, 5.0f, -0.1f);
    s.addTriangle(a, b, c, vec2(0), vec2(1, 0), vec2(1), 1);
    s.addTriangle(a, c, d, vec2(0), vec2(1), vec2(0, 1), 1);
    s.lights.push_back(makeRectangleLight(vec3(0.0f, LIGHT_HEIGHT, 0.0f), vec3(0.0f, -1.0f, 0.0f),
                                          vec2(LIGHT_WIDTH), vec3(1.0f), vec3(1.0f, 0.0f, 0.0f)));
    s.camera = parallelPlanes(ho).camera;
    s.camera.eye = vec3(3.0f, 0.3f, 0.0f);
    s.camera.target = vec3(3.0f, 0.0f, 0.0f);
    const ShadowMapView view = fitShadowMap(s.lights[0], s.bounds(), MAP_SIZE);
    ASSERT_EQ(view.projection, SHADOW_MAP_CUBE);
    const double texel = shadowMapTexelWorld(view, LIGHT_HEIGHT);
    const double W = penumbraWidth(ho);

    const Frame pcssFrame = renderCpu(s, Method::Pcss, WIDTH, HEIGHT, PCSS_PARAMS, 64, 3u);
    Profile pcss = columnProfile(pcssFrame);
    for (double& x : pcss.x) x -= 3.0;
    const Frame refFrame = renderCpu(s, Method::Reference, WIDTH, HEIGHT, {}, 256, 3u);
    Profile ref = columnProfile(refFrame);
    for (double& x : ref.x) x -= 3.0;
    const double pcssWidth = measuredWidth(pcss), refWidth = measuredWidth(ref);
    const auto all = [](int, int) { return true; };
    const auto rmse = compareVisibility(pcssFrame.visibility, refFrame.visibility, all);
    std::printf(
        "cube map, penumbra 37° off axis: pcss 5-95 %% width %.4f (disk kernel of W: %.4f), reference %.4f "
        "(0.9 W = %.4f); texel %.4f; visibility RMSE against the reference %.4f\n",
        pcssWidth, diskLevelWidth(W), refWidth, (HIGH - LOW) * W, texel, rmse.rmse);
    EXPECT_NEAR(refWidth, (HIGH - LOW) * W, 0.0035 + 0.02 * W); // as on the axis
    EXPECT_NEAR(pcssWidth, diskLevelWidth(W), 2.0 * texel);     // as on the axis
    // Over the whole view: the disk kernel's shape differs from the ramp by 0.042 RMS over the
    // penumbra, two thirds of the view, and the reference carries Monte-Carlo noise of at most
    // √(1/6/256) = 0.026 RMS there: together 0.040. (Before PCSS took axial depths on cube
    // maps, its kernel here was 10 % too narrow: 0.059.)
    EXPECT_LT(rmse.rmse, 0.05);
    writeFailureImages("pcss_cube_off_axis", pcssFrame.visibility, refFrame.visibility);
}

TEST(PcssOverlappingOccluders, AveragedBlockerDepthWidensTheLowPenumbraWhereDcsStsvStaysExact) {
    // The low occluder of parallelPlanes(0.5) (penumbra W = 1/7 m), and a small one 1 m under the
    // light, over its umbra: [−0.15, −0.05] × [−0.1, 0.1] at h = 3. Its hard shadow from the light
    // centre, x ∈ [−0.6, −0.2], lies inside the low occluder's umbra (x < −W/2), and it hides
    // light that the low occluder hides already for most of the penumbra, so the truth changes
    // little there; but it is in the blocker search of every receiver of the low penumbra, and
    // its depth (1) pulls PCSS's average blocker depth from 3.5 towards the light. (The ground is
    // 2.4 m wide so that the box, now 3 m high, keeps the map's texels at 9.4 mm on the ground.)
    const Scene without = parallelPlanes(0.5f, 1.2f);
    Scene with = without;
    addHorizontalQuad(with, 3.0f, -0.15f, -0.05f, -0.1f, 0.1f, 1);
    const MethodParams params = {{"sm_size", double(MAP_SIZE)}, {"sm_fit", 0.0}}; // the texels above
    // Reference and dcs+stsv at equal samples and seed: per-sample bits comparable one for one.
    const Frame refWith = renderCpu(with, Method::Reference, WIDTH, HEIGHT, {}, 256, 101u);
    const Frame refWithout = renderCpu(without, Method::Reference, WIDTH, HEIGHT, {}, 256, 101u);
    const Frame pcssWith = renderCpu(with, Method::Pcss, WIDTH, HEIGHT, params, 64, 3u);
    const Frame pcssWithout = renderCpu(without, Method::Pcss, WIDTH, HEIGHT, params, 64, 3u);
    const Frame dcsWith = renderCpu(with, Method::DcsStsv, WIDTH, HEIGHT, {}, 256, 101u);
    const GBuffer& g = refWith.gbuffer;
    // The low penumbra (|x| < W/2 = 0.071) and 8 cm of its umbra and lit side.
    auto region = [&](int x, int y) { return std::abs(g.position[g.index(x, y)].x) < 0.15f; };
    const auto truthShift = compareVisibility(refWith.visibility, refWithout.visibility, region);
    const auto pcssAlone = compareVisibility(pcssWithout.visibility, refWithout.visibility, region);
    const auto pcssOverlap = compareVisibility(pcssWith.visibility, refWith.visibility, region);
    const auto dcs = compareVisibility(dcsWith.visibility, refWith.visibility, region);
    const double widthWith = measuredWidth(columnProfile(pcssWith));
    const double widthWithout = measuredWidth(columnProfile(pcssWithout));
    const double widthRef = measuredWidth(columnProfile(refWith));
    std::printf(
        "overlapping occluders, |x| < 0.15 (%zu px): visibility RMSE pcss %.4f (max %.3f) against the "
        "reference, %.4f without the high occluder; the reference moves by %.4f; dcs+stsv %.5f.\n"
        "  5-95 %% widths: pcss %.4f (alone %.4f, disk kernel of W %.4f), reference %.4f (0.9 W = %.4f)\n",
        pcssOverlap.pixels, pcssOverlap.rmse, pcssOverlap.maxAbs, pcssAlone.rmse, truthShift.rmse, dcs.rmse,
        widthWith, widthWithout, diskLevelWidth(penumbraWidth(0.5f)), widthRef,
        (HIGH - LOW) * penumbraWidth(0.5f));
    ::testing::Test::RecordProperty("pcss_overlap_rmse", std::to_string(pcssOverlap.rmse));
    ::testing::Test::RecordProperty("dcs_stsv_overlap_rmse", std::to_string(dcs.rmse));
    ASSERT_GT(pcssOverlap.pixels, 2000u);
    // The set-up: the high occluder changes the truth here by little (measured 0.023) and PCSS
    // alone is good (measured 0.032: the disk kernel's shape, up to 0.058 from the linear ramp).
    EXPECT_LT(truthShift.rmse, 0.05);
    EXPECT_LT(pcssAlone.rmse, 0.05);
    // PCSS's limitation: the averaged blocker depth makes the low penumbra far too wide (measured
    // 0.22 m instead of 0.12 m) and its visibility wrong by 0.081 RMSE, two and a half times
    // PCSS's own error without the high occluder. (With the search cut at 64 texels, the default
    // before pcss_max_search became a safety bound, fewer of the low occluder's texels joined
    // the average: 0.45 m and 0.25 RMSE.)
    EXPECT_GT(widthWith, 1.5 * diskLevelWidth(penumbraWidth(0.5f)));
    EXPECT_GT(pcssOverlap.rmse, 0.06);
    EXPECT_GT(pcssOverlap.rmse, 2.0 * pcssAlone.rmse);
    // dcs+stsv counts every occluder per light sample: at equal samples it agrees with Embree
    // exactly here (no sample grazes an edge of these axis-aligned quads).
    EXPECT_EQ(dcs.rmse, 0.0);
    EXPECT_EQ(dcs.maxAbs, 0.0);
    writeFailureImages("pcss_overlap", pcssWith.visibility, refWith.visibility);
}

} // namespace
} // namespace stsv

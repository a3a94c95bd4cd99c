// PCF and PCSS (CPU) on the lights and scenes at the edges of the map fit: sphere lights (cube
// maps) and directional lights (orthographic maps) against the analytic disk penumbra and the
// reference; a light facing away from everything and one shining from below the ground; a scene
// of perforated triangles only.
#include "scene/geometry.h"
#include "scene/procedural.h"
#include "shadowmaps/shadow_map.h"
#include "tests/render/parallel_planes.h"
#include "tests/render/shadow_map_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace stsv {
namespace {

using namespace test;

// The map fitted to the scene box (sm_fit=0): the tolerances below are worked out from its texels.
const MethodParams PCSS_PARAMS = {
    {"sm_size", double(MAP_SIZE)}, {"sm_fit", 0.0}, {"pcss_max_kernel", 128.0}, {"pcss_max_search", 128.0}};
/// PCF with a kernel of 1.5 cm either side: about the 5 × 5 texels around the receiver's on the
/// ground of this 1024² scene-box map (texels of 5 to 6 mm).
const MethodParams PCF_PARAMS = {{"sm_size", double(MAP_SIZE)}, {"sm_fit", 0.0}, {"pcf_world_radius", 0.015}};
const MethodParams& paramsFor(Method m) {
    return m == Method::Pcss ? PCSS_PARAMS : PCF_PARAMS;
}

const PixelMask ALL = [](int, int) { return true; };

/// No pixel of the frame's visibility is NaN or outside [0, 1].
void expectValidVisibility(const Frame& f, const char* what) {
    std::size_t bad = 0;
    for (const float v : f.visibility.pixels) bad += !(v >= 0.0f && v <= 1.0f);
    EXPECT_EQ(bad, 0u) << what << ": visibility NaN or outside [0, 1]";
}

/// A light of disk-shaped silhouette (diameter w, seen from under the edge) over the parallel
/// planes: the true penumbra and PCSS's kernel are both the disk segment of width W, so the two
/// profiles have the same shape and LOW…HIGH width.
void checkDiskPenumbra(const Scene& scene, double W, unsigned projection, const char* what) {
    const ShadowMapView view = fitShadowMap(scene.lights[0], scene.bounds(), MAP_SIZE);
    ASSERT_EQ(view.projection, projection) << what;
    const double texel = shadowMapTexelWorld(view, LIGHT_HEIGHT);
    const Frame ref = renderCpu(scene, Method::Reference, WIDTH, HEIGHT, {}, 256, 3u);
    const Frame pcss = renderCpu(scene, Method::Pcss, WIDTH, HEIGHT, PCSS_PARAMS, 64, 3u);
    expectValidVisibility(pcss, what);
    const double refWidth = measuredWidth(columnProfile(ref)), pcssWidth = measuredWidth(columnProfile(pcss));
    const auto d = compareVisibility(pcss.visibility, ref.visibility, ALL);
    std::printf(
        "%s: W=%.4f, disk 5-95 %% width %.4f; reference %.4f, pcss %.4f (texel %.4f); visibility RMSE %.4f\n",
        what, W, diskLevelWidth(W), refWidth, pcssWidth, texel, d.rmse);
    // The reference: a column (3.5 mm) and 2 % of W for the light samples' spread; the silhouette
    // seen from the view's edge is tilted by up to 7° (1 − cos 7° < 1 %).
    EXPECT_NEAR(refWidth, diskLevelWidth(W), 0.0035 + 0.02 * W) << what;
    EXPECT_NEAR(pcssWidth, diskLevelWidth(W), 2.0 * texel) << what;
    // Same shape on both sides: what is left is the reference's Monte-Carlo noise at 256
    // samples (≤ 0.031 a pixel, over the penumbra only) and PCSS's 64 rotated taps.
    EXPECT_LT(d.rmse, 0.03) << what;
    writeFailureImages(what, pcss.visibility, ref.visibility);
}

TEST(ShadowMapLights, SphereLightCubeMapGivesTheDiskPenumbra) {
    // Sphere of diameter 1 at h_l = 4, occluder at h_o = 1: W = 1/3 m.
    Scene scene = parallelPlanes(1.0f);
    scene.lights[0] = makeSphereLight(vec3(0.0f, LIGHT_HEIGHT, 0.0f), 0.5f, vec3(1.0f));
    checkDiskPenumbra(scene, penumbraWidth(1.0f), SHADOW_MAP_CUBE, "sphere_light");
}

TEST(ShadowMapLights, DirectionalLightOrthographicMapGivesTheDiskPenumbra) {
    // Straight overhead, angular radius 0.1: the penumbra under an edge at h_o = 1.5 is
    // 2·tan(0.1)·h_o = 0.301 m wide.
    Scene scene = parallelPlanes(1.5f);
    scene.lights[0] = makeDirectionalLight(vec3(0.0f, 1.0f, 0.0f), 0.1f, vec3(1.0f));
    checkDiskPenumbra(scene, 2.0 * std::tan(0.1) * 1.5, SHADOW_MAP_ORTHOGRAPHIC, "directional_light");
}

TEST(ShadowMapLights, RectangleLightFacingAwayFromTheSceneShadowsAsTheReferenceDoes) {
    // The light emits upwards, away from the whole box: the perspective fit finds nothing in
    // front of it and falls back to a cube map, which still sees the occluder; visibility is
    // geometric in every method (the lighting is zero there anyway).
    Scene scene = parallelPlanes(1.0f);
    scene.lights[0] = makeRectangleLight(vec3(0.0f, LIGHT_HEIGHT, 0.0f), vec3(0.0f, 1.0f, 0.0f),
                                         vec2(LIGHT_WIDTH), vec3(1.0f), vec3(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(fitShadowMap(scene.lights[0], scene.bounds(), MAP_SIZE).projection, SHADOW_MAP_CUBE);
    const Frame ref = renderCpu(scene, Method::Reference, WIDTH, HEIGHT, {}, 256, 3u);
    for (const Method m : {Method::Pcss, Method::Pcf}) {
        const Frame f = renderCpu(scene, m, WIDTH, HEIGHT, paramsFor(m), 64, 3u);
        expectValidVisibility(f, "facing away");
        const auto d = compareVisibility(f.visibility, ref.visibility, ALL);
        std::printf("facing away, %s: visibility RMSE %.4f against the reference\n",
                    methodInfo(m).name.c_str(), d.rmse);
        // The square light's linear ramp against PCSS's disk kernel: 0.042 RMS over the penumbra
        // (0.33 m of the view's 0.9 m), 0.026 over the view; PCF's 5-texel step against the
        // 0.33 m ramp: √(1/12) = 0.29 RMS over the penumbra, 0.18 over the view. Either way the
        // umbra and the lit side agree.
        EXPECT_LT(d.rmse, m == Method::Pcss ? 0.04 : 0.2) << methodInfo(m).name;
    }
}

TEST(ShadowMapLights, DirectionalLightFromBelowTheGroundLeavesTheGroundLitAndTheOccluderDark) {
    // From below, the orthographic map's first surface is the ground's underside: the ground
    // (its normal turned towards the light) lies on its own plane in the map and stays lit; the
    // occluder's underside is behind the ground and is dark. The reference: rays from the ground
    // go down into nothing (the receiver's own triangle never blocks), rays from the occluder
    // meet the ground.
    Scene scene = parallelPlanes(1.0f);
    scene.lights[0] = makeDirectionalLight(vec3(0.0f, -1.0f, 0.0f), 0.05f, vec3(1.0f));
    scene.camera.eye = vec3(1.5f, 3.0f, 1.8f);
    scene.camera.target = vec3(0.0f, 0.5f, 0.0f);
    scene.camera.up = vec3(0.0f, 1.0f, 0.0f);
    scene.camera.fovY = 60.0f;
    EXPECT_EQ(fitShadowMap(scene.lights[0], scene.bounds(), MAP_SIZE).projection, SHADOW_MAP_ORTHOGRAPHIC);
    constexpr int W = 96, H = 64;
    const Frame ref = renderCpu(scene, Method::Reference, W, H, {}, 64, 3u);
    for (const Method m : {Method::Pcss, Method::Pcf}) {
        const Frame f = renderCpu(scene, m, W, H, paramsFor(m), 64, 3u);
        expectValidVisibility(f, "from below");
        std::size_t ground = 0, groundLit = 0, occluder = 0, occluderDark = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = f.gbuffer.index(x, y);
                if (!f.gbuffer.covered(i)) continue;
                const bool onGround = f.gbuffer.triangle[i] < 2;
                (onGround ? ground : occluder) += 1;
                (onGround ? groundLit : occluderDark) +=
                    onGround ? f.visibility.at(x, y, 0) == 1.0f : f.visibility.at(x, y, 0) == 0.0f;
            }
        const auto d = compareVisibility(f.visibility, ref.visibility, ALL);
        std::printf(
            "from below, %s: ground %zu/%zu lit, occluder %zu/%zu dark; RMSE %.4f against the reference\n",
            methodInfo(m).name.c_str(), groundLit, ground, occluderDark, occluder, d.rmse);
        ASSERT_GT(ground, 1000u);
        ASSERT_GT(occluder, 200u);
        // Exact: the ground's taps all hold its own depth, the occluder's all hold the ground.
        EXPECT_EQ(groundLit, ground) << methodInfo(m).name;
        EXPECT_EQ(occluderDark, occluder) << methodInfo(m).name;
        EXPECT_EQ(d.maxAbs, 0.0) << methodInfo(m).name;
    }
}

/// Horizontal perforated quad at height y over [−half, half]², the alpha texture `repeat` times
/// across it.
void addPerforatedQuad(Scene& s, float y, float half, float repeat, std::uint32_t material) {
    const vec3 a(-half, y, -half), b(half, y, -half), c(half, y, half), d(-half, y, half);
    s.addTriangle(a, c, b, vec2(0.0f), vec2(repeat), vec2(repeat, 0.0f), material);
    s.addTriangle(a, d, c, vec2(0.0f), vec2(0.0f, repeat), vec2(repeat), material);
}

TEST(ShadowMapScenes, OnlyPerforatedTrianglesRenderLikeTheReference) {
    // A chain-link floor (4 m, 8 tiles: 12.5 cm diamonds) under a chain-link canopy at 1 m (2 m,
    // 8 tiles: 6.25 cm), a 0.5 m light at 3 m; no opaque triangle anywhere. The camera under the canopy
    // sees the floor's wires (its holes show the background).
    Scene scene;
    scene.source = "perforated-only";
    scene.textures.push_back(makeChainLinkTexture(64));
    scene.materials.push_back({"floor", vec3(0.7f), 0, WrapMode::Repeat, true});
    scene.materials.push_back({"canopy", vec3(0.5f), 0, WrapMode::Repeat, true});
    addPerforatedQuad(scene, 0.0f, 2.0f, 8.0f, 0);
    addPerforatedQuad(scene, 1.0f, 1.0f, 8.0f, 1);
    scene.lights.push_back(
        makeRectangleLight(vec3(0.0f, 3.0f, 0.0f), vec3(0.0f, -1.0f, 0.0f), vec2(0.5f), vec3(1.0f)));
    scene.camera.eye = vec3(0.0f, 0.7f, 0.0f);
    scene.camera.target = vec3(0.0f);
    scene.camera.up = vec3(0.0f, 0.0f, -1.0f);
    scene.camera.fovY = 60.0f;
    scene.validate();
    constexpr int W = 128, H = 128;
    const ImageF ref = convergedReference(scene, W, H, 2, 128);
    // PCSS also on the map fitted to the view (sm_fit=1): the canopy alone, its texels 2.4 times
    // finer, must shadow the floor as well as the scene fit does.
    MethodParams viewFit = PCSS_PARAMS;
    viewFit["sm_fit"] = 1.0;
    for (const auto& [m, params] : {std::pair{Method::Pcss, PCSS_PARAMS}, std::pair{Method::Pcf, PCF_PARAMS},
                                    std::pair{Method::Pcss, viewFit}}) {
        const Frame f = renderCpu(scene, m, W, H, params, 64, 3u);
        expectValidVisibility(f, "perforated only");
        const GBuffer& g = f.gbuffer;
        const auto floor = [&](int x, int y) {
            return g.covered(g.index(x, y)) && g.triangle[g.index(x, y)] < 2;
        };
        const auto d = compareVisibility(f.visibility, ref, floor);
        double meanRef = 0.0, mean = 0.0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                if (floor(x, y)) {
                    meanRef += ref.at(x, y, 0) / double(d.pixels);
                    mean += f.visibility.at(x, y, 0) / double(d.pixels);
                }
        std::printf("perforated only, %s (sm_fit=%g): %zu floor px, mean visibility %.4f (reference %.4f), "
                    "RMSE %.4f\n",
                    methodInfo(m).name.c_str(), params.at("sm_fit"), d.pixels, mean, meanRef, d.rmse);
        ASSERT_GT(d.pixels, 2000u);
        // The canopy shadows the floor: seen from the floor, the light (0.5 m, 3 m up) covers
        // 0.17 m of the canopy (1 m up), almost three of its 6.25 cm diamonds, so the floor's
        // visibility is a soft pattern around the texture's open fraction. Loose agreement: the
        // mean within 0.05 (a map that lost the canopy would give 1, one without its holes 0;
        // measured within 0.004), and pixel by pixel PCSS within 0.1 RMSE (measured 0.05); PCF
        // keeps the wires' shadows hard (5 texels against a 0.25 m penumbra), off by their
        // contrast: 0.3 (measured 0.22).
        EXPECT_LT(meanRef, 0.9) << "the canopy must shadow the floor";
        EXPECT_NEAR(mean, meanRef, 0.05) << methodInfo(m).name;
        EXPECT_LT(d.rmse, m == Method::Pcss ? 0.1 : 0.3) << methodInfo(m).name;
        writeFailureImages(std::string("perforated_only_") + methodInfo(m).name +
                               (params.at("sm_fit") > 0.0 ? "_view_fit" : ""),
                           f.visibility, ref);
    }
}

} // namespace
} // namespace stsv

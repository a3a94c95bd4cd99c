// The Vulkan STSV renderer against the CPU mirror fed the GPU's own G-buffer and
// against Embree: built-in scenes at N = 16, 64, 256, every light shape, and the edge cases of
// DESIGN §4.2 (double-sided triangles with the light straddling their plane, a camera inside a
// volume, triangles crossing the near plane or behind the light, degenerate triangles).
#include "gpu_render_helpers.h"

#include "core/error.h"
#include "render/vulkan/gpu_deferred.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_volumes_dh.h"
#include "scene/camera.h"
#include "scene/geometry.h"
#include "scene/load.h"
#include "tests/scene/scene_test_util.h"

#include <algorithm>
#include <cstdlib>
#include <gtest/gtest.h>
#include <set>

namespace stsv::test {
namespace {

using GpuRenderer = GpuRenderTest;

// Small frames: lavapipe runs on two CPU cores and the mirror and Embree run beside it.
constexpr int W = 96, H = 72;

TEST_F(GpuRenderer, TheFrameSetHoldsTwelveBindingsAtMostEachOnce) {
    // Set 0 is what every pass binds: the scene tables, the frame and its lights, the G-buffer,
    // the light-sample buffers of each kind and the v_coef image the families write; what one
    // pass alone writes (the resolve's colour and visibility) lives in that pass's own set.
    const Scene scene = loadScene("fence");
    for (const BufferKind kind : {BufferKind::Bitmask, BufferKind::Counters, BufferKind::Transmittance}) {
        RenderOptions o = gpuOptions(W, H, 16);
        o.buffer = kind;
        const FrameResources resources(device(), scene, o, samplePlanOf(o));
        const std::vector<DescriptorBinding> bindings = resources.bindings();
        std::set<uint32_t> numbers;
        for (const DescriptorBinding& b : bindings) {
            EXPECT_LT(b.binding, 12u) << toString(kind);
            numbers.insert(b.binding);
        }
        EXPECT_EQ(numbers.size(), bindings.size()) << toString(kind) << ": a binding number twice";
        EXPECT_LE(bindings.size(), 12u) << toString(kind);
    }
}

TEST_F(GpuRenderer, GBufferAgreesWithEmbreePrimaryRays) {
    const Scene scene = loadScene("fence");
    const RenderOptions o = gpuOptions(W, H, 16);
    const Frame frame = renderGpu(scene, o);
    const GBuffer cpu = EmbreeScene(scene).traceGBuffer(W, H);
    std::size_t same = 0, covered = 0;
    const float size = length(scene.bounds().extent());
    for (std::size_t i = 0; i < cpu.triangle.size(); ++i) {
        covered += cpu.covered(i) ? 1 : 0;
        if (frame.gbuffer.triangle[i] != cpu.triangle[i]) continue;
        ++same;
        if (!cpu.covered(i)) continue;
        // Same triangle at the same pixel centre: rasterised barycentrics vs ray hit, float round-off.
        EXPECT_LT(length(frame.gbuffer.position[i] - cpu.position[i]), 1e-4f * size) << "pixel " << i;
        EXPECT_EQ(frame.gbuffer.normal[i], cpu.normal[i]) << "pixel " << i;
    }
    EXPECT_GT(covered, cpu.triangle.size() / 2);
    // Pixel centres on a triangle edge or a texel boundary may go either way.
    EXPECT_GE(double(same) / double(cpu.triangle.size()), 0.995) << same << " of " << cpu.triangle.size();
}

/// Fraction of pixels whose visible triangle the raster G-buffer and Embree's primary rays agree
/// on, and whether every pixel Embree covers is covered on the GPU too.
double gbufferAgreement(const Scene& scene, const Frame& frame, std::size_t& coveredOnlyOnCpu) {
    const GBuffer cpu = EmbreeScene(scene).traceGBuffer(W, H);
    std::size_t same = 0;
    coveredOnlyOnCpu = 0;
    for (std::size_t i = 0; i < cpu.triangle.size(); ++i) {
        same += frame.gbuffer.triangle[i] == cpu.triangle[i] ? 1 : 0;
        coveredOnlyOnCpu += cpu.covered(i) && !frame.gbuffer.covered(i) ? 1 : 0;
    }
    return double(same) / double(cpu.triangle.size());
}

// A ground 10 km across under the fence, and a stray triangle 30 km away: the scene's reach
// grows a thousandfold, yet the rasteriser must see the same surfaces as the ray tracer (a near
// plane at a fixed fraction of the far one cut the foreground away).
TEST_F(GpuRenderer, VastGroundAndAStrayFarTriangleLeaveTheVisibleSurfacesAsEmbreeSees) {
    for (int variant = 0; variant < 2; ++variant) {
        Scene scene = loadScene("fence");
        const std::uint32_t ground = scene.triangleMaterial.back();
        if (variant == 0) {
            const float r = 5000.0f;
            scene.addTriangle(vec3(-r, -1e-3f, -r), vec3(-r, -1e-3f, r), vec3(r, -1e-3f, r), vec2(0), vec2(0),
                              vec2(0), ground);
            scene.addTriangle(vec3(-r, -1e-3f, -r), vec3(r, -1e-3f, r), vec3(r, -1e-3f, -r), vec2(0), vec2(0),
                              vec2(0), ground);
        } else {
            scene.addTriangle(vec3(30000, 0, 0), vec3(30001, 0, 0), vec3(30000, 1, 0), vec2(0), vec2(0),
                              vec2(0), ground);
        }
        scene.validate();
        const RenderOptions o = gpuOptions(W, H, 16);
        const Frame frame = renderGpu(scene, o);
        std::size_t lost = 0;
        const double agreement = gbufferAgreement(scene, frame, lost);
        EXPECT_EQ(lost, 0u) << "variant " << variant << ": pixels Embree sees a surface at and the GPU not";
        // Pixel centres on a triangle edge or a texel boundary may go either way.
        EXPECT_GE(agreement, 0.995) << "variant " << variant;
        // And the shadow computed on them is the mirror's, bit for bit.
        expectMirrorExact(scene, frame, o, 0, variant == 0 ? "10 km ground" : "stray triangle 30 km away");
    }
}

// --supersample K: the G-buffer and the light-sample buffer hold the K·W × K·H sub-pixels, each
// with its pixel's light samples; the GPU's bits equal the mirror's on that grid, the CPU frame's
// on its own, and the images are W × H, the visibility the mean of the sub-pixels' bits.
TEST_F(GpuRenderer, SupersampledFramesKeepEverySubPixelAndAverageThem) {
    const Scene scene = loadScene("fence");
    RenderOptions o = gpuOptions(48, 36, 64);
    o.supersample = 2;
    const Frame gpu = renderGpu(scene, o);
    ASSERT_EQ(gpu.gbuffer.width, 96);
    ASSERT_EQ(gpu.lightSamples[0].width(), 96);
    ASSERT_EQ(gpu.color.width, 48);
    ASSERT_EQ(gpu.visibility.height, 36);
    EXPECT_EQ(gpu.stats["options"]["width"], 48);
    EXPECT_EQ(gpu.stats["options"]["supersample"], 2);
    // The mirror on the GPU's sub-pixel grid, every sub-pixel with its pixel's samples.
    SamplePlan plan = makeSamplePlan(o.pattern, o.samples, o.seed, o.interleave, o.decorrelate);
    plan.supersample = 2;
    LightSampleBuffer mirror(96, 72, 64, BufferKind::Bitmask);
    stsvCpuSamples(scene, gpu.gbuffer, scene.lights[0], plan, farDistanceFor(scene.bounds()), mirror);
    const LightSampleDiff diff = compareLightSamples(gpu.lightSamples[0], mirror, 8, false);
    EXPECT_EQ(diff.differingSamples, 0u)
        << describeDifferences(gpu.lightSamples[0], mirror, gpu.gbuffer, false);
    // The visibility of a pixel is the mean over its 2×2 sub-pixels' samples (the fence is the
    // only light's occluder; background sub-pixels count as visible, 1).
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 48; ++x) {
            double visible = 0.0;
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    const int sx = 2 * x + i, sy = 2 * y + j;
                    if (!gpu.gbuffer.covered(gpu.gbuffer.index(sx, sy))) {
                        visible += 1.0;
                        continue;
                    }
                    int lit = 0;
                    for (int k = 0; k < 64; ++k) lit += gpu.lightSamples[0].occluded(sx, sy, k) ? 0 : 1;
                    visible += lit / 64.0;
                }
            // Float sums of 4 · 64 terms against a double mean: 1e-5.
            ASSERT_NEAR(gpu.visibility.at(x, y, 0), visible / 4.0, 1e-5) << "pixel " << x << ", " << y;
        }
    // A sub-pixel's samples are its pixel's: the two sub-pixels of one pixel on the same surface
    // point would see the same bits; with the plan of a frame without supersampling, pixel (x, y)
    // gives sub-pixel (2x + 1, 2y)'s sample positions.
    const SamplePlan single = makeSamplePlan(o.pattern, o.samples, o.seed, o.interleave, o.decorrelate);
    for (int k = 0; k < 64; k += 7)
        EXPECT_EQ(pixelSamplePoint(plan, 2 * 5 + 1, 2 * 3, k, 0u), pixelSamplePoint(single, 5, 3, k, 0u))
            << k;
}

struct SceneSamples {
    const char* scene;
    int samples;
};

class GpuVsMirror : public GpuRenderTest, public ::testing::WithParamInterface<SceneSamples> {};

TEST_P(GpuVsMirror, BitmaskMatchesMirrorOnGpuGBuffer) {
    const Scene scene = loadScene(GetParam().scene);
    const RenderOptions o = gpuOptions(W, H, GetParam().samples);
    const Frame frame = renderGpu(scene, o);
    ASSERT_EQ(frame.lightSamples.size(), scene.lights.size());
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        EXPECT_GT(occludedCount(frame.lightSamples[l]), std::size_t(W * H * o.samples / 100))
            << "no shadows to test";
        expectMirrorExact(scene, frame, o, l,
                          std::string(GetParam().scene) + " N=" + std::to_string(o.samples));
    }
}

TEST_P(GpuVsMirror, CountersMatchMirrorOnGpuGBuffer) {
    const Scene scene = loadScene(GetParam().scene);
    const RenderOptions o = gpuOptions(W / 2, H / 2, GetParam().samples, BufferKind::Counters);
    const Frame frame = renderGpu(scene, o);
    for (std::size_t l = 0; l < scene.lights.size(); ++l)
        expectMirrorExact(scene, frame, o, l,
                          std::string(GetParam().scene) + " counters N=" + std::to_string(o.samples));
}

// The renderer's fallbacks for large data (render/vulkan/gpu_frame_resources.cpp): alpha bytes in a storage
// buffer when the texture bits exceed 16 KiB (512² chain-link texels = 32 KiB of bits), and the
// pattern read from a buffer instead of baked into the resolve when the sets are interleaved.
TEST_F(GpuRenderTest, LargeTextureAndInterleavedPatternMatchMirror) {
    const Scene scene = loadScene("fence", SceneOptions{{{"texture_size", "512"}}});
    RenderOptions o = gpuOptions(W, H, 64);
    o.interleave = 2;
    const Frame frame = renderGpu(scene, o);
    ASSERT_EQ(frame.lightSamples.size(), scene.lights.size());
    EXPECT_GT(occludedCount(frame.lightSamples[0]), std::size_t(W * H * o.samples / 100))
        << "no shadows to test";
    expectMirrorExact(scene, frame, o, 0, "fence texture 512 interleave 2");
}

INSTANTIATE_TEST_SUITE_P(Scenes, GpuVsMirror,
                         ::testing::Values(SceneSamples{"fence", 16}, SceneSamples{"fence", 64},
                                           SceneSamples{"fence", 256}, SceneSamples{"foliage", 16},
                                           SceneSamples{"foliage", 64}, SceneSamples{"foliage", 256}),
                         [](const auto& param) {
                             return std::string(param.param.scene) + std::to_string(param.param.samples);
                         });

TEST_F(GpuRenderer, FenceMatchesEmbree) {
    const Scene scene = loadScene("fence");
    const RenderOptions o = gpuOptions(W, H, 64);
    const Frame frame = renderGpu(scene, o);
    for (std::size_t l = 0; l < scene.lights.size(); ++l)
        expectMatchesEmbree(scene, frame, o, l, 1, "fence"); // measured 1 of 324 544
}

TEST_F(GpuRenderer, FoliageMatchesEmbree) {
    const Scene scene = loadScene("foliage");
    const RenderOptions o = gpuOptions(W, H, 64);
    const Frame frame = renderGpu(scene, o);
    for (std::size_t l = 0; l < scene.lights.size(); ++l)
        expectMatchesEmbree(scene, frame, o, l, 0, "foliage"); // measured 0 of 343 296
}

TEST_F(GpuRenderer, EveryLightShapeInOneFrameMatchesMirrorEmbreeAndCpuResolve) {
    Scene scene = testScene();
    scene.lights = {makeRectangleLight({0.0f, 3.0f, 0.0f}, {0, -1, 0}, {1.2f, 0.8f}, vec3(4.0f)),
                    makeDiskLight({1.0f, 3.0f, 0.5f}, normalize(vec3(-0.2f, -1.0f, 0.0f)), 0.5f, vec3(3.0f)),
                    makeSphereLight({-1.2f, 2.5f, 0.2f}, 0.35f, vec3(2.0f)),
                    makeDirectionalLight(normalize(vec3(0.3f, 1.0f, 0.2f)), 0.05f, vec3(1.5f))};
    scene.validate();
    const RenderOptions o = gpuOptions(W, H, 32);
    const Frame frame = renderGpu(scene, o);
    ASSERT_EQ(frame.lightSamples.size(), 4u);
    for (std::size_t l = 0; l < 4; ++l) {
        const std::string what = "light shape " + std::to_string(scene.lights[l].type);
        expectMirrorExact(scene, frame, o, l, what);
        expectMatchesEmbree(scene, frame, o, l, 0, what); // measured 0 of 127 552 for each shape
    }
    // Resolve: the CPU resolve of the GPU's own buffers (render/cpu/cpu_renderer.cpp's conventions).
    Frame cpu;
    initFrameImages(scene, frame.gbuffer, o.ambient, cpu);
    const SamplePlan plan = planOf(o);
    for (std::size_t l = 0; l < 4; ++l)
        resolveLight(scene, frame.gbuffer, scene.lights[l], plan, farDistanceFor(scene.bounds()),
                     frame.lightSamples[l], 0.25f, cpu.color, cpu.visibility);
    float maxColor = 0.0f, maxVisibility = 0.0f;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c)
                maxColor = std::max(maxColor, std::abs(frame.color.at(x, y, c) - cpu.color.at(x, y, c)) /
                                                  std::max(1.0f, std::abs(cpu.color.at(x, y, c))));
            maxVisibility =
                std::max(maxVisibility, std::abs(frame.visibility.at(x, y, 0) - cpu.visibility.at(x, y, 0)));
        }
    // GPU sin/cos/tan and fused multiply-adds differ from libm in the last bits; sums of ≤ 32 terms.
    EXPECT_LT(maxColor, 1e-4f);
    // v_coef sums four products weight·(visible/N): exact up to one rounding each.
    EXPECT_LT(maxVisibility, 1e-6f);
}

TEST_F(GpuRenderer, DoubleSidedTrianglesWithLightStraddlingTheirPlane) {
    // A vertical perforated quad in the plane x = 0 and a sphere light centred in that plane:
    // both sides are lit, so each triangle has two volumes (STSV §6) and shadows on both sides.
    Scene scene = testScene();
    scene.triangles.resize(2); // keep the ground
    scene.triangleMaterial.resize(2);
    const std::uint32_t fence = 1;
    scene.addTriangle({0, 0.2f, -1.5f}, {0, 0.2f, 1.5f}, {0, 1.8f, 1.5f}, {0, 0}, {3, 0}, {3, 2}, fence);
    scene.addTriangle({0, 0.2f, -1.5f}, {0, 1.8f, 1.5f}, {0, 1.8f, -1.5f}, {0, 0}, {3, 2}, {0, 2}, fence);
    scene.lights = {makeSphereLight({0.0f, 2.6f, 0.2f}, 0.6f, vec3(3.0f)),
                    makeRectangleLight({0.1f, 2.5f, -0.3f}, {0, -1, 0}, {1.0f, 1.0f}, vec3(3.0f))};
    scene.validate();
    const RenderOptions o = gpuOptions(W, H, 64);
    const Frame frame = renderGpu(scene, o);
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        expectMirrorExact(scene, frame, o, l, "straddling");
        expectMatchesEmbree(scene, frame, o, l, 0, "straddling"); // measured 0 of 255 104, both lights
    }
    // Shadow on both sides of the plane x = 0.
    std::size_t left = 0, right = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = frame.gbuffer.index(x, y);
            if (frame.gbuffer.triangle[i] >= 2 || frame.lightSamples[0].visibleFraction(x, y) == 1.0f)
                continue;
            (frame.gbuffer.position[i].x < 0.0f ? left : right) += 1;
        }
    EXPECT_GT(left, 10u);
    EXPECT_GT(right, 10u);
}

TEST_F(GpuRenderer, CameraInsideVolumeNearPlaneBehindLightAndDegenerateTriangles) {
    Scene scene = testScene();
    const std::uint32_t opaque = 2;
    const vec2 t(0.0f);
    // Behind the light (above it): its volume points away from the ground.
    scene.addTriangle({-0.5f, 3.6f, -0.5f}, {-0.5f, 3.6f, 0.5f}, {0.5f, 3.6f, 0.0f}, t, t, t, opaque);
    // Degenerate: collinear and repeated positions.
    scene.addTriangle({0, 0.5f, 0}, {0.5f, 0.5f, 0}, {1.0f, 0.5f, 0}, t, t, t, opaque);
    scene.addTriangle({0.3f, 0.4f, 0.3f}, {0.3f, 0.4f, 0.3f}, {0.3f, 0.4f, 0.3f}, t, t, t, opaque);
    // Camera under the perforated quad, inside its shadow volume, looking down at the ground.
    scene.camera.eye = vec3(0.1f, 0.8f, 0.2f);
    scene.camera.target = vec3(0.4f, 0.0f, -1.5f);
    scene.camera.fovY = 70.0f;
    // A triangle passing through the eye's neighbourhood: crosses the near plane.
    scene.addTriangle({-0.3f, 0.78f, 0.0f}, {0.5f, 0.78f, 0.4f}, {0.1f, 0.7f, -0.4f}, t, t, t, opaque);
    scene.lights = {makeRectangleLight({0.0f, 3.0f, 0.0f}, {0, -1, 0}, {0.8f, 0.8f}, vec3(4.0f))};
    scene.validate();
    const RenderOptions o = gpuOptions(W, H, 64);
    const Frame frame = renderGpu(scene, o);
    expectMirrorExact(scene, frame, o, 0, "camera inside");
    expectMatchesEmbree(scene, frame, o, 0, 0, "camera inside"); // measured 0 of 299 968
    for (std::size_t i = 0; i < frame.gbuffer.triangle.size(); ++i) {
        EXPECT_NE(frame.gbuffer.triangle[i], 6u) << "degenerate triangle rasterised";
        EXPECT_NE(frame.gbuffer.triangle[i], 7u) << "degenerate triangle rasterised";
    }
}

TEST_F(GpuRenderer, LightSampleBufferMemoryIsNWHBits) {
    RenderOptions o = gpuOptions(1024, 1024, 64);
    EXPECT_EQ(lightSampleBufferBytes(o), 8u * 1024u * 1024u); // the STSV paper's §5.1 figure
    o.samples = 256;
    EXPECT_EQ(lightSampleBufferBytes(o), 32u * 1024u * 1024u);
    o.buffer = BufferKind::Counters;
    EXPECT_EQ(lightSampleBufferBytes(o), 2u * 256u * 1024u * 1024u);
    const Scene scene = loadScene("fence");
    const RenderOptions small = gpuOptions(64, 40, 128);
    const Frame frame = renderGpu(scene, small);
    EXPECT_EQ(frame.stats["light_sample_buffer_bytes"].get<std::size_t>(), std::size_t(64 * 40 * 128 / 8));
    EXPECT_EQ(frame.lightSamples[0].memoryBytes(), std::size_t(64 * 40 * 128 / 8));
    EXPECT_GT(frame.stats["frame_ms"].get<double>(), 0.0);
    EXPECT_TRUE(frame.stats["passes"].contains("gbuffer"));
    EXPECT_TRUE(frame.stats["passes"].contains("light0/stsv_clusters"));
    EXPECT_TRUE(frame.stats["passes"].contains("light0/resolve"));
    EXPECT_GT(frame.stats["stsv"][0]["fragments"].get<std::size_t>(), 0u);
    EXPECT_LE(frame.stats["stsv"][0]["inside_fragments"].get<std::size_t>(),
              frame.stats["stsv"][0]["fragments"].get<std::size_t>());
    // stsv.frag tests every sample of a fragment inside its volume.
    EXPECT_EQ(frame.stats["stsv"][0]["samples_tested"].get<std::size_t>(),
              128u * frame.stats["stsv"][0]["inside_fragments"].get<std::size_t>());
}

TEST_F(GpuRenderer, TheSamplePassesGiveNoThreadMoreFragmentsThanLavapipesLoopsAllow) {
    // lavapipe ends an invocation's loops after 65 535 iterations in all and skips the rest
    // silently: a sample pass over the deferred fragments must spread a full list over enough
    // threads (64 a workgroup, at most 65 535 workgroups) that none takes more than
    // SAMPLE_LOOP_BUDGET / (2N + 16) fragments of N samples. A fixed 256 workgroups lost samples
    // of fence-mesh at 128×96 (15 M fragments listed at 64 samples; one 4×4 block's bits varied
    // from run to run).
    if (device().info().type != VK_PHYSICAL_DEVICE_TYPE_CPU) {
        // A GPU has no such limit; it needs threads in flight.
        EXPECT_EQ(deferredSampleGroups(device(), std::uint64_t(1) << 24, 64), 8192u);
        return;
    }
    for (const int samples : {16, 32, 64, 128, 256})
        for (const std::uint64_t capacity :
             {std::uint64_t(1), std::uint64_t(1) << 20, std::uint64_t(15'000'000), std::uint64_t(1) << 24,
              MAX_DEFERRED_FRAGMENTS}) {
            const std::uint64_t groups = deferredSampleGroups(device(), capacity, samples);
            const std::uint64_t perThread = (capacity + 64 * groups - 1) / (64 * groups);
            EXPECT_LE(perThread * std::uint64_t(2 * samples + 16), SAMPLE_LOOP_BUDGET)
                << samples << " " << capacity;
            EXPECT_LE(groups, 65535u);
            // A short list keeps the few hundred workgroups that keep the cores busy.
            if (capacity <= (std::uint64_t(1) << 20) && samples <= 64) {
                EXPECT_EQ(groups, 256u) << samples << " " << capacity;
            }
        }
}

TEST_F(GpuRenderer, AListWithEdgeTermsHoldsNoMoreThanItsTermsBindingAddresses) {
    // DCS's walk lists each pair with a 32-byte edge term beside the 8-byte pair: the list may
    // then hold only what one binding of the terms addresses, whichever family used it first
    // (STSV's mask words, then DCS's terms, as a dcs+stsv frame does), and a frame that lists
    // more is an error the walk avoids by taking its tiles in parts.
    const std::uint64_t range = device().limits().maxStorageBufferRange;
    const std::uint64_t termBytes = 16 * std::uint64_t(GPU_DEFERRED_TERM_TEXELS);
    ASSERT_EQ(termBytes, 32u);
    const RenderOptions o = gpuOptions(64, 48, 64);
    DeferredFragments list(device(), o, std::uint64_t(1) << 40);
    EXPECT_EQ(list.maxCapacity(), std::min(MAX_DEFERRED_FRAGMENTS, range / 8));
    list.use(true);
    EXPECT_EQ(list.capacity(), list.maxCapacity());
    EXPECT_EQ(list.terms.size(), termBytes); // a stand-in
    list.use(false, true);
    EXPECT_EQ(list.maxCapacity(), std::min(MAX_DEFERRED_FRAGMENTS, range / termBytes));
    EXPECT_EQ(list.capacity(), list.maxCapacity());
    EXPECT_EQ(list.fragments.size(), 8 * list.capacity());
    EXPECT_EQ(list.terms.size(), termBytes * list.capacity());
    EXPECT_LE(list.terms.size(), range);
    EXPECT_THROW(list.growFor(list.maxCapacity() + 1), Error);
    // A short list grows with its terms.
    DeferredFragments small(device(), o, 100);
    small.use(false, true);
    EXPECT_EQ(small.capacity(), 100u);
    EXPECT_TRUE(small.growFor(1000));
    EXPECT_EQ(small.capacity(), 1250u);
    EXPECT_EQ(small.terms.size(), termBytes * 1250u);
    EXPECT_FALSE(small.growFor(1000));
}

TEST_F(GpuRenderer, RepeatedFramesAreIdentical) {
    const Scene scene = loadScene("foliage");
    const RenderOptions o = gpuOptions(64, 48, 64);
    VulkanRenderer renderer(scene, o, {&device()});
    const Frame a = renderer.render();
    const Frame b = renderer.render();
    EXPECT_EQ(a.lightSamples[0].words(), b.lightSamples[0].words());
    EXPECT_EQ(a.gbuffer.triangle, b.gbuffer.triangle);
}

TEST_F(GpuRenderer, MakeRendererChoosesVulkanForStsv) {
    const Scene scene = loadScene("fence");
    RenderOptions o = gpuOptions(32, 24, 16);
    o.validation = true;
    const std::unique_ptr<FrameRenderer> renderer = makeRenderer(scene, o);
    ASSERT_NE(dynamic_cast<VulkanRenderer*>(renderer.get()), nullptr);
    const Frame frame = renderer->render();
    // Auto extrusion: the cluster walk, on every device (compute passes, no volume drawn).
    EXPECT_EQ(frame.stats["gpu"]["extrusion"].get<std::string>(), "cluster walk");
    EXPECT_FALSE(static_cast<VulkanRenderer*>(renderer.get())->usesMeshShader());
    EXPECT_EQ(static_cast<VulkanRenderer*>(renderer.get())->device().validationMessageCount(), 0u);
}

/// The foliage under a disk light (its volumes' light planes bound the disk's square).
Scene foliageUnderDiskLight() {
    Scene scene = loadScene("foliage");
    const Light& light = scene.lights[0];
    scene.lights[0] = makeDiskLight(light.position, light.normal, 2.0f, light.radiance);
    return scene;
}

/// The fence under a sphere light (no light planes: the volumes' own planes).
Scene fenceUnderSphereLight() {
    Scene scene = loadScene("fence");
    scene.lights[0] = makeSphereLight(scene.lights[0].position, 0.5f, scene.lights[0].radiance);
    return scene;
}

TEST_F(GpuRenderer, HullsAndPrismsGiveTheSameBitsCountersAndInsideFragments) {
    // The hull pass (--extrusion hull) against the paper's prism (geometry shader): both enclose every point
    // the fragment accepts, so the buffers are identical and so are the fragments that reach the
    // sample loop; and the hulls rasterise far fewer fragments. Foliage: large light, leaves
    // edge-on; fence: two big perforated triangles; the knot's scene with a disk light (a light
    // square around the disk) and a sphere light (no light planes: the volume's own planes).
    struct Case {
        const char* name;
        Scene scene;
        double maxFragmentRatio; ///< hull fragments / prism fragments, at most
    };
    std::vector<Case> cases;
    // Bounds with a margin over the ratios measured when this was written: 0.17, 0.66, 0.16, 0.92
    // (the sphere light has no light planes: the hull is the prism's region inside the box).
    cases.push_back({"foliage", loadScene("foliage"), 0.25});
    cases.push_back({"fence", loadScene("fence"), 0.8});
    cases.push_back({"foliage, disk light", foliageUnderDiskLight(), 0.25});
    cases.push_back({"fence, sphere light", fenceUnderSphereLight(), 1.0});
    for (const Case& c : cases)
        for (BufferKind kind : {BufferKind::Bitmask, BufferKind::Counters}) {
            RenderOptions o = gpuOptions(96, 72, 64, kind);
            o.extrusion = ExtrusionStage::Hull;
            // Room for 16 deferred fragments a pixel: more than any case defers (the foliage at
            // 96 × 72 defers 2.0 a pixel, past the default of 2).
            VulkanRenderer hullRenderer(c.scene, o, {&device(), 16 * 96 * 72});
            const Frame hull = hullRenderer.render();
            const Frame prism = renderGpu(c.scene, o, ExtrusionStage::Geometry);
            const std::string what = std::string(c.name) + " " + toString(kind);
            EXPECT_EQ(hull.lightSamples[0].words(), prism.lightSamples[0].words()) << what;
            EXPECT_EQ(hull.lightSamples[0].counters(), prism.lightSamples[0].counters()) << what;
            const nlohmann::json& h = hull.stats["stsv"][0];
            const nlohmann::json& p = prism.stats["stsv"][0];
            EXPECT_EQ(h["inside_fragments"], p["inside_fragments"]) << what;
            EXPECT_GT(h["inside_fragments"].get<std::size_t>(), 0u) << what;
            std::printf("[hull] %s: fragments %zu, prism %zu\n", what.c_str(),
                        h["fragments"].get<std::size_t>(), p["fragments"].get<std::size_t>());
            EXPECT_LE(double(h["fragments"].get<std::size_t>()),
                      c.maxFragmentRatio * double(p["fragments"].get<std::size_t>()))
                << what << ": hull " << h.dump() << ", prism " << p.dump();
            EXPECT_GT(h["hull_volumes"].get<std::size_t>(), 0u) << what;
            // With room for them, the sample pass tested every inside fragment.
            EXPECT_EQ(h["deferred_fragments"], h["inside_fragments"]) << what;
            EXPECT_EQ(hull.stats["gpu"]["extrusion"], "hull (compute)");
            EXPECT_EQ(prism.stats["gpu"]["extrusion"], "geometry shader");
        }
}

TEST_F(GpuRenderer, TheClusterWalkListsTheFragmentsTheHullDrawAccepts) {
    // STSV with the auto extrusion walks the tree of its triangles' balls per 4 × 4 block
    // (stsv_clusters.comp) instead of drawing the volumes' hulls: its per-pixel test is the hull
    // fragment's, and its culling drops only pairs whose triangle meets no segment from the
    // block's points to the light, so it lists the draw's (pixel, volume) pairs less some that
    // occlude no sample (a volume, larger than the region its triangle shadows, can hold such a
    // point: the fence under the sphere light, whose volumes have no light planes), and the
    // buffers are the draw's. Foliage with its rectangle light and a disk
    // light, the fence under a sphere light (no light planes), the two-light example scene, and
    // the fence with opaque posts (dcs+stsv: perforated triangles only); a second frame is the
    // same.
    struct Case {
        const char* name;
        Scene scene;
        Method method;
    };
    std::vector<Case> cases;
    cases.push_back({"foliage", loadScene("foliage"), Method::Stsv});
    cases.push_back({"foliage, disk light", foliageUnderDiskLight(), Method::Stsv});
    cases.push_back({"fence, sphere light", fenceUnderSphereLight(), Method::Stsv});
    cases.push_back({"example", loadScene(dataPath("example.json")), Method::Stsv});
    cases.push_back({"fence, dcs+stsv", loadScene("fence"), Method::DcsStsv});
    for (const Case& c : cases)
        for (BufferKind kind : {BufferKind::Bitmask, BufferKind::Counters}) {
            RenderOptions o = gpuOptions(96, 72, 64, kind);
            o.method = c.method;
            VulkanRenderer walker(c.scene, o, {&device()});
            const Frame walk = walker.render();
            const Frame again = walker.render();
            RenderOptions ho = o;
            ho.extrusion = ExtrusionStage::Hull;
            const Frame hull = renderGpu(c.scene, ho);
            const std::string what = std::string(c.name) + " " + toString(kind);
            ASSERT_EQ(walk.lightSamples.size(), c.scene.lights.size()) << what;
            for (std::size_t l = 0; l < c.scene.lights.size(); ++l) {
                const std::string light = what + " light " + std::to_string(l);
                EXPECT_EQ(walk.lightSamples[l].words(), hull.lightSamples[l].words()) << light;
                EXPECT_EQ(walk.lightSamples[l].counters(), hull.lightSamples[l].counters()) << light;
                EXPECT_EQ(again.lightSamples[l].words(), walk.lightSamples[l].words()) << light;
                EXPECT_EQ(again.lightSamples[l].counters(), walk.lightSamples[l].counters()) << light;
                const nlohmann::json& w = walk.stats["stsv"][l];
                const nlohmann::json& h = hull.stats["stsv"][l];
                EXPECT_EQ(w["path"], "clusters") << light;
                EXPECT_EQ(h["path"], "volumes") << light;
                EXPECT_LE(w["listed_fragments"].get<std::size_t>(), h["listed_fragments"].get<std::size_t>())
                    << light << ": " << w.dump();
                EXPECT_LE(w["inside_fragments"].get<std::size_t>(), h["inside_fragments"].get<std::size_t>())
                    << light;
                EXPECT_GT(w["inside_fragments"].get<std::size_t>(), 0u) << light;
                // The walk builds a record for every volume, the draw for those whose hull has a
                // face to draw.
                EXPECT_GE(w["volumes"].get<std::size_t>(), h["hull_volumes"].get<std::size_t>()) << light;
                EXPECT_GT(w["clusters_rejected"].get<std::size_t>(), 0u) << light;
                EXPECT_LT(w["clusters_rejected"].get<std::size_t>(), w["cluster_tests"].get<std::size_t>())
                    << light;
                // Its pixel tests reach the listed pairs and more.
                EXPECT_GE(w["fragments"].get<std::size_t>(), w["listed_fragments"].get<std::size_t>())
                    << light;
                EXPECT_EQ(again.stats["stsv"][l], w) << light;
            }
            EXPECT_TRUE(walk.stats["passes"].contains("light0/stsv_clusters")) << what;
            EXPECT_FALSE(walk.stats["passes"].contains("light0/stsv")) << what;
            EXPECT_EQ(walker.device().validationMessageCount(), 0u) << what;
        }
}

TEST_F(GpuRenderer, AnStsvWalkWhoseListsCannotHoldItTakesTheTilesInParts) {
    // Lists limited to 2000 pairs (as a storage buffer's range limits them on a large frame): the
    // walk over the foliage takes the tiles in parts, each with the lists to itself, and the
    // bits are those of the hull draw.
    const Scene scene = loadScene("foliage");
    const RenderOptions o = gpuOptions(96, 72, 64);
    VulkanRendererConfig config{&device()};
    config.clusterListLimit = 2000;
    VulkanRenderer limited(scene, o, config);
    const Frame parts = limited.render();
    const nlohmann::json limitless = renderGpu(scene, o).stats;
    RenderOptions ho = o;
    ho.extrusion = ExtrusionStage::Hull;
    const Frame hull = renderGpu(scene, ho);
    EXPECT_EQ(parts.lightSamples[0].words(), hull.lightSamples[0].words());
    const nlohmann::json& w = parts.stats["stsv"][0];
    std::cout << w.dump() << "\n";
    EXPECT_GT(w["parts"].get<std::uint32_t>(), 1u);
    EXPECT_LE(w["list_capacity"].get<std::uint64_t>(), 2000u);
    EXPECT_EQ(w["listed_fragments"], limitless["stsv"][0]["listed_fragments"]);
    EXPECT_EQ(limited.device().validationMessageCount(), 0u);
}

TEST_F(GpuRenderer, AnStsvWalkListingMoreThanTheSampleListHoldsSamplesItPartByPart) {
    // The sample list limited to 2000 fragments, fewer than the foliage's walk lists for the
    // frame: the walk takes the tiles in parts, each part's fragments sampled before the next
    // part lists its own (the mask words add up until the merge), and the bits and counters are
    // the hull draw's, in this frame and the next.
    const Scene scene = loadScene("foliage");
    for (BufferKind kind : {BufferKind::Bitmask, BufferKind::Counters}) {
        const RenderOptions o = gpuOptions(96, 72, 64, kind);
        const std::string what = toString(kind);
        VulkanRendererConfig config{&device()};
        config.deferredLimit = 2000;
        VulkanRenderer limited(scene, o, config);
        const Frame parts = limited.render();
        const Frame again = limited.render();
        const Frame whole = renderGpu(scene, o);
        RenderOptions ho = o;
        ho.extrusion = ExtrusionStage::Hull;
        const Frame hull = renderGpu(scene, ho);
        for (const Frame* frame : {&parts, &again}) {
            if (kind == BufferKind::Bitmask)
                EXPECT_EQ(frame->lightSamples[0].words(), hull.lightSamples[0].words()) << what;
            else
                EXPECT_EQ(frame->lightSamples[0].counters(), hull.lightSamples[0].counters()) << what;
        }
        const nlohmann::json& w = parts.stats["stsv"][0];
        std::cout << what << ": " << w.dump() << "\n";
        EXPECT_GT(whole.stats["stsv"][0]["listed_fragments"].get<std::uint64_t>(), 3 * config.deferredLimit)
            << what;
        EXPECT_GT(w["parts"].get<std::uint32_t>(), 1u) << what;
        EXPECT_EQ(w["listed_fragments"], whole.stats["stsv"][0]["listed_fragments"]) << what;
        EXPECT_EQ(w["deferred_fragments"], whole.stats["stsv"][0]["deferred_fragments"]) << what;
        EXPECT_EQ(limited.device().validationMessageCount(), 0u) << what;
    }
}

TEST_F(GpuRenderer, AShortFragmentListGrowsAndTheFrameIsRenderedAgain) {
    // A list with room for 50 fragments: the hull draw lists far more, drops those past the end,
    // and the renderer grows the list and renders the frame again; the buffers are those of the
    // prism path, which lists nothing, in this frame and the next.
    constexpr std::uint64_t CAPACITY = 50;
    const Scene scene = loadScene("foliage");
    for (BufferKind kind : {BufferKind::Bitmask, BufferKind::Counters}) {
        const RenderOptions o = gpuOptions(96, 72, 64, kind);
        VulkanRenderer small(scene, o, {&device(), CAPACITY});
        const Frame first = small.render();
        const Frame second = small.render();
        const Frame prism = renderGpu(scene, o, ExtrusionStage::Geometry);
        const std::string what = toString(kind);
        for (const Frame* hull : {&first, &second}) {
            EXPECT_EQ(hull->lightSamples[0].words(), prism.lightSamples[0].words()) << what;
            EXPECT_EQ(hull->lightSamples[0].counters(), prism.lightSamples[0].counters()) << what;
            const nlohmann::json& h = hull->stats["stsv"][0];
            EXPECT_EQ(h["inside_fragments"], prism.stats["stsv"][0]["inside_fragments"]) << what;
            // Every inside fragment was listed and tested by the sample pass; listed fragments the
            // side rule rejects are not inside.
            EXPECT_EQ(h["deferred_fragments"], h["inside_fragments"]) << what;
            EXPECT_GE(h["listed_fragments"].get<std::uint64_t>(),
                      h["deferred_fragments"].get<std::uint64_t>())
                << what;
            EXPECT_GT(h["deferred_fragments"].get<std::uint64_t>(), 10 * CAPACITY) << what;
        }
        EXPECT_EQ(small.device().validationMessageCount(), 0u) << what;
    }
}

TEST_F(GpuRenderer, MeshShaderExtrusionMatchesMirrorOrSkips) {
    const Scene scene = loadScene("fence");
    const RenderOptions o = gpuOptions(W, H, 64);
    RenderOptions viaOptions = o; // --extrusion mesh
    viaOptions.extrusion = ExtrusionStage::Mesh;
    if (!device().info().meshShader) {
        EXPECT_THROW(VulkanRenderer(scene, viaOptions, {&device()}), UsageError);
        // ctest mesh_shaders.lavapipe_backports runs this on a driver that has them.
        if (std::getenv("STSV_REQUIRE_MESH_SHADERS"))
            FAIL() << device().info().name
                   << " lacks VK_EXT_mesh_shader, which STSV_REQUIRE_MESH_SHADERS requires";
        GTEST_SKIP() << device().info().name
                     << " lacks VK_EXT_mesh_shader: stsv.mesh compiled and validated at build time, not run";
    }
    const Frame frame = renderGpu(scene, o, ExtrusionStage::Mesh);
    expectMirrorExact(scene, frame, o, 0, "mesh shader");
    VulkanRenderer fromOptions(scene, viaOptions, {&device()});
    EXPECT_TRUE(fromOptions.usesMeshShader());
    const Frame geometry = renderGpu(scene, o, ExtrusionStage::Geometry);
    const LightSampleDiff diff =
        compareLightSamples(frame.lightSamples[0], geometry.lightSamples[0], 8, false);
    EXPECT_EQ(diff.differingSamples, 0u) << "mesh and geometry shader extrusion differ";
}

} // namespace
} // namespace stsv::test
